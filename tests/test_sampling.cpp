// The sampling core (issue: MPS on Vulkan with a CPU twin): validation, conflict-freeness,
// determinism, gpu = cpu = serial parity (on lavapipe in CI) and the RSA density (bias).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include "cpu/cover_scatter.h"
#include "engine.h"
#include "plan.h"
#include "shared/sampler.h"
#include "support.h"
#include "vulkan/vulkan_engine.h"

using namespace vrpd;
using vrpd::test::options;

TEST_CASE("bad options are refused with a reason", "[options]") {
    auto refuses = [](SampleOptions o, const char* words) {
        try {
            validate(o);
        } catch (const Error& e) {
            CHECK_THAT(e.what(), Catch::Contains(words));
            return;
        }
        FAIL("accepted " << o.radius << " " << o.box.width << "x" << o.box.height);
    };
    refuses(options(0.0, 0, Backend::Cpu), "radius must be > 0");
    refuses(options(-1.0, 0, Backend::Cpu), "radius must be > 0");
    refuses(options(std::nan(""), 0, Backend::Cpu), "finite");
    refuses(options(0.5, 0, Backend::Cpu), "too large");
    refuses(options(0.1, 0, Backend::Cpu, {0.0, 1.0, Boundary::Free}), "extent");
    refuses(options(0.1, 0, Backend::Cpu, {1.0, -2.0, Boundary::Periodic}), "extent");
    refuses(options(0.1, 0, Backend::Cpu, {INFINITY, 1.0, Boundary::Free}), "extent");
    SampleOptions crowd = options(0.1, 0, Backend::Cpu);
    crowd.threads = 1u << 20;
    refuses(crowd, "threads");
    CHECK_NOTHROW(validate(options(0.4, 0, Backend::Cpu, {1.0, 1.0, Boundary::Free})));
    // Lengths whose squares or the box's area would leave the normal doubles.
    refuses(options(1e-301, 0, Backend::Cpu, {1e-300, 1e-300, Boundary::Periodic}), "outside the extents");
    refuses(options(1e101, 0, Backend::Cpu, {1e102, 1e102, Boundary::Free}), "outside the extents");
    refuses(options(1e-101, 0, Backend::Cpu, {1e-100, 1e-100, Boundary::Free}), "below the smallest length");
}

TEST_CASE("a periodic box must be tiled by the base cells", "[options]") {
    CHECK_NOTHROW(detail::make_plan(options(5.0, 0, Backend::Cpu, {1920, 1080, Boundary::Periodic})));
    CHECK_THROWS_WITH(detail::make_plan(options(0.1, 0, Backend::Cpu, {1.0, std::sqrt(2.0), Boundary::Periodic})),
                      Catch::Contains("ratio"));
}

TEST_CASE("the lattice plan keeps the invariants the kernels rely on", "[options]") {
    for (double r : {0.3, 0.05, 0.001, 0.0003}) {
        const detail::Plan plan = detail::make_plan(options(r, 0, Backend::Cpu));
        const std::uint64_t side = std::uint64_t(1) << plan.domain.cell_bits;
        INFO("r = " << r);
        CHECK(plan.domain.radii.inhibition2 > 2 * (side - 1) * (side - 1));      // a sample covers its base cell
        CHECK(plan.domain.lattice.extent_x < 0x80000000u);                    // grid tag bit stays free
        CHECK(std::abs(std::sqrt(double(plan.domain.radii.inhibition2)) * plan.quantum - r) < 1e-6 * r);
        CHECK(shared::conflict_reach(plan.domain.radii) <= int(shared::MAX_REACH));
    }
    // The conflict scans read their rows from the plan's table (shared::conflict_row), down to
    // lattices a few steps per base cell, where the rows are narrowest.
    for (std::uint32_t bits : {2u, 3u, 4u, 30u}) {
        for (double r : {0.3, 0.05, 0.03, 0.001}) {
            const detail::Plan plan = detail::make_plan(options(r, 0, Backend::Cpu), bits);
            const shared::Domain& d = plan.domain;
            const int reach = shared::conflict_reach(d.radii);
            INFO("r = " << r << ", at most " << bits << " cell bits");
            for (int dy = -reach; dy <= reach; ++dy) {
                CHECK(shared::conflict_row(d.radii, dy) ==
                      shared::computed_row_reach(d, dy, reach, d.radii.inhibition2));
                CHECK(shared::row_reach(d, dy, reach, d.radii.inhibition2) ==
                      shared::computed_row_reach(d, dy, reach, d.radii.inhibition2));
            }
        }
    }
}

struct Case {
    double radius;
    Box box;
    std::uint32_t max_cell_bits;
};

const Case kCases[] = {
    {0.05, {1, 1, Boundary::Periodic}, 30},
    {0.02, {1, 1, Boundary::Periodic}, 30},
    {0.03, {2, 1, Boundary::Periodic}, 30},
    {0.05, {1.5, 0.7, Boundary::Free}, 30},
    {0.02, {1, 1, Boundary::Free}, 30},
    // A coarse lattice: runs reach the deepest level, where cells are single lattice points.
    {0.03, {1, 1, Boundary::Periodic}, 4},
    {0.03, {1, 0.6, Boundary::Free}, 4},
    // The cpu backend's mask mode (levels 0-2) down to the deepest level, and ending at it.
    {0.03, {1, 0.6, Boundary::Free}, 2},
    {0.03, {1, 1, Boundary::Periodic}, 3},
};

TEST_CASE("samples are conflict-free, inside the box and in a defined order", "[sampling]") {
    for (const Case& c : kCases) {
        for (std::uint32_t seed : {1u, 2u}) {
            const SampleOptions o = options(c.radius, seed, Backend::Cpu, c.box);
            const detail::Plan plan = detail::make_plan(o, c.max_cell_bits);
            const Sampling s = detail::sample_plan(o, plan);
            INFO("r " << c.radius << " box " << c.box.width << "x" << c.box.height << " seed " << seed);
            REQUIRE(s.size() > 10);
            CHECK(vrpd::test::brute_force_conflicts(plan, s) == 0);
            for (std::size_t i = 0; i < s.size(); ++i) {
                const glm::dvec2 p = s.point(i);
                REQUIRE((p.x >= 0 && p.y >= 0 && p.x < c.box.width && p.y < c.box.height));
            }
            if (c.max_cell_bits == 4) CHECK(s.stats.levels > plan.deepest_level);
        }
    }
}

TEST_CASE("a radius far larger than a free box gives one sample, uniform over the box", "[sampling][gpu]") {
    // The lattice must stay fine across the box however large r is (and r^2 must not overflow).
    for (double r : {3.0, 1e300}) {
        std::vector<glm::dvec2> seen;
        for (std::uint32_t seed = 1; seed <= 4; ++seed) {
            const Box box{1, 0.5, Boundary::Free};
            const Sampling cpu = sample(options(r, seed, Backend::Cpu, box));
            const Sampling gpu = sample(options(r, seed, Backend::Gpu, box));
            REQUIRE(cpu.size() == 1);
            CHECK(gpu.lattice == cpu.lattice);
            const glm::dvec2 p = cpu.point(0);
            CHECK((p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 0.5));
            for (const glm::dvec2& q : seen) CHECK(q != p);
            seen.push_back(p);
        }
    }
}

TEST_CASE("the same seed gives the same points, another seed other points", "[sampling]") {
    const Sampling a = sample(options(0.02, 11, Backend::Cpu));
    const Sampling b = sample(options(0.02, 11, Backend::Cpu));
    const Sampling c = sample(options(0.02, 12, Backend::Cpu));
    CHECK(a.lattice == b.lattice);
    CHECK(a.lattice != c.lattice);
}

TEST_CASE("the cpu backend's points do not depend on its thread count", "[sampling]") {
    SampleOptions o = options(0.004, 6, Backend::Cpu);
    o.threads = 1;
    const Sampling one = sample(o);
    o.threads = 2;
    const Sampling two = sample(o);
    o.threads = 3;
    const Sampling three = sample(o);
    REQUIRE(one.size() > 40000);
    CHECK(two.lattice == one.lattice);
    CHECK(three.lattice == one.lattice);
}

TEST_CASE("gpu, cpu and serial give identical samples in identical order", "[sampling][gpu]") {
    for (const Case& c : kCases) {
        for (std::uint32_t seed : {3u, 4u}) {
            INFO("r " << c.radius << " box " << c.box.width << "x" << c.box.height << " bits " << c.max_cell_bits
                      << " seed " << seed);
            auto run = [&](Backend b, unsigned threads = 0) {
                SampleOptions o = options(c.radius, seed, b, c.box);
                o.threads = threads;
                detail::Plan plan = detail::make_plan(o, c.max_cell_bits);
                plan.strip_darts = 0;  // cpu on 2 threads: strips in every round, however small
                return detail::sample_plan(o, plan);
            };
            const Sampling serial = run(Backend::Serial);
            const Sampling cpu = run(Backend::Cpu, 3);             // the parallel resolution
            const Sampling cpu_one_thread = run(Backend::Cpu, 1);  // decides in arrival order
            const Sampling cpu_strips = run(Backend::Cpu, 2);      // in arrival order, a strip a thread
            const Sampling gpu = run(Backend::Gpu);
            REQUIRE(serial.size() > 10);
            CHECK(cpu.lattice == serial.lattice);
            CHECK(cpu_one_thread.lattice == serial.lattice);
            CHECK(cpu_strips.lattice == serial.lattice);
            CHECK(gpu.lattice == serial.lattice);
            CHECK(gpu.stats.darts == serial.stats.darts);
        }
    }
}

// The arrival-order decisions in three and four strips, whose neighbours on either side are other
// threads (the cpu backend takes them on up to two threads), in every round however small; one
// radius and two, periodic and free.
TEST_CASE("arrival order in three and four strips decides as the serial oracle does", "[sampling]") {
    for (const Box& box : {Box{1, 1, Boundary::Periodic}, Box{1, 0.8, Boundary::Free}}) {
        for (double rc : {0.0, 0.008}) {
            SampleOptions o = options(0.004, 7, Backend::Serial, box);
            o.coverage = rc;
            detail::Plan plan = detail::make_plan(o);
            plan.strip_darts = 0;
            const Sampling serial = detail::sample_plan(o, plan);
            REQUIRE(serial.size() > 10000);
            for (unsigned threads : {3u, 4u}) {
                INFO("box " << box.width << "x" << box.height << " Rc " << rc << " threads " << threads);
                const auto engine = detail::make_host_engine(plan, detail::Resolution::ArrivalOrder, threads);
                CHECK(detail::run_plan(o, plan, *engine).lattice == serial.lattice);
            }
        }
    }
}

// The profile (SampleOptions::profile) is for finding where the time goes: it must name the
// phases that ran, account for no more than the run's wall time, and leave the points alone.
TEST_CASE("profiling names the phases that ran, within the run's time, and changes no point", "[sampling][gpu]") {
    // The cpu backend on 3 threads resolves in parallel, on 1 it decides and emits in arrival order.
    for (auto [b, threads] :
         {std::pair{Backend::Serial, 0u}, {Backend::Cpu, 3u}, {Backend::Cpu, 1u}, {Backend::Gpu, 0u}}) {
        INFO("backend " << int(b) << " threads " << threads);
        SampleOptions o = options(0.01, 9, b);
        o.threads = threads;
        const Sampling plain = sample(o);
        CHECK(plain.stats.profile.empty());
        o.profile = true;
        const Sampling timed = sample(o);
        CHECK(timed.lattice == plain.lattice);
        std::vector<std::string> names;
        double sum = 0.0;
        for (const PhaseTime& p : timed.stats.profile) {
            names.push_back(p.name);
            CHECK(p.seconds >= 0.0);
            CHECK(p.calls > 0);
            // Host phases run once a round; kernels at least once a round that reaches them.
            if (b != Backend::Gpu) CHECK(p.calls == timed.stats.rounds);
            sum += p.seconds;
        }
        // Device timestamps and the host clock differ by their rates: allow 1 %.
        CHECK(sum <= timed.stats.seconds * 1.01);
        CHECK(sum > 0.0);
        const std::vector<std::string> expected =
            b == Backend::Gpu
                ? std::vector<std::string>{"count_masked",  "mark_masked",  "throw_sited", "resolve_darts",
                                           "refine_masked", "refine_cells", "emit_samples"}
            : threads == 1 ? std::vector<std::string>{"throw", "resolve", "commit", "refine"}
                           : std::vector<std::string>{"throw", "resolve", "commit", "emit", "refine"};
        for (const std::string& e : expected) CHECK(std::count(names.begin(), names.end(), e) == 1);
        if (b != Backend::Gpu) CHECK(names == expected);  // in the order they first ran
    }
}

// A submit the host waits on costs a real GPU a queue's latency however little it carries. Past
// the first levels a round (one a level) is 1: throw, resolution passes and, behind a gate that
// holds while darts are undecided, commit, emission, sort, refinement into a worst-case list and
// the next round's dart counts. Setup, read-back and the first levels' larger lists add a dozen.
TEST_CASE("the Vulkan engine waits on the device once a deep level", "[sampling][gpu]") {
    for (double r : {0.01, 0.004}) {
        INFO("r = " << r);
        const Sampling gpu = sample(options(r, 3, Backend::Gpu));
        CHECK(gpu.stats.levels > 10);
        CHECK(gpu.stats.round_trips > gpu.stats.levels);
        CHECK(gpu.stats.round_trips <= 2 * gpu.stats.levels + 12);
        CHECK(sample(options(r, 3, Backend::Cpu)).stats.round_trips == 0);
    }
}

// With one resolution pass a submit, the deep rounds' resolutions outrun the submit that carries
// their gated end: the gate must hold it (a commit over undecided darts would keep none of them),
// and the end recorded with the submit that finishes the passes gives the same points.
TEST_CASE("a gated round end waits for its resolution's last submit", "[sampling][gpu]") {
    const SampleOptions o = options(0.004, 5, Backend::Gpu);
    const detail::Plan plan = detail::make_plan(o);
    detail::VulkanEngine engine(plan, o.device, nullptr, 1);
    const Sampling gpu = detail::run_plan(o, plan, engine);
    CHECK(engine.shut_gates() > 0);
    CHECK(gpu.lattice == sample(options(0.004, 5, Backend::Cpu)).lattice);
}

// Every dispatch, and every resolution pass over a work list, runs in rows of at most 65 535
// workgroups (the least limit Vulkan allows; lavapipe's, and many GPUs'): from r = 0.0007 on, a
// kernel over the base cells needs more. With rows of one workgroup every dispatch of more than
// 64 items takes several rows, and each kernel must number its items across them.
TEST_CASE("dispatches and passes longer than a row of workgroups take several rows", "[sampling][gpu]") {
    for (const double rc : {0.0, 0.016}) {
        SampleOptions o = options(0.01, 3, Backend::Gpu);
        o.coverage = rc;
        const detail::Plan plan = detail::make_plan(o);
        detail::VulkanEngine engine(plan, o.device, nullptr, detail::VulkanEngine::kResolvePassesPerSubmit, 1);
        const Sampling gpu = detail::run_plan(o, plan, engine);
        REQUIRE(gpu.size() > 2000);
        o.backend = Backend::Cpu;
        CHECK(gpu.lattice == sample(o).lattice);
    }
}

TEST_CASE("parity holds on a large first round (many darts per resolution pass)", "[sampling][gpu]") {
    const Sampling cpu = sample(options(0.004, 5, Backend::Cpu));
    const Sampling gpu = sample(options(0.004, 5, Backend::Gpu));
    REQUIRE(cpu.size() > 40000);
    CHECK(gpu.lattice == cpu.lattice);
}

// The memory check before a run (plan.cpp) counts 48 bytes of arrays per base cell; measured at
// r = 0.001: 25 on lavapipe, 20 for cpu, 32 for serial. Every engine must stay within it, or a run the check lets
// through could still run out of memory; the lower bound is the grid and the samples themselves.
// Rc = 1.1 Rf, the nearest two radii allowed, once multiplied its active cells by 3-4 a level
// and ran out of memory (driver.cpp, kCrowded).
TEST_CASE("the engines' arrays stay within the memory estimate checked before a run", "[sampling][gpu]") {
    for (double rc : {0.0, 0.008, 0.0044}) {
        for (auto [b, threads] : {std::pair{Backend::Gpu, 0u},
                                  {Backend::Cpu, 3u},
                                  {Backend::Cpu, 2u},
                                  {Backend::Cpu, 1u},
                                  {Backend::Serial, 0u}}) {
            SampleOptions o = options(0.004, 2, b);
            o.coverage = rc;
            o.threads = threads;  // cpu: 3 threads resolve in parallel, 1-2 in arrival order
            const detail::Plan plan = detail::make_plan(o);
            const Sampling s = detail::sample_plan(o, plan);
            INFO("backend " << int(b) << " threads " << threads << " Rc " << rc << " base cells " << plan.base_cells
                            << " peak " << s.stats.peak_bytes);
            CHECK(s.stats.peak_bytes >= plan.base_cells * 8 + s.size() * 8);
            CHECK(s.stats.peak_bytes <= plan.base_cells * 48 + (1u << 20));
            // Mask mode and 12-byte darts: the goal of 64 bytes per sample (measured here:
            // cpu 56, gpu 60; the serial oracle keeps the explicit lists).
            if (b != Backend::Serial && rc == 0.0) CHECK(s.stats.peak_bytes <= 64 * s.size());
        }
    }
}

// RSA (the bias-free process of Eq. 4) jams at n r^2 / area = 4 theta / pi = 0.69656 (theta =
// 0.547069). Measured here, r = 0.002, seeds 1-8: mean 0.696609, per-seed sd 0.00043, so the
// standard error of the mean is 0.00015; the 0.1 % tolerance (0.0007) is 4.6 standard errors. A
// biased sampler fails it: in the prototype measurements quoted in the issue, one dart per cell
// per round came out -0.24 % and nine phase groups +2.5 %.
// Refinement reads a base cell's samples as offsets gathered once (sampler.h), with no torus
// arithmetic; this checks it against all samples and torus distances computed here, on tori
// only 2 reach + 1 base cells wide, where the offsets' exactness argument is tightest.
TEST_CASE("refinement drops exactly the children one sample's disk covers", "[sampling]") {
    struct RefineCase {
        double rf, rc;
        Box box;
        std::uint32_t max_cell_bits;
    };
    const RefineCase cases[] = {
        {0.3, 0.3, {1, 1, Boundary::Periodic}, 30},   {0.13, 0.13, {1, 1, Boundary::Periodic}, 30},
        {0.2, 0.2, {2, 1, Boundary::Periodic}, 30},   {0.05, 0.05, {1.5, 0.7, Boundary::Free}, 30},
        {0.03, 0.03, {1, 0.6, Boundary::Free}, 4},     {0.05, 0.2, {1, 1, Boundary::Periodic}, 30},
        {0.05, 0.15, {1.3, 1, Boundary::Free}, 30},
    };
    using namespace shared;
    std::mt19937 rng(7);
    for (const RefineCase& c : cases) {
        SampleOptions o = options(c.rf, 3, Backend::Cpu, c.box);
        if (c.rc != c.rf) o.coverage = c.rc;
        const detail::Plan plan = detail::make_plan(o, c.max_cell_bits);
        const Sampling full = detail::sample_plan(o, plan);
        const Domain& d = plan.domain;
        INFO("Rf " << c.rf << " Rc " << c.rc << " box " << c.box.width << "x" << c.box.height);
        // Every third sample removed, so that cells stay uncovered.
        std::vector<uvec2> grid(plan.base_cells, uvec2(GRID_EMPTY, GRID_EMPTY));
        std::vector<uvec2> kept;
        for (std::size_t i = 0; i < full.size(); ++i)
            if (i % 3 != 0) kept.push_back(full.lattice[i]);
        for (uvec2 p : kept) grid[base_of_point(d, p)] = p;
        std::size_t dropped = 0, alive = 0;
        for (std::uint32_t b = 0; b < plan.base_cells; ++b) {
            if (grid_is_sample(grid[b])) continue;
            const uvec2 base(b % d.cells_x, b / d.cells_x);
            const uvec2 origin(base.x << d.cell_bits, base.y << d.cell_bits);
            const Domain dom = local_domain(d, base);
            const uint n = gather_cell_samples(dom, Grid{grid.data()}, base);
            if (!two_radii(d.radii)) REQUIRE(n <= MAX_CELL_SAMPLES);
            for (int trial = 0; trial < 3; ++trial) {
                // A random active cell of the base cell, at level 0 (kept whole) or split in 4.
                const uint level = std::uniform_int_distribution<uint>(0, std::min(d.cell_bits, 6u))(rng);
                const uint fanout = level == 0 ? 1u : 4u;
                const uint side = level == 0 ? 1u << d.cell_bits : 1u << (d.cell_bits - level);
                const uint cells_across = 1u << d.cell_bits >> (level == 0 ? d.cell_bits : d.cell_bits - level + 1);
                std::uniform_int_distribution<uint> pick(0, cells_across - 1);
                const uvec2 corner = origin + uvec2(pick(rng), pick(rng)) * (fanout == 4u ? 2u * side : side);
                const uint mask = surviving_children(dom, Grid{grid.data()}, base, corner, side, fanout, n);
                const uint scanned =
                    surviving_children(dom, Grid{grid.data()}, base, corner, side, fanout, MAX_CELL_SAMPLES + 1);
                REQUIRE(mask == scanned);
                if (two_radii(d.radii)) continue;  // the exact U test of two radii has tests of its own
                for (uint ch = 0; ch < fanout; ++ch) {
                    const uvec2 cc = child_corner(corner, side, ch);
                    bool expect = cc.x < d.lattice.extent_x && cc.y < d.lattice.extent_y;
                    const uvec2 hi(std::min(cc.x + side - 1, d.lattice.extent_x - 1),
                                   std::min(cc.y + side - 1, d.lattice.extent_y - 1));
                    // Between the rounds of a level above the deepest, one radius tests no cover (cover_tested).
                    for (uvec2 p : kept) {
                        if (!expect || !cover_tested(d, fanout, side)) break;
                        bool covers = true;
                        for (uvec2 q : {cc, hi, uvec2(cc.x, hi.y), uvec2(hi.x, cc.y)})
                            covers = covers && vrpd::test::lattice_distance2(plan, p, q) < d.radii.inhibition2;
                        expect = !covers;
                    }
                    CHECK(((mask >> ch) & 1u) == (expect ? 1u : 0u));
                    (expect ? alive : dropped)++;
                }
            }
        }
        if (!two_radii(d.radii)) CHECK((dropped > 20 && alive > 20));
    }
}

TEST_CASE("mask mode's refinement by scattered covers keeps the children the gathered test keeps", "[sampling]") {
    struct ScatterCase {
        double r;
        Box box;
        std::uint32_t max_cell_bits;
    };
    // A coarse lattice (max_cell_bits 3 or 4) puts samples at exactly r from children's corners.
    const ScatterCase cases[] = {{0.02, {1, 1, Boundary::Periodic}, 30},
                                 {0.013, {1.3, 0.7, Boundary::Free}, 30},
                                 {0.03, {1, 1, Boundary::Periodic}, 3},
                                 {0.05, {0.6, 1, Boundary::Free}, 4}};
    using namespace shared;
    std::mt19937 rng(11);
    detail::ThreadPool pool(3);
    std::uint64_t taken = 0;
    for (const ScatterCase& c : cases) {
        const SampleOptions o = options(c.r, 5, Backend::Cpu, c.box);
        const detail::Plan plan = detail::make_plan(o, c.max_cell_bits);
        const Sampling full = detail::sample_plan(o, plan);
        const Domain& d = plan.domain;
        for (uint level = 1u; level <= 2u; ++level) {
            INFO("r " << c.r << " box " << c.box.width << "x" << c.box.height << " children of level " << level);
            // Every third sample removed, so that cells stay uncovered; the other base cells hold
            // level 0's one cell or random cells of level 1, some as a round's darts word.
            std::vector<uvec2> grid(plan.base_cells);
            for (uvec2& w : grid) {
                const uint mask = level == 1u ? 1u : uint(rng() % 16u);
                w = rng() % 4u ? uvec2(GRID_EMPTY, mask) : uvec2(GRID_TAG | GRID_PACKED | 7u, 3u << 16u | mask);
            }
            for (std::size_t i = 0; i < full.size(); ++i)
                if (i % 3 != 0) grid[base_of_point(d, full.lattice[i])] = full.lattice[i];
            // On a coarse lattice, r^2 becomes the commonest squared gap from a sample to a child's
            // farthest corner in [r^2 / 2, r^2]: many children lie at exactly r (r shrinks, so
            // the samples stay conflict-free and the reaches hold).
            Domain dom = d;
            if (c.max_cell_bits <= 4u) {
                const int h = (1 << d.cell_bits) >> level, reach = cover_reach(d.radii);
                const int lo = -reach << level, hi = (reach + 1) << level;
                std::map<std::uint64_t, int> seen;
                for (std::size_t i = 1; i < std::min<std::size_t>(full.size(), 400); i += 3) {
                    const uvec2 at = full.lattice[i] & uvec2((1u << d.cell_bits) - 1u);
                    for (int jy = lo; jy < hi; ++jy)
                        for (int jx = lo; jx < hi; ++jx) {
                            const std::uint64_t g =
                                far2(int(at.x), jx * h, jx * h + h - 1) + far2(int(at.y), jy * h, jy * h + h - 1);
                            if (2u * g >= d.radii.coverage2 && g <= d.radii.coverage2) ++seen[g];
                        }
                }
                const auto common = std::max_element(seen.begin(), seen.end(),
                                                     [](const auto& x, const auto& y) { return x.second < y.second; });
                REQUIRE(common != seen.end());
                dom.radii.coverage2 = dom.radii.inhibition2 = common->first;
            }
            const CellArgs a{dom, 0, 0, 0, 0, 0, 0, 0, 0, uint(plan.base_cells), 0, (1u << d.cell_bits) >> level, 4u};
            std::vector<uint> expected(plan.base_cells);
            std::uint64_t active = 0;
            for (uint b = 0; b < plan.base_cells; ++b) {
                expected[b] = refine_masked_base(a, Grid{grid.data()}, b).x;
                active += uint(bitCount(expected[b]));
                const uvec2 w = grid[b];
                if (!grid_is_sample(w))
                    for (uint m = w.y & 15u; m != 0u; m &= m - 1u)
                        taken += 4u - uint(bitCount(expected[b] >> (4u * uint(findLSB(m))) & 15u));
            }
            for (const bool vector : {true, false}) {
                INFO("vector bodies " << vector);
                std::vector<uint> masks(plan.base_cells, 0xDEADu);
                CHECK(detail::refine_masked_scattered(pool, a, Grid{grid.data()}, masks.data(), vector) == active);
                REQUIRE(masks == expected);
            }
        }
    }
    CHECK(taken > 10000);
}

TEST_CASE("density matches random sequential adsorption within 0.1 %", "[statistics]") {
    double sum = 0;
    const int seeds = 8;
    for (int seed = 1; seed <= seeds; ++seed) {
        const Sampling s = sample(options(0.002, std::uint32_t(seed), Backend::Cpu));
        sum += double(s.size()) * 0.002 * 0.002;
    }
    const double mean = sum / seeds;
    INFO("mean n r^2 over " << seeds << " seeds: " << mean);
    CHECK(std::abs(mean - 0.69656) < 0.001 * 0.69656);
}
