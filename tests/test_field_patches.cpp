// A sizing field's patches (field/patches.h): quadtrees over the table cells at a kink, within
// the target, continuous across every leaf's edges, and within their budget.
#include <catch2/catch.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "field/table.h"
#include "vrpd/sizing.h"

using namespace vrpd;

namespace {

// Calls leaf(corner, bits) for each leaf of each patch of t: its corner in lattice units and its
// side's bits.
template <typename Leaf>
void each_patch_leaf(const detail::FieldTable& t, Leaf&& leaf) {
    struct Node {
        std::uint32_t split, bits;
        glm::uvec2 corner;
    };
    std::uint32_t q = 0;
    for (std::size_t w = 0; w < t.patched.size(); ++w)
        for (std::uint64_t word = t.patched[w]; word != 0; word &= word - 1, ++q) {
            const std::size_t c = w * 64 + std::size_t(std::countr_zero(word));
            std::vector<Node> stack{{q, t.cell_bits, glm::uvec2(c % t.cells_x, c / t.cells_x) << t.cell_bits}};
            while (!stack.empty()) {
                const Node n = stack.back();
                stack.pop_back();
                const std::uint32_t bits = n.bits - 1;
                for (std::uint32_t k = 0; k < 4; ++k) {
                    const glm::uvec2 corner = n.corner + glm::uvec2((k & 1) << bits, (k >> 1) << bits);
                    const int split = shared::field_child_split(t.view(), n.split, k);
                    if (split >= 0)
                        stack.push_back({std::uint32_t(split), bits, corner});
                    else
                        leaf(corner, bits);
                }
            }
        }
}

// The largest step of r between neighbouring lattice points across the edges of the leaves of
// t's patches (around a torus), at nine points along each edge, its ends (where a split's nodes
// that continuity moves sit) among them.
std::int64_t worst_leaf_step(const detail::FieldTable& t) {
    const bool periodic = t.lattice.periodic != 0;
    const std::int64_t ex = t.lattice.extent_x, ey = t.lattice.extent_y;
    std::int64_t worst = 0;
    each_patch_leaf(t, [&](glm::uvec2 corner, std::uint32_t bits) {
        const std::int64_t side = std::int64_t(1) << bits, x0 = corner.x, y0 = corner.y;
        for (std::int64_t k = 0; k <= 8; ++k) {
            const std::int64_t along = std::min(side - 1, k * (side / 8));
            const std::int64_t pairs[4][4] = {{x0, y0 + along, x0 - 1, y0 + along},
                                              {x0 + along, y0, x0 + along, y0 - 1},
                                              {x0 + side - 1, y0 + along, x0 + side, y0 + along},
                                              {x0 + along, y0 + side - 1, x0 + along, y0 + side}};
            for (const auto& q : pairs) {
                std::int64_t ox = q[2], oy = q[3];
                if (periodic) ox = (ox + ex) % ex, oy = (oy + ey) % ey;
                if (q[0] >= ex || q[1] >= ey || ox < 0 || oy < 0 || ox >= ex || oy >= ey) continue;
                const std::int64_t in = t.radius(glm::uvec2(q[0], q[1])), out = t.radius(glm::uvec2(ox, oy));
                worst = std::max(worst, std::abs(in - out));
            }
        }
    });
    return worst;
}

// Table t of s: no step across any leaf's edge beyond its slope and the rounding, and on one
// thread the same patches, error and L as on several.
void continuous_and_repeatable(const Sizing& s, const Box& box, const detail::FieldTable& t) {
    CHECK(worst_leaf_step(t) <= std::int64_t(std::ceil(t.lipschitz)) + 2);
    const detail::FieldTable one = detail::tabulate(s, box, 1);
    CHECK(one.splits == t.splits);
    CHECK(one.patched == t.patched);
    CHECK(one.tabulation_error == t.tabulation_error);
    CHECK(one.lipschitz == t.lipschitz);
}

}  // namespace

TEST_CASE("a kink: patched table cells bring the table within 0.1 % of its source, continuous, with its L", "[field]") {
    // Without patches this table is 0.40 % from the source at the kink x = 0.3, where a bilinear
    // cell cuts the corner; the waves along y get patches too, beside cells without.
    Sizing s;
    s.expression = "0.02 + 0.1*abs(x - 0.3) + 0.004*sin(40*y)";
    const Box box{1, 1, Boundary::Free};
    const detail::FieldTable t = detail::tabulate(s, box, 3);
    REQUIRE(t.patch_count > 0);
    CHECK(t.tabulation_error <= 0.00075);
    CHECK(t.lipschitz == Approx(std::hypot(0.1, 0.16)).epsilon(0.02));
    // Measured at random points of the box: the table's own claim, plus the lattice rounding.
    std::mt19937_64 rng(11);
    double worst = 0;
    for (int i = 0; i < 200000; ++i) {
        const glm::uvec2 p(std::uint32_t(rng() % t.lattice.extent_x), std::uint32_t(rng() % t.lattice.extent_y));
        const double x = p.x * t.quantum, y = p.y * t.quantum;
        const double source = 0.02 + 0.1 * std::abs(x - 0.3) + 0.004 * std::sin(40 * y);
        worst = std::max(worst, std::abs(t.radius(p) * t.quantum - source) / source);
    }
    CHECK(worst <= 0.001);
    // Across every edge of every leaf of every patch, r steps by no more than its slope and the
    // rounding: a split's node on an edge with a leaf of its size across lies on that leaf's edge.
    std::size_t levels = 0;
    each_patch_leaf(
        t, [&](glm::uvec2, std::uint32_t bits) { levels = std::max<std::size_t>(levels, t.cell_bits - bits); });
    CHECK(levels >= 3);
    continuous_and_repeatable(s, box, t);
}

TEST_CASE("two kinks whose leaves change level along their lines: within the target and the budget", "[field]") {
    // r, and with it the relative error, varies along each kink line, so the patches' leaves change
    // level along it; each change leaves a node moved for continuity and a leaf steeper than the
    // field, and splitting the coarser leaf only moves the change along the line. Fixed without
    // end, those slopes would take the line to its deepest level, past the budget at every target
    // (the table would stop at 0.37 %). Past two thirds of the budget the steeper leaves stay.
    Sizing s;
    s.expression = "0.002 + 0.05*abs(x - 0.5) + 0.05*abs(y - 0.3)";
    const Box box{1, 1, Boundary::Free};
    const detail::FieldTable t = detail::tabulate(s, box, 2);
    CHECK(t.kink_count == 0);
    REQUIRE(t.patch_count > 0);
    CHECK(t.tabulation_error <= 0.00075);
    // The kept slopes: steeper than the source's 0.05 sqrt(2), and measured.
    CHECK(t.lipschitz > 0.05 * std::sqrt(2.0));
    CHECK(t.lipschitz < 2 * 0.05 * std::sqrt(2.0));
    continuous_and_repeatable(s, box, t);
}

TEST_CASE("a cusp: the settling stops, and the error it reports holds", "[field]") {
    // sqrt(x)'s slope has no bound at the box's edge x = 0: there a leaf past the target after
    // continuity splits into another past it, one split a settling pass, each pass settling its
    // patches whole: to its end the chain would make over 250 000 splits. The passes stop at 32
    // times the budget's splits settled, and the leaves still past the target stay.
    Sizing s;
    s.expression = "0.001 + 0.004*sqrt(x)";
    const Box box{1, 1, Boundary::Free};
    const detail::FieldTable t = detail::tabulate(s, box, 2);
    REQUIRE(t.patch_count > 0);
    CHECK(t.splits.size() < 200000);
    CHECK(t.tabulation_error > 0.00075);
    CHECK(t.tabulation_error < 0.005);
    // The error reported is the table's, measured with its leaves as they stand: at random
    // lattice points, and along the cusp, within it and the lattice's rounding.
    std::mt19937_64 rng(5);
    double worst = 0;
    for (int i = 0; i < 200000; ++i) {
        const glm::uvec2 p(std::uint32_t(i % 4 == 0 ? rng() % 64 : rng() % t.lattice.extent_x),
                           std::uint32_t(rng() % t.lattice.extent_y));
        const double x = p.x * t.quantum, source = 0.001 + 0.004 * std::sqrt(x);
        worst = std::max(worst, std::abs(t.radius(p) * t.quantum - source) / source);
    }
    CHECK(worst <= t.tabulation_error + 0.0005);
    continuous_and_repeatable(s, box, t);
}

TEST_CASE("patches reach the least target their budget allows", "[field]") {
    // The rectified sine at 76 000 samples: its kinks' cells are kinked, and its troughs, where r
    // bends most, would take more than a split a sample to reach 0.075 %; within a budget of 8
    // words a sample the patches reach 0.212 % (the table alone: 0.72 %), which the run reports.
    Sizing s;
    s.expression = "0.015 + (0.0015 - 0.015)*abs(sin(8*pi*d))";
    s.table_budget = 8;
    const detail::FieldTable t = detail::tabulate(s, {1, 1, Boundary::Periodic});
    CHECK(t.kink_count > 0);
    CHECK(t.patch_count > 0);
    CHECK(t.splits.size() <= 80000);
    CHECK(t.tabulation_error > 0.00075);
    CHECK(t.tabulation_error < 0.003);
    // Continuous across the leaves' edges, around the torus too.
    CHECK(worst_leaf_step(t) <= std::int64_t(std::ceil(t.lipschitz)) + 2);
    // A larger budget (Sizing::table_budget, words a sample) brings it closer: within the 0.1 %
    // the run warns past at 32 words a sample (the default), and at 64 to the target, with about
    // four times the splits; past what it needs, it takes no more.
    s.table_budget = Sizing{}.table_budget;
    const detail::FieldTable closer = detail::tabulate(s, {1, 1, Boundary::Periodic});
    CHECK(closer.tabulation_error < 0.001);
    CHECK(closer.tabulation_error > 0.00075);
    s.table_budget = 64;
    const detail::FieldTable within = detail::tabulate(s, {1, 1, Boundary::Periodic});
    CHECK(within.tabulation_error <= 0.00075);
    CHECK(within.splits.size() > 3 * t.splits.size());
    CHECK(worst_leaf_step(within) <= std::int64_t(std::ceil(within.lipschitz)) + 2);
    s.table_budget = 128;
    CHECK(detail::tabulate(s, {1, 1, Boundary::Periodic}).splits == within.splits);
    for (double bad : {0.0, 0.5, 1025.0, std::nan("")}) {
        s.table_budget = bad;
        CHECK_THROWS_WITH(detail::tabulate(s, {1, 1, Boundary::Periodic}),
                          Catch::Contains("the table budget must be 1 to 1024 words a sample"));
    }
    s.table_budget = 8;
    // A field that does not wrap jumps across a torus's edge: no patch can follow a jump.
    s.expression = "0.02 + 0.1*abs(x - 0.3)";
    const detail::FieldTable jump = detail::tabulate(s, {1, 1, Boundary::Periodic});
    CHECK(jump.patch_count == 0);
    CHECK(jump.tabulation_error > 0.1);
}
