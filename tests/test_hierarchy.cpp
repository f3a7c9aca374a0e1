// Hierarchies (paper section 4) and runs from given samples: every level a prefix that is
// conflict-free and maximal at its radii, judged by the exact checker; births in order; the same
// points on every device; counts against direct sampling; bad options refused.
#include <catch2/catch.hpp>

#include <cmath>

#include "cli_support.h"
#include "support.h"
#include "vrpd/continuous.h"
#include "vrpd/hierarchy.h"
#include "vrpd/io.h"
#include "vrpd/verify.h"

using namespace vrpd;

namespace {

SampleOptions hierarchy(double rf, double rc, unsigned steps, double start, std::uint32_t seed, Backend backend,
                        Box box = {}) {
    SampleOptions o = test::options(rf, seed, backend, box);
    o.coverage = rc == rf ? 0.0 : rc;
    o.hierarchy = {steps, start};
    return o;
}

std::vector<glm::dvec2> points_of(const Sampling& s, std::size_t n) {
    std::vector<glm::dvec2> p(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = s.point(i);
    return p;
}

}  // namespace

TEST_CASE("discrete hierarchy: each level is a prefix, conflict-free and maximal at its radii", "[hierarchy]") {
    const struct {
        double rf, rc;
        unsigned steps;
        double start;
        Box box;
    } cases[] = {
        {0.02, 0.02, 10, 0, Box{}},                       // Figure 6's construction
        {0.01, 0.02, 10, 0, Box{}},                       // Figure 9's
        {0.01, 0.02, 4, 3.5, Box{1, 1, Boundary::Free}},  // S not a power of two, free boundary
        {0.03, 0.03, 3, 2, Box{2, 1, Boundary::Periodic}},
    };
    for (const auto& c : cases) {
        INFO("Rf " << c.rf << " Rc " << c.rc << " K " << c.steps << " S " << c.start << " box " << c.box.width);
        const Sampling s = sample(hierarchy(c.rf, c.rc, c.steps, c.start, 7, Backend::Cpu, c.box));
        REQUIRE(s.birth.size() == s.size());
        const Hierarchy h(s);
        const std::vector<double> levels = h.levels();
        REQUIRE(levels.size() == c.steps);  // every step added samples here
        CHECK(levels.front() == 1.0);
        const double start = c.start == 0 ? c.steps : c.start;
        CHECK(levels.back() == Approx(1 / start).epsilon(1e-15));
        std::size_t previous = 0;
        for (std::size_t k = 0; k < levels.size(); ++k) {
            const double t = levels[k], scale = t * start;
            const std::size_t n = h.count_at(t);
            CHECK(n > previous);
            previous = n;
            // Radii at this level, and the points' resolution on the run's lattice.
            const Radii r{c.rf * scale, c.rc * scale, 2 * s.quantum};
            const Report rep = verify(points_of(s, n), r, c.box);
            INFO("level " << k << ": t " << t << ", " << n << " samples, largest empty circle "
                          << rep.largest_empty_radius << ", min distance " << rep.min_distance);
            CHECK(rep.conflicts == 0);
            CHECK(rep.maximal);
        }
        CHECK(previous == s.size());
    }
}

TEST_CASE("hierarchy and given samples: gpu = cpu = serial", "[hierarchy][gpu]") {
    for (const auto& [rf, rc] : {std::pair{0.02, 0.02}, std::pair{0.01, 0.02}}) {
        INFO("Rf " << rf << " Rc " << rc);
        const Sampling serial = sample(hierarchy(rf, rc, 5, 0, 3, Backend::Serial));
        CHECK(sample(hierarchy(rf, rc, 5, 0, 3, Backend::Cpu)).lattice == serial.lattice);
        const Sampling gpu = sample(hierarchy(rf, rc, 5, 0, 3, Backend::Gpu));
        CHECK(gpu.lattice == serial.lattice);
        CHECK(gpu.birth == serial.birth);
        CHECK(gpu.stats.darts == serial.stats.darts);
    }
    // Completing a coarse set: the same points everywhere.
    const Sampling coarse = sample(test::options(0.03, 1, Backend::Cpu));
    SampleOptions fine = test::options(0.012, 2, Backend::Serial, Box{1, 1, Boundary::Free});
    fine.initial = points_of(coarse, coarse.size());
    const Sampling serial = sample(fine);
    fine.backend = Backend::Cpu;
    CHECK(sample(fine).lattice == serial.lattice);
    fine.backend = Backend::Gpu;
    CHECK(sample(fine).lattice == serial.lattice);
}

TEST_CASE("from given samples: they come first, then a maximal completion", "[hierarchy]") {
    const Box box{};
    const Sampling coarse = sample(test::options(0.02, 4, Backend::Cpu, box));
    // On the run's own lattice (same radius and box) the given samples are kept exactly.
    SampleOptions same = test::options(0.02, 9, Backend::Cpu, box);
    same.initial = points_of(coarse, coarse.size());
    const Sampling again = sample(same);
    CHECK(again.lattice == coarse.lattice);  // already maximal: nothing to add
    SampleOptions finer = test::options(0.008, 9, Backend::Cpu, box);
    finer.initial = points_of(coarse, coarse.size());
    const Sampling s = sample(finer);
    REQUIRE(s.size() > coarse.size());
    for (std::size_t i = 0; i < coarse.size(); ++i) {
        // Rounded to the finer run's lattice: within half a step's diagonal.
        CHECK(std::abs(s.point(i).x - coarse.point(i).x) <= s.quantum);
        CHECK(std::abs(s.point(i).y - coarse.point(i).y) <= s.quantum);
    }
    const Report rep = verify(points_of(s, s.size()), {0.008, 0.008, 2 * s.quantum}, box);
    CHECK(rep.conflicts == 0);
    CHECK(rep.maximal);
}

// Given samples packed hexagonally at just over Rf fill more than half the base cells (whose side
// is just under Rf/sqrt(2)), so the first round throws only near the active cells, from a list of
// the free base cells, not into every free base cell without one: both ways, gpu = cpu = serial,
// the given samples first and the completion maximal.
TEST_CASE("two radii from given samples filling most base cells: gpu = cpu = serial", "[two-radii][gpu]") {
    const double rf = 0.02, rc = 0.03;
    const int columns = 49, rows = 56;  // spacing 1/49 across, 1/56 between rows: 0.0206 diagonally
    std::vector<glm::dvec2> hexagonal;
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < columns; ++i) hexagonal.push_back({(i + 0.5 * (j % 2)) / columns, double(j) / rows});
    for (std::size_t given : {hexagonal.size(), hexagonal.size() / 4}) {
        INFO(given << " given samples");
        auto run = [&](Backend b, unsigned threads = 0) {
            SampleOptions o = test::options(rf, 3, b);
            o.coverage = rc;
            o.threads = threads;
            o.initial.assign(hexagonal.begin(), hexagonal.begin() + std::ptrdiff_t(given));
            return sample(o);
        };
        const Sampling serial = run(Backend::Serial);
        REQUIRE(serial.size() >= given);
        CHECK(run(Backend::Cpu, 1).lattice == serial.lattice);
        CHECK(run(Backend::Cpu, 2).lattice == serial.lattice);
        CHECK(run(Backend::Cpu, 3).lattice == serial.lattice);
        CHECK(run(Backend::Gpu).lattice == serial.lattice);
        const Report rep = verify(test::points_of(serial), {rf, rc, 2 * serial.quantum}, Box{});
        CHECK(rep.conflicts == 0);
        CHECK(rep.maximal);
    }
}

TEST_CASE("hierarchy and given samples: bad options refused with the reason", "[hierarchy]") {
    auto refused = [](SampleOptions o, const char* why) {
        INFO(why);
        CHECK_THROWS_WITH(sample(o), Catch::Contains(why));
    };
    refused(hierarchy(0.01, 0.01, 1, 0, 1, Backend::Cpu), "2 to 1000 steps");
    refused(hierarchy(0.01, 0.01, 5, 0.5, 1, Backend::Cpu), "start S must be 1 to 1024");
    refused(hierarchy(0.1, 0.1, 10, 0, 1, Backend::Cpu), "the hierarchy's first step, at 10 times the radii");
    SampleOptions both = hierarchy(0.01, 0.01, 5, 0, 1, Backend::Cpu);
    both.initial = {{0.5, 0.5}};
    refused(both, "give --from or --hierarchy, not both");
    SampleOptions close = test::options(0.01, 1, Backend::Cpu);
    close.initial = {{0.2, 0.2}, {0.5, 0.5}, {0.5, 0.505}};
    refused(close, "given samples 2 (0.5, 0.5) and 3 (0.5, 0.505) are closer than Rf = 0.01");
    // Across a torus's seam, too.
    close.initial = {{0.001, 0.5}, {0.998, 0.5}};
    refused(close, "given samples 1");
    SampleOptions outside = test::options(0.01, 1, Backend::Cpu);
    outside.initial = {{0.5, 1.0}};
    refused(outside, "given sample 1 (0.5, 1) is outside the box");
}

TEST_CASE("Hierarchy: count_at finds each level, refuses unordered births", "[hierarchy]") {
    const Hierarchy h({{0, 0}, {1, 1}, {2, 2}, {3, 3}}, {1.0, 0.5, 0.5, 0.2}, 0.1);
    CHECK(h.count_at(1.0) == 1);
    CHECK(h.count_at(0.5) == 3);
    CHECK(h.count_at(0.4999999999999999) == 3);
    CHECK(h.count_at(0.3) == 3);
    CHECK(h.count_at(0.2) == 4);
    CHECK(h.count_at_radius(0.05) == 3);  // born at radius 0.05 or more: t >= 0.5
    CHECK(h.levels() == std::vector<double>{1.0, 0.5, 0.2});
    CHECK_THROWS_WITH(Hierarchy({{0, 0}, {1, 1}}, {0.5, 1.0}, 0.1), Catch::Contains("not in birth order"));
    CHECK_THROWS_WITH(Hierarchy({{0, 0}}, {}, 0.1), Catch::Contains("needs a birth t"));
    CHECK_THROWS_WITH(Hierarchy({{0, 0}}, {1.5}, 0.1), Catch::Contains("outside (0, 1]"));
}

TEST_CASE("lod and --hierarchy from the command line", "[hierarchy][cli]") {
    using test::cli;
    const auto dir = test::scratch();
    const std::string h = (dir / "h.csv").string(), p = (dir / "p.csv").string();
    REQUIRE(cli("sample --radius 0.02 --hierarchy discrete:5 --device cpu -o " + h).code == 0);
    REQUIRE(cli("lod " + h + " --t 0.6 -o " + p).code == 0);
    const PointSet prefix = read_point_set(p);
    REQUIRE(prefix.column("t"));
    for (double t : *prefix.column("t")) CHECK(t >= 0.6);
    REQUIRE(cli("lod " + h + " --radius 0.06 --r0 0.1 -o " + (dir / "q.csv").string()).code == 0);
    CHECK(read_point_set((dir / "q.csv").string()).points == prefix.points);  // t >= 0.06 / 0.1
    REQUIRE(cli("sample --radius 0.02 --device cpu -o " + p).code == 0);
    for (const std::string& bad : std::vector<std::string>{
             "lod " + p + " --t 0.5", "lod " + h + " --radius 0.05", "lod " + h + " --t 0", "lod " + h,
             "sample --radius 0.01 --hierarchy discrete:1", "sample --radius 0.01 --hierarchy continuous:0.5",
             "sample --radius 0.01 --hierarchy spiral:3", "sample --radius 0.01 --hierarchy discrete:5:0.5",
             "sample --radius 0.01 --hierarchy discrete:-3", "sample --radius 0.01 --hierarchy discrete:0",
             "sample --radius 0.01 --from " + (dir / "missing.csv").string()}) {
        const test::Run r = cli(bad + " -o " + (dir / "never.csv").string());
        INFO(bad << "\n" << r.err);
        CHECK(r.code == 2);
        CHECK(r.err.rfind("vrpd: error: ", 0) == 0);
        CHECK_FALSE(std::filesystem::exists(dir / "never.csv"));
    }
}

namespace {

SampleOptions continuous(double rf, double rc, double start, std::uint32_t seed) {
    SampleOptions o = test::options(rf, seed, Backend::Cpu);
    o.coverage = rc == rf ? 0.0 : rc;
    o.hierarchy.continuous = true;
    o.hierarchy.start = start;
    return o;
}

// The largest empty circle of points on the unit torus, by every triple of points and their
// images near the box, each circle tested against every point: centre and radius.
std::pair<glm::dvec2, double> largest_empty_circle(const std::vector<glm::dvec2>& pts, double margin) {
    std::vector<glm::dvec2> all;
    for (const glm::dvec2& p : pts)
        for (int sy = -1; sy <= 1; ++sy)
            for (int sx = -1; sx <= 1; ++sx) {
                const glm::dvec2 q{p.x + sx, p.y + sy};
                if (q.x > -margin && q.y > -margin && q.x < 1 + margin && q.y < 1 + margin) all.push_back(q);
            }
    std::pair<glm::dvec2, double> best{{0, 0}, 0};
    for (std::size_t i = 0; i < all.size(); ++i)
        for (std::size_t j = i + 1; j < all.size(); ++j)
            for (std::size_t k = j + 1; k < all.size(); ++k) {
                const glm::dvec2 a = all[i], b = all[j], c = all[k];
                const double d = 2 * (a.x * (b.y - c.y) + b.x * (c.y - a.y) + c.x * (a.y - b.y));
                if (std::abs(d) < 1e-14) continue;
                const double a2 = a.x * a.x + a.y * a.y, b2 = b.x * b.x + b.y * b.y, c2 = c.x * c.x + c.y * c.y;
                const glm::dvec2 o{(a2 * (b.y - c.y) + b2 * (c.y - a.y) + c2 * (a.y - b.y)) / d,
                                   (a2 * (c.x - b.x) + b2 * (a.x - c.x) + c2 * (b.x - a.x)) / d};
                if (o.x < 0 || o.y < 0 || o.x >= 1 || o.y >= 1) continue;
                const double r = std::hypot(a.x - o.x, a.y - o.y);
                if (r <= best.second || r > margin) continue;
                bool empty = true;
                for (const glm::dvec2& p : all) empty = empty && std::hypot(p.x - o.x, p.y - o.y) >= r * (1 - 1e-12);
                if (empty) best = {o, r};
            }
    return best;
}

}  // namespace

// Section 4.2 with one radius, checked from its definition: each inserted sample is the centre of
// the largest empty circle of the samples before it, and its t is that circle's radius over Rc0.
TEST_CASE("continuous hierarchy, one radius: each sample is the largest empty circle's centre, at its t",
          "[hierarchy]") {
    const double rf = 0.15, start = 2;
    const Sampling s = continuous_hierarchy(continuous(rf, rf, start, 3));
    std::size_t first = 0;
    while (first < s.size() && s.birth[first] == 1.0) ++first;
    REQUIRE(first >= 4);
    REQUIRE(s.size() - first >= 10);
    for (std::size_t k = first; k < s.size(); ++k) {
        const auto [centre, radius] = largest_empty_circle(points_of(s, k), 1.01 * rf * start);
        INFO("sample " << k << ": t " << s.birth[k] << ", circle " << radius << " at (" << centre.x << ", "
                       << centre.y << ")");
        CHECK(s.birth[k] == Approx(radius / (rf * start)).epsilon(1e-9));
        const glm::dvec2 p = s.point(k);
        const double dx = std::abs(p.x - centre.x), dy = std::abs(p.y - centre.y);
        CHECK(std::hypot(std::min(dx, 1 - dx), std::min(dy, 1 - dy)) <= s.quantum);
        CHECK(s.birth[k] <= s.birth[k - 1]);
    }
    // After the last sample, the largest empty circle is within the final radius.
    CHECK(largest_empty_circle(points_of(s, s.size()), 1.01 * rf * start).second <= rf);
}

// Every prefix, not only at steps: the samples born at t or earlier are conflict-free and maximal
// at t (Rf0, Rc0), up to the lattice rounding (one step).
TEST_CASE("continuous hierarchy: the prefix at any t is a maximal sampling at t's radii", "[hierarchy]") {
    for (const auto& [rf, rc] : {std::pair{0.02, 0.02}, std::pair{0.01, 0.02}}) {
        const double start = 5;
        const Sampling s = continuous_hierarchy(continuous(rf, rc, start, 11));
        const Hierarchy h(s);
        REQUIRE(h.levels().size() > 100);  // a t of its own for almost every sample
        for (int i = 0; i <= 40; ++i) {
            const double t = 1.0 / start + (1 - 1.0 / start) * i / 40.0;
            const std::size_t n = h.count_at(t);
            const Report rep = verify(points_of(s, n), {rf * start * t, rc * start * t, 2 * s.quantum}, Box{});
            INFO("Rf " << rf << " Rc " << rc << " t " << t << ": " << n << " samples, largest empty circle "
                       << rep.largest_empty_radius);
            CHECK(rep.conflicts == 0);
            CHECK(rep.maximal);
        }
    }
    SampleOptions free = continuous(0.02, 0.02, 5, 1);
    free.box.boundary = Boundary::Free;
    CHECK_THROWS_WITH(continuous_hierarchy(free), Catch::Contains("needs a periodic box"));
    CHECK_THROWS_WITH(sample(continuous(0.02, 0.02, 5, 1)), Catch::Contains("vrpd_geometry's continuous_hierarchy"));
}

// Section 4's comparison (Figures 4-9): a ten-step hierarchy against direct sampling at the same
// final radii, mean counts over 8 seeds. The laws need not be equal (the paper saw +1.1 %); the
// issue's bound is 3 %.
TEST_CASE("hierarchical counts are within 3 % of direct sampling", "[hierarchy][statistics]") {
    for (const auto& [rf, rc] : {std::pair{0.01, 0.01}, std::pair{0.005, 0.01}, std::pair{0.01, 0.02}}) {
        double direct = 0, layered = 0;
        for (std::uint32_t seed = 1; seed <= 8; ++seed) {
            SampleOptions o = hierarchy(rf, rc, 10, 0, seed, Backend::Cpu);
            layered += double(sample(o).size()) / 8;
            o.hierarchy = {};
            direct += double(sample(o).size()) / 8;
        }
        INFO("Rf " << rf << " Rc " << rc << ": direct " << direct << ", hierarchical " << layered);
        CHECK(layered == Approx(direct).epsilon(0.03));
    }
}
