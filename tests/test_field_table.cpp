// The tabulated sizing field (field/table.h): the fixed-point interpolant, a ramp's table within
// its tolerance and with its L, and the bounds of r over blocks the sampler's tests rely on.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <tuple>

#include "cpu/thread_pool.h"
#include "field/quadtree.h"
#include "field/table.h"
#include "field_table_probe.h"
#include "field_tree_probe.h"
#include "probe_support.h"
#include "vrpd/sizing.h"

using namespace vrpd;

using test::DeviceCopies;
using test::run_probe;

TEST_CASE("field_interpolate is the floor of the exact bilinear interpolant", "[field]") {
    std::mt19937_64 rng(7);
    for (int i = 0; i < 20000; ++i) {
        const std::uint32_t bits = std::uint32_t(rng() % (shared::MAX_FIELD_CELL_BITS + 1));
        const std::uint64_t c = std::uint64_t(1) << bits;
        const glm::uvec4 v{std::uint32_t(rng()), std::uint32_t(rng()), std::uint32_t(rng()), std::uint32_t(rng())};
        const glm::uvec2 f{std::uint32_t(rng() % c), std::uint32_t(rng() % c)};
        const unsigned __int128 s = (unsigned __int128)v.x * (c - f.x) * (c - f.y) +
                                    (unsigned __int128)v.y * f.x * (c - f.y) +
                                    (unsigned __int128)v.z * (c - f.x) * f.y + (unsigned __int128)v.w * f.x * f.y;
        const std::uint32_t r = shared::field_interpolate(v, f, bits);
        REQUIRE(r == std::uint32_t(s / ((unsigned __int128)c * c)));
        REQUIRE(r >= std::min({v.x, v.y, v.z, v.w}));
        REQUIRE(r <= std::max({v.x, v.y, v.z, v.w}));
    }
}

TEST_CASE("a tabulated ramp is within 0.1 % of its source, with its L measured", "[field]") {
    Sizing s;
    s.expression = "0.001 + 0.3*x";
    const Box box{1, 1, Boundary::Free};
    const SizingField field(s, box);
    const FieldStats f = field.stats();
    CHECK(f.tabulation_error <= 0.001);
    CHECK(f.r_min == Approx(0.001).epsilon(1e-3));
    CHECK(f.r_max == Approx(0.301).epsilon(1e-3));
    CHECK(f.lipschitz == Approx(0.3).epsilon(1e-3));
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 2000; ++i) {
        const glm::dvec2 p(u(rng), u(rng));
        REQUIRE(field(p) == Approx(0.001 + 0.3 * p.x).epsilon(1e-3));
    }
}

TEST_CASE("the tiles are those with the fewest leaves, by an estimate that follows the quadtree", "[field]") {
    // A torus's rectified sine (tiles of side 1/118 give 13 % fewer leaves than the largest,
    // 1/67, and a coarser table), a torus of 2 x 1, a free ramp over 300x and a smooth wave. The survey's 256 cells a
    // side resolve each but the ramp near x = 0 (r 0.001 there, a cell 0.0039 wide), where it
    // sees fewer leaves than the quadtree holds: `most` is the leaves' largest ratio to it.
    struct Case {
        const char* expression;
        Box box;
        double most;
    };
    const std::array cases{Case{"0.015 + (0.0015 - 0.015)*abs(sin(8*pi*d))", {1, 1, Boundary::Periodic}, 1.05},
                           Case{"0.03 + (0.006 - 0.03)*abs(sin(4*pi*d))", {2, 1, Boundary::Periodic}, 1.05},
                           Case{"0.001 + 0.3*x", {1, 1, Boundary::Free}, 1.5},
                           Case{"0.006 + 0.003*sin(2*pi*x)*cos(2*pi*y)", {1, 1, Boundary::Periodic}, 1.05}};
    detail::ThreadPool pool(2);
    for (const Case& c : cases) {
        INFO(c.expression);
        Sizing s;
        s.expression = c.expression;
        const detail::FieldTable t = detail::tabulate(s, c.box, 2);
        // r at the centres of the survey's 256 x 256 cells, as tabulate() reads it.
        const detail::FieldSource f = detail::field_source(s, c.box);
        constexpr std::uint32_t n = 256;
        std::vector<double> xs(n * n), ys(n * n), survey(n * n);
        for (std::uint32_t k = 0; k < n * n; ++k)
            xs[k] = c.box.width * (k % n + 0.5) / n, ys[k] = c.box.height * (k / n + 0.5) / n;
        f(xs.data(), ys.data(), survey.data(), survey.size());
        const detail::LeafDensity density(survey, n, c.box);
        double hi = 0;
        for (double v : survey) hi = std::max(hi, v);
        // The estimate is the count of its comment, point by point, to its bins (1/1024 octave).
        const bool periodic = c.box.boundary == Boundary::Periodic;
        auto at = [&](std::int64_t i, std::int64_t j) {
            auto wrap = [&](std::int64_t v) { return periodic ? (v + n) % n : std::clamp<std::int64_t>(v, 0, n - 1); };
            return survey[std::size_t(wrap(j)) * n + std::size_t(wrap(i))];
        };
        for (const double tile : {hi, hi * 0.8, hi * 0.6}) {
            double sum = 0;
            for (std::int64_t k = 0; k < n * n; ++k) {
                const std::int64_t i = k % n, j = k / n;
                const double g = std::hypot((at(i + 1, j) - at(i - 1, j)) * n / (2 * c.box.width),
                                            (at(i, j + 1) - at(i, j - 1)) * n / (2 * c.box.height));
                double side = tile;
                while (side * (std::sqrt(2.0) + 2 / M_PI * g) >= at(i, j)) side /= 2;
                sum += 1 / (side * side);
            }
            CHECK(density(tile) == Approx(sum / double(survey.size())).epsilon(0.005));
        }
        // The chosen side takes the fewest bytes of the sides from hi / 2 to hi (on a torus, of
        // its tilings: n x n tiles on the unit torus, 2n x n on the 2 x 1 one), to the candidates'
        // spacing (64 an octave: the leaves' estimate changes by up to 4^(1/64)).
        const double side = t.quantum * double(std::uint64_t(1) << t.tile_bits);
        CHECK(side <= hi * (1 + 1e-12));
        CHECK(side > hi / 2);
        const double lo = t.box_lo * t.quantum;  // r's least, as the table's own survey found it
        double least = INFINITY;
        for (double k = std::ceil(c.box.height / hi); k < 2 * std::ceil(c.box.height / hi); ++k)
            least = std::min(least, detail::tile_bytes(density, c.box.height / k, lo));
        if (!periodic)
            for (int j = 0; j < 1000; ++j)
                least = std::min(least, detail::tile_bytes(density, hi * std::exp2(-j / 1000.0), lo));
        CHECK(detail::tile_bytes(density, side, lo) <= least * 1.022);
        if (c.expression == cases[0].expression) CHECK(density(side) < 0.9 * density(1.0 / 67));
        // And the quadtree's leaves follow the estimate.
        const detail::FieldQuadtree tree(t, UINT32_MAX, pool);
        const double leaves = double(tree.leaves()) / (c.box.width * c.box.height);
        CHECK(leaves >= density(side) * 0.98);
        CHECK(leaves <= density(side) * c.most);
    }
}

TEST_CASE("the table and its bounds do not depend on the tabulation's thread count", "[field]") {
    Sizing s;
    s.expression = "0.004 + 0.03*abs(sin(5*pi*d))";
    s.lipschitz = 0.4;  // the Lipschitz limit runs on the threads too
    const Box box{1, 1, Boundary::Periodic};
    const detail::FieldTable one = detail::tabulate(s, box, 1), three = detail::tabulate(s, box, 3);
    CHECK(one.nodes.size() > 10000);
    CHECK(one.nodes == three.nodes);
    CHECK(one.pyramid_lo == three.pyramid_lo);
    CHECK(one.pyramid_hi == three.pyramid_hi);
    CHECK(one.pyramid_start == three.pyramid_start);
    CHECK(one.tabulation_error == three.tabulation_error);
    CHECK(one.lipschitz == three.lipschitz);
}

TEST_CASE(
    "min_over and max_over (and extremes_over, both) bound r over a block, exactly inside one table cell, and "
    "children_min is min_over of each child, on a table and on it scaled",
    "[field]") {
    // A smooth field; one with a kink, whose cells along it are kinked (the greater of two
    // branches), and one whose valley's kinked cells are the lesser; and one with two kinks, whose
    // cells along them hold patches. Half the blocks start in a table cell at x = 0.3. Each also
    // scaled by 2.5 (a hierarchy's level), whose r is within 2.5 + 2 lattice units of 2.5 times
    // the table's.
    Sizing smooth, kink, valley, kinks;
    smooth.expression = "0.02 + 0.01*sin(9*x)*cos(7*y)";
    kink.expression = "0.01 + 0.05*abs(x - 0.3)";
    valley.expression = "0.05 - 0.04*abs(x - 0.3)";
    kinks.expression = "0.01 + 0.05*abs(x - 0.3) + 0.02*abs(y - 0.6)";
    detail::ThreadPool pool(2);
    const Box torus{1, 1, Boundary::Periodic}, free{1, 1, Boundary::Free};
    for (const auto& [s, box, scale] :
         {std::tuple{smooth, torus, 1.0}, std::tuple{smooth, torus, 2.5}, std::tuple{kink, free, 1.0},
          std::tuple{kink, free, 2.5}, std::tuple{valley, free, 1.0}, std::tuple{kinks, free, 1.0},
          std::tuple{kinks, free, 2.5}}) {
        INFO(s.expression << " times " << scale);
        const detail::FieldTable base = detail::tabulate(s, box);
        const detail::FieldTable t = scale == 1 ? base : detail::scaled(base, scale, pool);
        REQUIRE((t.patch_count > 0) == (s.expression == kinks.expression));
        REQUIRE((t.kink_count > 0) == (s.expression == kink.expression || s.expression == valley.expression));
        if (t.kink_count > 0)
            CHECK(t.kinks[shared::FIELD_KINK_WORDS - 1] ==
                  (s.expression == kink.expression ? shared::FIELD_KINK_MAX : shared::FIELD_KINK_MIN));
        CHECK(t.lipschitz == Approx(scale * base.lipschitz).epsilon(0.01));
        std::mt19937_64 rng(5);
        for (int i = 0; i < 3000; ++i) {
            const std::uint32_t side = 1u << (rng() % 20);
            glm::uvec2 a(std::uint32_t(rng() % (t.lattice.extent_x - side)),
                         std::uint32_t(rng() % (t.lattice.extent_y - side)));
            if (s.expression != smooth.expression && i % 2 == 0) {
                // Into the table cell at x = 0.3, at a random row.
                a.x = std::min(std::uint32_t(0.3 / t.quantum) - std::uint32_t(rng() % side), t.lattice.extent_x - side);
            }
            const glm::uvec2 b(a.x + side - 1, a.y + side - 1);
            const std::uint32_t lo = t.min_over(a, b), hi = t.max_over(a, b);
            REQUIRE(t.extremes_over(a, b) == std::pair{lo, hi});
            std::uint32_t seen_lo = UINT32_MAX, seen_hi = 0;
            for (int k = 0; k < 64; ++k) {
                const glm::uvec2 p(a.x + std::uint32_t(rng() % side), a.y + std::uint32_t(rng() % side));
                seen_lo = std::min(seen_lo, t.radius(p));
                seen_hi = std::max(seen_hi, t.radius(p));
            }
            for (glm::uvec2 p : {a, b, glm::uvec2(a.x, b.y), glm::uvec2(b.x, a.y)}) {
                seen_lo = std::min(seen_lo, t.radius(p));
                seen_hi = std::max(seen_hi, t.radius(p));
                REQUIRE(std::abs(double(t.radius(p)) - scale * base.radius(p)) <= scale + 2);
            }
            REQUIRE(lo <= seen_lo);
            REQUIRE(hi >= seen_hi);
            // Inside one table cell, or one leaf of its patch, the interpolant is bilinear: its
            // extremes are at the corners. A kinked cell's join of two is exact on its own side:
            // the least of a min, the greatest of a max.
            const glm::uvec2 cell = a >> t.cell_bits;
            glm::uvec4 v = t.cell_nodes(cell.x, cell.y);
            glm::uvec2 f = a & glm::uvec2((1u << t.cell_bits) - 1);
            std::uint32_t bits = t.cell_bits;
            shared::field_descend(t.view(), shared::field_patch(t.view(), cell.x, cell.y), v, f, bits);
            if ((a.x >> t.cell_bits) == (b.x >> t.cell_bits) && (a.y >> t.cell_bits) == (b.y >> t.cell_bits) &&
                (a.x >> bits) == (b.x >> bits) && (a.y >> bits) == (b.y >> bits)) {
                const int k = shared::field_kink(t.view(), cell.x, cell.y);
                const bool least =
                    k < 0 || t.kinks[std::size_t(k) * shared::FIELD_KINK_WORDS + 8] == shared::FIELD_KINK_MIN;
                if (least) REQUIRE(lo == seen_lo);
                if (k < 0 || !least) REQUIRE(hi == seen_hi);
            }
            // children_min: min_over of each child of the block split at its middle (or, cut short
            // by the lattice's edge, with no second part along an axis).
            if (side < 2) continue;
            const glm::uvec2 m = a + glm::uvec2(side / 2);
            const glm::uvec2 cut(rng() % 4 == 0 ? m.x - 1 : b.x,
                                 rng() % 4 == 0 ? m.y - 1 : b.y);  // the block's far corner
            const glm::uvec2 e = glm::min(m - glm::uvec2(1), cut);
            std::uint32_t open = 0;
            for (std::uint32_t k = 0; k < 4; ++k)
                if (((k & 1) == 0 || m.x <= cut.x) && ((k >> 1) == 0 || m.y <= cut.y)) open |= 1u << k;
            const std::array<std::uint32_t, 4> least = t.children_min(a, e, m, cut, open);
            for (std::uint32_t k = 0; k < 4; ++k)
                if (open >> k & 1)
                    REQUIRE(least[k] == t.min_over({(k & 1) ? m.x : a.x, (k >> 1) ? m.y : a.y},
                                                   {(k & 1) ? cut.x : e.x, (k >> 1) ? cut.y : e.y}));
        }
    }
}

TEST_CASE("a table copied, moved or assigned views its own arrays", "[field]") {
    // The lookups read the table through its view: each copy must point into its own vectors,
    // and a table moved from into its emptied ones, or a copy would read freed memory.
    Sizing s;
    // Kinked cells along x = 0.3 and patches at the cone's tip, d = 0: every array is in use.
    s.expression = "0.02 + 0.1*abs(x - 0.3) + 0.05*d";
    const detail::FieldTable original = detail::tabulate(s, {1, 1, Boundary::Free});
    REQUIRE(original.patch_count > 0);
    REQUIRE(original.kink_count > 0);
    auto owns = [](const detail::FieldTable& t) {
        const shared::FieldTableView& v = t.view();
        return v.nodes.value == t.nodes.data() && v.patched.value == t.patched.data() &&
               v.kinked.value == t.kinked.data() && v.kink_rank.value == t.kink_rank.data() &&
               v.kinks.value == t.kinks.data() && v.kink_count == t.kink_count &&
               v.patch_rank.value == t.patch_rank.data() &&
               v.splits.value == reinterpret_cast<const std::uint32_t*>(t.splits.data()) &&
               v.pyramid_lo.value == t.pyramid_lo.data() && v.pyramid_hi.value == t.pyramid_hi.data() &&
               v.pyramid_start.value == t.pyramid_start.data() && v.patch_count == t.patch_count &&
               v.cells_x == t.cells_x && v.cell_bits == t.cell_bits;
    };
    const glm::uvec2 p(std::uint32_t(0.3 / original.quantum), 12345);
    const std::uint32_t r = original.radius(p);
    detail::FieldTable copy = original;
    CHECK(owns(copy));
    detail::FieldTable moved = std::move(copy);
    CHECK(owns(moved));
    CHECK(owns(copy));
    detail::FieldTable assigned;
    assigned = moved;
    CHECK(owns(assigned));
    detail::FieldTable move_assigned;
    move_assigned = std::move(assigned);
    CHECK(owns(move_assigned));
    CHECK(owns(assigned));
    CHECK(move_assigned.radius(p) == r);
    CHECK(moved.radius(p) == r);
}

TEST_CASE("a leaf search meets exactly the leaves that meet its square, read as a window or by descent", "[field]") {
    // Tiles whose leaves are all of one side are read as a window, the others by descent: on a
    // torus and on a free box (whose edge tiles have blocks outside the lattice), each search
    // must meet every leaf that meets its square, each once, and near_samples those of them with
    // a sample. The square is checked against each leaf's block and its torus images.
    detail::ThreadPool pool(2);
    for (const Box& box : {Box{1, 1, Boundary::Periodic}, Box{1.3, 1, Boundary::Free}}) {
        Sizing s;
        s.expression = "0.0045 + (0.0015 - 0.0045)*abs(sin(5*pi*d))";
        const detail::FieldTable t = detail::tabulate(s, box);
        detail::FieldQuadtree tree(t, 1u << 26, pool);
        INFO((box.boundary == Boundary::Periodic ? "periodic" : "free"));
        REQUIRE(tree.flat_tiles() > 0);
        REQUIRE(tree.flat_tiles() < tree.tiles());
        std::vector<std::pair<glm::uvec2, std::uint32_t>> blocks(tree.leaves());
        tree.each_leaf([&](std::uint32_t leaf, glm::uvec2 corner, std::uint32_t bits) {
            blocks[leaf] = {corner, bits};
        });
        std::mt19937_64 rng(9);
        for (std::uint32_t leaf = 0; leaf < tree.leaves(); leaf += 1 + std::uint32_t(rng() % 5))
            tree.set_sample(leaf, blocks[leaf].first, leaf);
        const bool periodic = box.boundary == Boundary::Periodic;
        auto meets = [&](std::int64_t c, std::int64_t side, std::int64_t lo, std::int64_t hi, std::int64_t extent) {
            for (const std::int64_t shift : {std::int64_t(0), extent, -extent})
                if ((shift == 0 || periodic) && c + shift <= hi && c + shift + side - 1 >= lo) return true;
            return false;
        };
        for (int q = 0; q < 150; ++q) {
            const glm::uvec2 p(std::uint32_t(rng() % t.lattice.extent_x), std::uint32_t(rng() % t.lattice.extent_y));
            const std::int64_t reach = std::int64_t(rng() % (std::uint64_t(t.r_hi) * 3));
            std::vector<std::uint32_t> all, with_sample, want_all, want_sample;
            tree.near(p, p, std::uint64_t(reach), [&](std::uint32_t leaf) { return all.push_back(leaf), false; });
            tree.near_samples(p, p, std::uint64_t(reach),
                              [&](std::uint32_t leaf) { return with_sample.push_back(leaf), false; });
            for (std::uint32_t leaf = 0; leaf < tree.leaves(); ++leaf) {
                const auto [c, bits] = blocks[leaf];
                const std::int64_t side = std::int64_t(1) << bits;
                if (!meets(c.x, side, p.x - reach, p.x + reach, t.lattice.extent_x) ||
                    !meets(c.y, side, p.y - reach, p.y + reach, t.lattice.extent_y))
                    continue;
                want_all.push_back(leaf);
                if (tree.sample(leaf) != detail::FieldQuadtree::kNone) want_sample.push_back(leaf);
            }
            std::sort(all.begin(), all.end());
            std::sort(with_sample.begin(), with_sample.end());
            INFO("query " << q << " at (" << p.x << ", " << p.y << "), reach " << reach);
            REQUIRE(all == want_all);
            REQUIRE(with_sample == want_sample);
        }
    }
}

TEST_CASE("the device reads a table as the host does: r at points and its bounds over blocks", "[field][gpu]") {
    // The probe kernel runs shared/field_table.h's lookups on each block; the host's FieldTable
    // answers from the same header compiled as C++. A smooth field, one with kinked cells along a
    // kink and patches at a cone's tip, and that one scaled (a hierarchy's level); blocks from one
    // lattice point to most of the box, a third of them starting in the kink's cells.
    Sizing smooth, kink;
    smooth.expression = "0.02 + 0.01*sin(9*x)*cos(7*y)";
    kink.expression = "0.02 + 0.1*abs(x - 0.3) + 0.05*d";
    detail::ThreadPool pool(2);
    detail::VulkanContext ctx("");
    constexpr std::uint32_t kResults = 6;  // PROBE_RESULTS of field_table_probe.comp
    detail::Kernel probe(ctx, "field_table_probe", {spirv_field_table_probe, std::size(spirv_field_table_probe)}, 128,
                         64);
    for (const auto& [s, box, scale] :
         {std::tuple{smooth, Box{1, 1, Boundary::Periodic}, 1.0}, std::tuple{kink, Box{1, 0.8, Boundary::Free}, 1.0},
          std::tuple{kink, Box{1, 0.8, Boundary::Free}, 2.5}}) {
        const detail::FieldTable base = detail::tabulate(s, box);
        const detail::FieldTable t = scale == 1 ? base : detail::scaled(base, scale, pool);
        INFO(s.expression << " times " << scale);
        REQUIRE((t.patch_count == 0) == (s.expression == smooth.expression));
        REQUIRE((t.kink_count == 0) == (s.expression == smooth.expression));
        DeviceCopies upload{ctx, {}};
        auto words = [&](const std::vector<std::uint32_t>& v) { return upload(v.data(), v.size() * 4); };
        struct {
            std::uint32_t cell_bits, cells_x, cells_y, patch_count;
            std::uint64_t nodes, patched, patch_rank, splits, pyramid_lo, pyramid_hi, pyramid_start;
            std::uint32_t kink_count, kink_pad;
            std::uint64_t kinked, kink_rank, kinks;
            std::uint64_t blocks, results;
            std::uint32_t count;
        } push{};
        static_assert(offsetof(decltype(push), nodes) == 16 && offsetof(decltype(push), kinked) == 80 &&
                      offsetof(decltype(push), count) == 120 && sizeof(push) <= 128);
        const shared::FieldTableView v = t.view();
        push.cell_bits = v.cell_bits;
        push.cells_x = v.cells_x;
        push.cells_y = v.cells_y;
        push.patch_count = v.patch_count;
        push.nodes = words(t.nodes);
        push.patched = upload(t.patched.data(), t.patched.size() * 8);
        push.patch_rank = words(t.patch_rank);
        push.splits = upload(t.splits.data(), t.splits.size() * sizeof(detail::FieldTable::Split));
        push.pyramid_lo = words(t.pyramid_lo);
        push.pyramid_hi = words(t.pyramid_hi);
        push.pyramid_start = words(t.pyramid_start);
        push.kink_count = v.kink_count;
        push.kinked = upload(t.kinked.data(), t.kinked.size() * 8);
        push.kink_rank = words(t.kink_rank);
        push.kinks = words(t.kinks);
        std::mt19937_64 rng(11);
        std::vector<glm::uvec4> blocks;
        for (int i = 0; i < 6000; ++i) {
            const std::uint32_t side = 1u + std::uint32_t(rng() % (std::uint64_t(1) << (rng() % 29)));
            const glm::uvec2 w(std::min(side, t.lattice.extent_x), std::min(side, t.lattice.extent_y));
            glm::uvec2 a(std::uint32_t(rng() % (t.lattice.extent_x - w.x + 1)),
                         std::uint32_t(rng() % (t.lattice.extent_y - w.y + 1)));
            if (t.kink_count > 0 && i % 3 == 0)
                a.x = std::min(std::uint32_t(0.3 / t.quantum) - std::uint32_t(rng() % w.x), t.lattice.extent_x - w.x);
            blocks.emplace_back(a, a + w - glm::uvec2(1));
        }
        push.blocks = upload(blocks.data(), blocks.size() * sizeof(glm::uvec4));
        detail::Buffer out(ctx, blocks.size() * kResults * 4, true);
        push.results = out.address();
        push.count = std::uint32_t(blocks.size());
        run_probe(ctx, probe, &push, blocks.size());
        const auto* got = static_cast<const std::uint32_t*>(out.mapped());
        std::size_t kinked = 0, one_cell = 0;
        for (std::size_t i = 0; i < blocks.size(); ++i) {
            const glm::uvec2 a(blocks[i].x, blocks[i].y), b(blocks[i].z, blocks[i].w);
            INFO("block (" << a.x << ", " << a.y << ") to (" << b.x << ", " << b.y << ")");
            const auto [lo, hi] = t.extremes_over(a, b);
            const std::array<std::uint32_t, kResults> host{t.radius(a),      t.radius(b), t.min_over(a, b),
                                                           t.max_over(a, b), lo,          hi};
            for (std::uint32_t k = 0; k < kResults; ++k) REQUIRE(got[i * kResults + k] == host[k]);
            kinked += t.kink(a.x >> t.cell_bits, a.y >> t.cell_bits);
            one_cell += (a.x >> t.cell_bits) == (b.x >> t.cell_bits) && (a.y >> t.cell_bits) == (b.y >> t.cell_bits);
        }
        // Both kinds of block, and on the kinked tables blocks in kinked cells, were asked.
        CHECK(one_cell > blocks.size() / 10);
        CHECK(blocks.size() - one_cell > blocks.size() / 10);
        if (t.kink_count > 0) CHECK(kinked > blocks.size() / 8);
    }
}

TEST_CASE("the device descends a field's leaf tree as the host does", "[field][gpu]") {
    // The probe kernel runs shared/field_tree.h's descent for random lattice points of a tree
    // whose leaves span several depths; each leaf's index and side must be the host's.
    Sizing s;
    s.expression = "0.002 + 0.05*abs(sin(6*x))*y";
    const detail::FieldTable t = detail::tabulate(s, {1.5, 1, Boundary::Free});
    detail::ThreadPool pool(2);
    const detail::FieldQuadtree tree(t, 1u << 26, pool);
    detail::VulkanContext ctx("");
    detail::Kernel probe(ctx, "field_tree_probe", {spirv_field_tree_probe, std::size(spirv_field_tree_probe)}, 56, 64);
    const shared::FieldTreeView v = tree.view();
    DeviceCopies upload{ctx, {}};
    std::mt19937_64 rng(3);
    std::vector<glm::uvec2> points(20000);
    for (glm::uvec2& p : points)
        p = {std::uint32_t(rng() % t.lattice.extent_x), std::uint32_t(rng() % t.lattice.extent_y)};
    struct {
        std::uint32_t tile_bits, tiles_x, tiles_y;
        std::uint64_t roots, nodes, points, leaves;
        std::uint32_t count;
    } push{v.tile_bits,
           v.tiles_x,
           v.tiles_y,
           upload(tree.root_words().data(), tree.root_words().size_bytes()),
           upload(tree.node_words().data(), tree.node_words().size_bytes()),
           upload(points.data(), points.size() * 8),
           0,
           std::uint32_t(points.size())};
    static_assert(offsetof(decltype(push), roots) == 16 && offsetof(decltype(push), count) == 48);
    detail::Buffer out(ctx, points.size() * 8, true);
    push.leaves = out.address();
    run_probe(ctx, probe, &push, points.size());
    const auto* got = static_cast<const glm::uvec2*>(out.mapped());
    std::uint32_t least = UINT32_MAX, most = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const detail::FieldQuadtree::Leaf leaf = tree.leaf_at(points[i]);
        INFO("point (" << points[i].x << ", " << points[i].y << ")");
        REQUIRE(leaf.holds(points[i]));
        REQUIRE(got[i] == glm::uvec2(leaf.index, leaf.bits));
        least = std::min(least, leaf.bits);
        most = std::max(most, leaf.bits);
    }
    CHECK(most >= least + 3);  // leaves of four sides or more were met
}
