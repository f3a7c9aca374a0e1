// The shared predicates against oracles written from the paper's definitions (Eqs. 1-3), not from
// shared/: the lattice distance, conflict and cover of a point (strict: a pair at exactly r neither
// conflicts nor covers), and the quadtree's cover test of a cell, on random and tied inputs. Then
// whole runs on a lattice where pairs at exactly r occur: they must be kept, and every lattice
// point must end strictly covered. Last, the host's versions of two GLSL built-ins, and its
// vectorised bodies (window scans, children's cover test, dart counts) against the scalar ones.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "plan.h"
#include "shared/sampler.h"
#include "support.h"

using namespace vrpd;

namespace {

// |a - b| the shorter way round a circle of `extent` points, in 64 bits from first principles.
std::uint64_t oracle_gap(std::int64_t a, std::int64_t b, std::int64_t extent, bool periodic) {
    std::int64_t d = a > b ? a - b : b - a;
    if (periodic) d = std::min(d, extent - d);
    return std::uint64_t(d);
}

std::uint64_t oracle_distance2(glm::i64vec2 p, glm::i64vec2 q, glm::i64vec2 extent, bool periodic) {
    const unsigned __int128 dx = oracle_gap(p.x, q.x, extent.x, periodic);
    const unsigned __int128 dy = oracle_gap(p.y, q.y, extent.y, periodic);
    const unsigned __int128 d2 = dx * dx + dy * dy;
    REQUIRE(d2 < (unsigned __int128)(1) << 64);
    return std::uint64_t(d2);
}

// Squared radii that are sums of two squares in several ways, so that ties occur.
constexpr std::uint64_t kTiedRadii2[] = {25, 50, 65, 85, 125, 325};

}  // namespace

TEST_CASE("predicates: the lattice distance is the shorter way round, exactly, up to 2^31", "[predicates]") {
    std::mt19937_64 rng(7);
    for (int i = 0; i < 20000; ++i) {
        const bool periodic = i % 2 == 0;
        const std::uint32_t ex = 1 + std::uint32_t(rng() % ((i % 3 == 0) ? 0x7FFFFFFFu : 1000u));
        const std::uint32_t ey = 1 + std::uint32_t(rng() % ((i % 5 == 0) ? 0x7FFFFFFFu : 1000u));
        const shared::Lattice l{ex, ey, periodic ? 1u : 0u};
        const glm::uvec2 p(std::uint32_t(rng() % ex), std::uint32_t(rng() % ey));
        const glm::uvec2 q(std::uint32_t(rng() % ex), std::uint32_t(rng() % ey));
        INFO("extent " << ex << "x" << ey << " p " << p.x << "," << p.y << " q " << q.x << "," << q.y);
        CHECK(shared::distance2(l, p, q) == oracle_distance2(p, q, glm::i64vec2(ex, ey), periodic));
        CHECK(shared::distance2(l, p, q) == shared::distance2(l, q, p));
    }
}

TEST_CASE("predicates: the farthest gap to an interval is its farthest coordinate's, half a torus where it holds one",
          "[predicates]") {
    // Against every coordinate of the interval on small extents, odd and even; on a torus an
    // interval past the point's antipode has a farther coordinate than either end.
    std::mt19937_64 rng(11);
    int antipodal = 0;
    for (int i = 0; i < 20000; ++i) {
        const std::uint32_t periodic = std::uint32_t(i % 2), extent = 2 + std::uint32_t(rng() % 60);
        const std::uint32_t v = std::uint32_t(rng() % extent), a = std::uint32_t(rng() % extent);
        const std::uint32_t b = a + std::uint32_t(rng() % (extent - a));
        std::uint32_t far = 0;
        for (std::uint32_t c = a; c <= b; ++c) far = std::max(far, shared::axis_gap(v, c, extent, periodic));
        INFO("extent " << extent << " periodic " << periodic << " v " << v << " [" << a << ", " << b << "]");
        REQUIRE(shared::axis_far_gap(v, a, b, extent, periodic) == far);
        antipodal += far > std::max(shared::axis_gap(v, a, extent, periodic), shared::axis_gap(v, b, extent, periodic));
    }
    CHECK(antipodal > 1000);
    // At the largest extent the sums stay within 32 bits.
    const std::uint32_t big = 0x80000000u;
    CHECK(shared::axis_far_gap(big - 1, big / 2 - 1, big / 2 - 1, big, 1u) == big / 2);
    CHECK(shared::axis_far_gap(big - 1, 0, 5, big, 1u) == 6u);
    CHECK(shared::axis_far_gap(big - 1, 0, big - 1, big, 0u) == big - 1);
}

TEST_CASE("predicates: conflict and cover are strict, a pair at exactly r neither conflicts nor covers",
          "[predicates]") {
    const shared::Lattice l{1000, 1000, 0};
    for (const std::uint64_t r2 : kTiedRadii2) {
        const shared::Radii radii{r2, r2, shared::RADII_ONE, 0};
        int ties = 0;
        for (int dx = 0; dx * dx <= int(r2) + 1; ++dx)
            for (int dy = 0; dx * dx + dy * dy <= int(r2) + 1; ++dy) {
                const std::uint64_t d2 = shared::distance2(l, glm::uvec2(500, 500), glm::uvec2(500 + dx, 500 - dy));
                const bool inside = std::uint64_t(dx * dx + dy * dy) < r2;  // Eqs. 1-2: closer than r
                ties += std::uint64_t(dx * dx + dy * dy) == r2 ? 1 : 0;
                CHECK(shared::inhibits(radii, d2) == inside);
                CHECK(shared::covers(radii, d2) == inside);
                CHECK(shared::reaches(radii, d2) == (std::uint64_t(dx * dx + dy * dy) <= r2));  // T: closed disk
            }
        CHECK(ties >= 2);  // these radii do meet ties
    }
}

TEST_CASE("predicates: one disk drops a quadtree cell iff it covers every lattice point of it", "[predicates]") {
    using namespace shared;
    std::mt19937_64 rng(11);
    for (const std::uint64_t r2 : kTiedRadii2) {
        Domain dom{};
        dom.radii = {r2, r2, RADII_ONE, 0};
        for (std::uint32_t side = 1; side <= 4; side *= 2) {
            // Four children of side `side` as closed intervals of their lattice points (one radius:
            // surviving_children's cells), from the base cell's corner.
            ChildBoxes b;
            b.lo0 = ivec2(0, 0);
            b.hi0 = ivec2(int(side) - 1, int(side) - 1);
            b.lo1 = ivec2(int(side), int(side));
            b.hi1 = ivec2(2 * int(side) - 1, 2 * int(side) - 1);
            for (int k = 0; k < 400; ++k) {
                const ivec2 o(int(rng() % 40) - 15, int(rng() % 40) - 15);
                uint mask = 0xFu, corners = 0u;
                cover_children(dom, b, 4u, o, mask, corners);
                for (uint c = 0; c < 4; ++c) {
                    const ivec2 lo((c & 1u) ? b.lo1.x : b.lo0.x, (c & 2u) ? b.lo1.y : b.lo0.y);
                    const ivec2 hi((c & 1u) ? b.hi1.x : b.hi0.x, (c & 2u) ? b.hi1.y : b.hi0.y);
                    bool all = true;
                    for (int x = lo.x; x <= hi.x; ++x)
                        for (int y = lo.y; y <= hi.y; ++y)
                            all = all && std::uint64_t((x - o.x) * (x - o.x) + (y - o.y) * (y - o.y)) < r2;
                    INFO("r2 " << r2 << " side " << side << " sample " << o.x << "," << o.y << " child " << c);
                    CHECK(((mask >> c) & 1u) == (all ? 0u : 1u));
                }
            }
        }
    }
}

TEST_CASE("runs where pairs at exactly r occur keep them, and leave no lattice point at exactly r uncovered",
          "[predicates][gpu]") {
    // Periodic unit box, r = 0.03, two lattice bits: 48 x 48 cells of 4 x 4 points; Rf^2 = 34 =
    // 5^2 + 3^2 lattice units, so samples may sit exactly r apart.
    const SampleOptions base = test::options(0.03, 1, Backend::Cpu);
    const detail::Plan plan = detail::make_plan(base, 2);
    const std::uint64_t r2 = plan.domain.radii.inhibition2;
    REQUIRE(r2 == 34);
    const std::uint32_t n = plan.domain.lattice.extent_x;
    std::uint64_t ties = 0;
    for (Backend b : {Backend::Cpu, Backend::Serial, Backend::Gpu}) {
        for (std::uint32_t seed = 1; seed <= 3; ++seed) {
            SampleOptions o = base;
            o.backend = b;
            o.seed = seed;
            const Sampling s = detail::sample_plan(o, plan);
            INFO("backend " << int(b) << " seed " << seed);
            // Buckets of samples by base cell, for the brute-force scans.
            const std::uint32_t cells = plan.domain.cells_x, side = 1u << plan.domain.cell_bits;
            std::vector<std::vector<glm::uvec2>> bucket(std::size_t(cells) * cells);
            for (const glm::uvec2 p : s.lattice) bucket[(p.y / side) * cells + p.x / side].push_back(p);
            std::uint64_t closer = 0;
            for (std::size_t i = 0; i < s.size(); ++i)
                for (std::size_t j = i + 1; j < s.size(); ++j) {
                    const std::uint64_t d2 = test::lattice_distance2(plan, s.lattice[i], s.lattice[j]);
                    closer += d2 < r2 ? 1 : 0;
                    ties += d2 == r2 ? 1 : 0;
                }
            CHECK(closer == 0);
            std::uint64_t uncovered = 0;
            for (std::uint32_t y = 0; y < n; ++y)
                for (std::uint32_t x = 0; x < n; ++x) {
                    bool covered = false;
                    for (int dy = -3; dy <= 3 && !covered; ++dy)
                        for (int dx = -3; dx <= 3 && !covered; ++dx) {
                            const std::uint32_t cx = (x / side + cells + dx) % cells,
                                                cy = (y / side + cells + dy) % cells;
                            for (const glm::uvec2 p : bucket[cy * cells + cx])
                                covered = covered || test::lattice_distance2(plan, p, glm::uvec2(x, y)) < r2;
                        }
                    uncovered += covered ? 0 : 1;
                }
            CHECK(uncovered == 0);
        }
    }
    CHECK(ties > 0);  // the runs did meet pairs at exactly r
}

TEST_CASE("predicates: the host's bitCount and findLSB are GLSL's, on every bit position and random words",
          "[predicates]") {
    std::mt19937 rng(11);
    auto oracle_count = [](std::uint32_t v) {
        int n = 0;
        for (int b = 0; b < 32; ++b) n += int(v >> b & 1u);
        return n;
    };
    std::vector<std::uint32_t> words = {0u, 0xFFFFFFFFu, 0x80000000u, 0x55555555u, 0xAAAAAAAAu};
    for (int b = 0; b < 32; ++b) words.push_back(1u << b);
    for (int i = 0; i < 20000; ++i) words.push_back(rng());
    for (std::uint32_t v : words) {
        REQUIRE(shared::bitCount(v) == oracle_count(v));
        int lsb = -1;
        for (int b = 31; b >= 0; --b)
            if (v >> b & 1u) lsb = b;
        REQUIRE(shared::findLSB(v) == lsb);
    }
}

TEST_CASE(
    "predicates: the host's vectorised window scans find the samples within a radius of a point or a cell, "
    "or covering a cell",
    "[predicates]") {
#ifndef VRPD_HOST_AVX2
    SUCCEED("not x86-64: near_sample keeps its scalar scan");
#else
    if (!shared::host_has_avx2()) SUCCEED("no AVX2 here: near_sample keeps its scalar scan");
    if (!shared::host_has_avx2()) return;
    std::mt19937_64 rng(13);
    constexpr int kSide = 9;  // a 9 x 9 grid of base cells, the window around the middle one
    int found = 0, covering = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const std::uint32_t bits = 1 + std::uint32_t(rng() % 20), side = 1u << bits;
        const int reach = 1 + int(rng() % 3);
        // Half the grids with the middle cell last below x = 2^31: a darts word's x (GRID_TAG |
        // its first dart) then differs little from p's, and only the tag tells it from a sample.
        const bool top = rng() % 2;
        const std::uint32_t origin = top ? (0x80000000u >> bits) - 5 : 0;
        std::vector<glm::uvec2> grid(kSide * kSide);
        std::vector<std::uint64_t> gaps;  // the samples' squared distances to p
        const glm::uvec2 p(((origin + 4) << bits) + std::uint32_t(rng() % side),
                           ((origin + 4) << bits) + std::uint32_t(rng() % side));
        for (int cy = 0; cy < kSide; ++cy)
            for (int cx = 0; cx < kSide; ++cx) {
                glm::uvec2& w = grid[std::size_t(cy * kSide + cx)];
                switch (top && cx > 4 ? rng() % 2 : rng() % 3) {  // no sample past the lattice
                    case 0:
                        w = glm::uvec2(shared::GRID_EMPTY, shared::GRID_EMPTY);
                        break;
                    case 1:
                        w = glm::uvec2(shared::GRID_TAG | std::uint32_t(rng() % side), p.y);
                        break;
                    default:
                        w = glm::uvec2(((origin + std::uint32_t(cx)) << bits) + std::uint32_t(rng() % side),
                                       ((origin + std::uint32_t(cy)) << bits) + std::uint32_t(rng() % side));
                        if (std::abs(cx - 4) <= reach && std::abs(cy - 4) <= reach)
                            gaps.push_back(std::uint64_t((std::int64_t(w.x) - p.x) * (std::int64_t(w.x) - p.x) +
                                                         (std::int64_t(w.y) - p.y) * (std::int64_t(w.y) - p.y)));
                }
            }
        // The radius at random, or tied with the nearest sample's distance (at it or one unit past).
        std::uint64_t limit2 = rng() % (std::uint64_t(reach + 1) * side * (std::uint64_t(reach + 1) * side));
        if (!gaps.empty() && rng() % 2) limit2 = *std::min_element(gaps.begin(), gaps.end()) + rng() % 2;
        bool oracle = false;
        for (std::uint64_t g : gaps) oracle |= g < limit2;
        found += oracle ? 1 : 0;
        INFO("trial " << trial << " bits " << bits << " reach " << reach << " limit2 " << limit2);
        REQUIRE(shared::window_holds_within<false>(&grid[4 * kSide + 4], kSide, reach, p, limit2) == oracle);
        // The gather: the samples whose squared gap to the middle cell's closed square is below
        // limit2, as offsets from its corner, the 3 x 3 adjacent cells' first, rows in order.
        const glm::uvec2 corner((origin + 4) << bits, (origin + 4) << bits);
        std::vector<glm::ivec2> expected[2];
        for (int dy = -reach; dy <= reach; ++dy)
            for (int dx = -reach; dx <= reach; ++dx) {
                const glm::uvec2 w = grid[std::size_t((4 + dy) * kSide + 4 + dx)];
                if (w.x & shared::GRID_TAG) continue;
                const glm::i64vec2 o(std::int64_t(w.x) - corner.x, std::int64_t(w.y) - corner.y);
                const std::int64_t gx = std::max<std::int64_t>({-o.x, o.x - side, 0});
                const std::int64_t gy = std::max<std::int64_t>({-o.y, o.y - side, 0});
                if (std::uint64_t(gx * gx + gy * gy) < limit2)
                    expected[std::abs(dx) <= 1 && std::abs(dy) <= 1 ? 0 : 1].emplace_back(o);
            }
        // The cover of the middle cell [0, far.x] x [0, far.y] from its corner (base_covered's, far
        // clipped as at a free boundary): a sample's farthest squared distance to it below limit2,
        // at random or tied with the least (at it or one unit past).
        const glm::ivec2 far(int(rng() % (side + 1)), int(rng() % (side + 1)));
        std::vector<std::uint64_t> farthest;
        for (int dy = -reach; dy <= reach; ++dy)
            for (int dx = -reach; dx <= reach; ++dx) {
                const glm::uvec2 w = grid[std::size_t((4 + dy) * kSide + 4 + dx)];
                if (w.x & shared::GRID_TAG) continue;
                const glm::i64vec2 o(std::int64_t(w.x) - corner.x, std::int64_t(w.y) - corner.y);
                const std::int64_t fx = std::max(o.x, far.x - o.x), fy = std::max(o.y, far.y - o.y);
                farthest.push_back(std::uint64_t(fx * fx + fy * fy));
            }
        std::uint64_t cover2 = rng() % (std::uint64_t(reach + 2) * side * (std::uint64_t(reach + 2) * side));
        if (!farthest.empty() && rng() % 2) cover2 = *std::min_element(farthest.begin(), farthest.end()) + rng() % 2;
        bool covered = false;
        for (std::uint64_t f : farthest) covered |= f < cover2;
        covering += covered ? 1 : 0;
        REQUIRE(shared::window_holds_within<true>(&grid[4 * kSide + 4], kSide, reach, corner, cover2, far) == covered);
        // The two-radii dart's gather: the samples closer than sqrt(limit2) to p in a window of any
        // reach (up to the grid's 4: one to three loads a row, the last partial), as offsets from
        // p in the scan's order, or past `most` its count plus one.
        const int wide = 1 + int(rng() % 4);
        const std::uint32_t most = rng() % 2 ? shared::MAX_DISKS : std::uint32_t(rng() % 4);
        std::vector<glm::ivec2> near;
        for (int dy = -wide; dy <= wide; ++dy)
            for (int dx = -wide; dx <= wide; ++dx) {
                const glm::uvec2 w = grid[std::size_t((4 + dy) * kSide + 4 + dx)];
                const glm::i64vec2 o(std::int64_t(w.x) - p.x, std::int64_t(w.y) - p.y);
                if (!(w.x & shared::GRID_TAG) && std::uint64_t(o.x * o.x + o.y * o.y) < limit2) near.emplace_back(o);
            }
        const glm::ivec2 unwritten(INT32_MIN);
        std::vector<glm::ivec2> gathered(most + 1, unwritten);  // nothing past `most` is written
        const std::uint32_t count =
            shared::window_gather_within<false>(&grid[4 * kSide + 4], kSide, wide, p, limit2, gathered.data(), most);
        REQUIRE(gathered[most] == unwritten);
        if (near.size() > most) {
            REQUIRE(count == most + 1);
        } else {
            gathered.resize(count);
            REQUIRE(gathered == near);
        }
        // The same for a cell's T test: the samples whose squared gap to the box [0, far] from the
        // middle cell's corner is below limit2, as offsets from the corner.
        std::vector<glm::ivec2> boxed;
        for (int dy = -wide; dy <= wide; ++dy)
            for (int dx = -wide; dx <= wide; ++dx) {
                const glm::uvec2 w = grid[std::size_t((4 + dy) * kSide + 4 + dx)];
                const glm::i64vec2 o(std::int64_t(w.x) - corner.x, std::int64_t(w.y) - corner.y);
                const std::int64_t gx = std::max<std::int64_t>({-o.x, o.x - far.x, 0});
                const std::int64_t gy = std::max<std::int64_t>({-o.y, o.y - far.y, 0});
                if (!(w.x & shared::GRID_TAG) && std::uint64_t(gx * gx + gy * gy) < limit2) boxed.emplace_back(o);
            }
        gathered.assign(shared::MAX_DISKS + 1, unwritten);
        const std::uint32_t in_box = shared::window_gather_within<true>(
            &grid[4 * kSide + 4], kSide, wide, corner, limit2, gathered.data(), shared::MAX_DISKS, far);
        gathered.resize(in_box);
        REQUIRE(gathered == boxed);
        expected[0].insert(expected[0].end(), expected[1].begin(), expected[1].end());
        std::vector<glm::ivec2> got(shared::MAX_CELL_SAMPLES);
        got.resize(shared::window_gather(&grid[4 * kSide + 4], kSide, reach, corner, int(side), limit2, got.data()));
        REQUIRE(got == expected[0]);
    }
    CHECK(found > 2000);
    CHECK(found < 18000);
    CHECK(covering > 2000);
    CHECK(covering < 18000);
#endif
}

TEST_CASE("predicates: the host's vectorised cover test of a cell's children drops what the scalar one does",
          "[predicates]") {
    using namespace shared;
#ifndef VRPD_HOST_AVX2
    SUCCEED("not x86-64: surviving_children keeps its scalar loop");
#else
    if (!host_has_avx2()) SUCCEED("no AVX2 here: surviving_children keeps its scalar loop");
    if (!host_has_avx2()) return;
    std::mt19937_64 rng(17);
    int dropped = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        // Small sides at the tied radii (pairs at exactly r occur), larger ones at random radii.
        const bool tied = trial % 2 == 0;
        const int side = tied ? 1 << (rng() % 3) : 1 << (4 + rng() % 12);
        Domain dom{};
        const std::uint64_t r2 = tied ? kTiedRadii2[rng() % std::size(kTiedRadii2)]
                                      : rng() % (std::uint64_t(4 * side) * std::uint64_t(4 * side));
        dom.radii = {r2, r2, RADII_ONE, 0};
        // Children of side `side` at a random place in the base cell (of side 4 side), the second
        // column and row sometimes clipped to a free boundary (hi1 = hi0, as surviving_children).
        const ivec2 at(int(rng() % 2) * 2 * side, int(rng() % 2) * 2 * side);
        ChildBoxes b;
        b.lo0 = at;
        b.hi0 = at + ivec2(side - 1);
        b.lo1 = rng() % 4 ? at + ivec2(side) : b.lo0;
        b.hi1 = b.lo1 == b.lo0 ? b.hi0 : at + ivec2(2 * side - 1);
        std::vector<ivec2> near(1 + rng() % MAX_CELL_SAMPLES);
        for (ivec2& o : near) o = ivec2(int(rng() % (12 * side)) - 4 * side, int(rng() % (12 * side)) - 4 * side);
        const uint start = 1u + uint(rng() % 15);
        uint scalar = start, corners = 0u;
        for (const ivec2& o : near) cover_children(dom, b, 4u, o, scalar, corners);
        dropped += scalar != start ? 1 : 0;
        INFO("trial " << trial << " side " << side << " r2 " << r2 << " samples " << near.size());
        REQUIRE(uncovered_children(b, near.data(), uint(near.size()), r2, start) == scalar);
    }
    CHECK(dropped > 2000);
    CHECK(dropped < 18000);
#endif
}

TEST_CASE("predicates: the host's vectorised dart counts are the scalar ones, for any number of cells and any lambda",
          "[predicates]") {
    using namespace shared;
#ifndef VRPD_HOST_AVX2
    SUCCEED("not x86-64: cell_dart_counts keeps its scalar loop");
#else
    if (!host_has_avx2()) SUCCEED("no AVX2 here: cell_dart_counts keeps its scalar loop");
    if (!host_has_avx2()) return;
    std::mt19937_64 rng(19);
    std::uint64_t darts = 0;
    uint most = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        // Lambda from 0.01 to 8 (a lane may need a dozen uniforms), corners anywhere below 2^31.
        const double lambda = 0.01 + 8.0 * double(rng() % 1000) / 1000.0;
        const uint exp_neg = uint(std::floor(std::exp(-lambda) * 4294967296.0));
        const uint key = uint(rng());
        std::vector<uvec2> corners(rng() % 40);  // tails of every length, and none
        for (uvec2& c : corners) c = uvec2(uint(rng() >> 33), uint(rng() >> 33));
        std::vector<uint> counts(corners.size() + 1, 0xDEADBEEFu);  // one past the end: left alone
        cell_dart_counts_avx2(key, corners.data(), uint(corners.size()), exp_neg, counts.data());
        INFO("trial " << trial << " lambda " << lambda << " cells " << corners.size());
        for (std::size_t k = 0; k < corners.size(); ++k) {
            REQUIRE(counts[k] == dart_count(cell_stream(key, corners[k]), exp_neg));
            darts += counts[k];
            most = std::max(most, counts[k]);
        }
        REQUIRE(counts.back() == 0xDEADBEEFu);
    }
    CHECK(darts > 100000);
    CHECK(most >= 12);
#endif
}
