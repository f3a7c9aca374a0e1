// A sizing field's kinked cells (field/table.h): where one of the source's kinks (an abs, min or
// max, two a clamp) crosses a table cell, the cell is the least or greatest of its two branches'
// interpolants, so the table follows the kink as closely as it follows a smooth field.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "field/table.h"
#include "vrpd/sizing.h"

using namespace vrpd;

namespace {

// The largest step of r between neighbouring lattice points across the edges of t's kinked cells
// (around a torus), at 33 points along each edge and at the kink's crossing of it.
std::int64_t worst_kinked_step(const detail::FieldTable& t) {
    const bool periodic = t.lattice.periodic != 0;
    const std::int64_t ex = t.lattice.extent_x, ey = t.lattice.extent_y, side = std::int64_t(1) << t.cell_bits;
    std::int64_t worst = 0;
    auto step = [&](std::int64_t x, std::int64_t y, std::int64_t ox, std::int64_t oy) {
        if (periodic) ox = (ox + ex) % ex, oy = (oy + ey) % ey;
        if (x >= ex || y >= ey || ox < 0 || oy < 0 || ox >= ex || oy >= ey) return;
        const std::int64_t in = t.radius(glm::uvec2(x, y)), out = t.radius(glm::uvec2(ox, oy));
        worst = std::max(worst, std::abs(in - out));
    };
    for (std::uint32_t j = 0; j < t.cells_y; ++j)
        for (std::uint32_t i = 0; i < t.cells_x; ++i) {
            const int k = shared::field_kink(t.view(), i, j);
            if (k < 0) continue;
            const std::int64_t x0 = std::int64_t(i) * side, y0 = std::int64_t(j) * side;
            const glm::uvec4 a = shared::field_kink_branch(t.view(), std::uint32_t(k), 0),
                             b = shared::field_kink_branch(t.view(), std::uint32_t(k), 1);
            const double d[4] = {double(a.x) - b.x, double(a.y) - b.y, double(a.z) - b.z, double(a.w) - b.w};
            std::vector<double> along;
            for (int n = 0; n <= 32; ++n) along.push_back(n / 32.0);
            // Where the branches cross on the bottom and left edges.
            if ((d[0] < 0) != (d[1] < 0)) along.push_back(d[0] / (d[0] - d[1]));
            if ((d[0] < 0) != (d[2] < 0)) along.push_back(d[0] / (d[0] - d[2]));
            for (const double f : along) {
                const std::int64_t o = std::min(side - 1, std::int64_t(f * double(side)));
                step(x0, y0 + o, x0 - 1, y0 + o);
                step(x0 + o, y0, x0 + o, y0 - 1);
                step(x0 + side - 1, y0 + o, x0 + side, y0 + o);
                step(x0 + o, y0 + side - 1, x0 + o, y0 + side);
            }
        }
    return worst;
}

// The largest relative distance of the table from `source` at n random lattice points.
template <typename Source>
double measured_error(const detail::FieldTable& t, Source&& source, int n) {
    std::mt19937_64 rng(3);
    double worst = 0;
    for (int i = 0; i < n; ++i) {
        const glm::uvec2 p(std::uint32_t(rng() % t.lattice.extent_x), std::uint32_t(rng() % t.lattice.extent_y));
        const double v = source(p.x * t.quantum, p.y * t.quantum);
        worst = std::max(worst, std::abs(t.radius(p) * t.quantum - v) / v);
    }
    return worst;
}

// A kinked table t of s over box: within 0.1 % of the source at 100 000 random lattice points, no
// step across a kinked cell's edge beyond its slope and rounding, and the same table on one thread.
void check_kinked(const Sizing& s, const Box& box, const detail::FieldTable& t) {
    const SizingExpression source(s.expression);
    CHECK(measured_error(
              t, [&](double x, double y) { return source(x, y, box); }, 100000) <= 0.001);
    CHECK(worst_kinked_step(t) <= std::int64_t(std::ceil(t.lipschitz)) + 2);
    const detail::FieldTable one = detail::tabulate(s, box, 1);
    CHECK(one.kinks == t.kinks);
    CHECK(one.kinked == t.kinked);
    CHECK(one.nodes == t.nodes);
}

}  // namespace

TEST_CASE("kinked cells follow a kink: within the target without patches, continuous, with the branches' L",
          "[field]") {
    // A ridge (the greater of the branches) and a valley (the lesser), on a free box and a torus:
    // linear branches, which the cells take exactly, and curved ones.
    struct Case {
        const char* expression;
        Box box;
        std::uint32_t join;
        double lipschitz;
    };
    for (const Case& c : {Case{"0.01 + 0.05*abs(x - 0.3)", {1, 1, Boundary::Free}, shared::FIELD_KINK_MAX, 0.05},
                          Case{"0.05 - 0.04*abs(x - 0.3)", {1, 1, Boundary::Free}, shared::FIELD_KINK_MIN, 0.04},
                          Case{"0.02 + 0.01*abs(sin(2*pi*(x + y)))",
                               {1, 1, Boundary::Periodic},
                               shared::FIELD_KINK_MAX,
                               0.02 * std::numbers::pi * std::sqrt(2.0)}}) {
        INFO(c.expression);
        Sizing s;
        s.expression = c.expression;
        const detail::FieldTable t = detail::tabulate(s, c.box, 2);
        REQUIRE(t.kink_count > 0);
        CHECK(t.patch_count == 0);
        CHECK(t.kinks[shared::FIELD_KINK_WORDS - 1] == c.join);
        CHECK(t.tabulation_error <= 0.00075);
        CHECK(t.lipschitz == Approx(c.lipschitz).epsilon(0.02));
        check_kinked(s, c.box, t);
    }
    // A second kink (past the box here) leaves the cells the first crosses kinked.
    Sizing two;
    two.expression = "0.01 + 0.05*abs(x - 0.3) + 0.0001*abs(y - 2)";
    const detail::FieldTable both = detail::tabulate(two, {1, 1, Boundary::Free}, 2);
    CHECK(both.kink_count > 0);
    CHECK(both.patch_count == 0);
    CHECK(both.tabulation_error <= 0.00075);
    // Where two kinks cross, the cells around the crossing take both: without kinked cells (plain
    // nodes, patched along the kinks) the same ridge takes thousands of splits.
    two.expression = "0.01 + 0.05*abs(x - 0.3) + 0.0001*abs(y - 0.5)";
    const detail::FieldTable patched = detail::tabulate(two, {1, 1, Boundary::Free}, 2);
    CHECK(patched.kink_count == 0);
    CHECK(patched.splits.size() > 500);
}

TEST_CASE("kinked cells follow each of several kinks that do not cross", "[field]") {
    // A triangle wave (nested abs: kinks at x = 0.25, 0.5 and 0.75) and a clamped ramp (a clamp's
    // two kinks), whose branches are linear, so that the kinked cells take them exactly, and a
    // disk's radius capped and floored (two circles): kinked cells along each kink, no patches.
    struct Case {
        const char* expression;
        Box box;
        double error;  // the most the table may stray by its measure (at random points its
                       // rounding to lattice units adds about 1e-4)
    };
    for (const Case& c : {Case{"0.003 + 0.01*abs(abs(x - 0.5) - 0.25)", {1, 1, Boundary::Free}, 1e-9},
                          Case{"clamp(0.002 + 0.03*x, 0.006, 0.02)", {1, 1, Boundary::Free}, 1e-9},
                          Case{"max(0.003, min(0.02, 0.03*d))", {1, 1, Boundary::Free}, 0.00075}}) {
        INFO(c.expression);
        Sizing s;
        s.expression = c.expression;
        const detail::FieldTable t = detail::tabulate(s, c.box, 2);
        CHECK(t.kink_count > 0);
        CHECK(t.patch_count == 0);
        CHECK(t.tabulation_error <= c.error);
        check_kinked(s, c.box, t);
    }
}

TEST_CASE("a table takes no kinked cells where the branches cannot make it", "[field]") {
    Sizing s;
    // One branch is not a radius beside the kink (sqrt of a negative number): the cells there
    // are no join of the branches, so the table patches the kink instead.
    s.expression = "0.01 + 0.05*sqrt(abs(x - 0.3))";
    const detail::FieldTable root = detail::tabulate(s, {1, 1, Boundary::Free}, 2);
    CHECK(root.kink_count == 0);
    CHECK(root.patch_count > 0);
    // Patches beside the kink (the waves along y) would meet the kinked cells, whose edges cannot
    // follow a patch's finer leaves: the table patches the kink too.
    s.expression = "0.02 + 0.1*abs(x - 0.3) + 0.004*sin(40*y)";
    const detail::FieldTable waves = detail::tabulate(s, {1, 1, Boundary::Free}, 2);
    CHECK(waves.kink_count == 0);
    CHECK(waves.patch_count > 0);
    CHECK(waves.tabulation_error <= 0.00075);
    // Branches that bend within a kinked cell past the target (the other branch of
    // sqrt(|x - 0.5| + 0.01) meets its own root 0.01 past the kink), which kinked cells cannot
    // refine: 0.129 % with them, within the target patched without them.
    s.expression = "0.005 + 0.01*sqrt(abs(x - 0.5) + 0.01)";
    const detail::FieldTable bent = detail::tabulate(s, {1, 1, Boundary::Free}, 2);
    CHECK(bent.kink_count == 0);
    CHECK(bent.patch_count > 0);
    CHECK(bent.tabulation_error <= 0.00075);
    // --lipschitz tabulates the limited nodes alone.
    s.expression = "0.01 + 0.05*abs(x - 0.3)";
    s.lipschitz = 0.04;
    CHECK(detail::tabulate(s, {1, 1, Boundary::Free}, 2).kink_count == 0);
}
