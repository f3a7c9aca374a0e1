// Hierarchies (paper section 4) and runs from given samples: every level a prefix that is
// conflict-free and maximal at its radii, judged by the exact checker; births in order; the same
// points on every device; counts against direct sampling; bad options refused.
#include <catch2/catch.hpp>

#include <cmath>

#include "cli_support.h"
#include "support.h"
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
          "sample --radius 0.01 --hierarchy discrete:1", "sample --radius 0.01 --hierarchy continuous:10",
          "sample --radius 0.01 --hierarchy discrete:5:0.5", "sample --radius 0.01 --hierarchy discrete:-3",
          "sample --radius 0.01 --from " + (dir / "missing.csv").string()}) {
        const test::Run r = cli(bad + " -o " + (dir / "never.csv").string());
        INFO(bad << "\n" << r.err);
        CHECK(r.code == 2);
        CHECK(r.err.rfind("vrpd: error: ", 0) == 0);
        CHECK_FALSE(std::filesystem::exists(dir / "never.csv"));
    }
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
