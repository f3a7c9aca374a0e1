// The device's leaf search (shared/field_search.h) against the host's (field/quadtree.h): compiled
// as C++ and run as a test kernel, it must meet the leaves the host's search meets, as many times.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "cpu/thread_pool.h"
#include "field/quadtree.h"
#include "field/table.h"
#include "field_search_probe.h"
#include "probe_support.h"
#include "shared/darts.h"
#include "shared/field_run.h"
#include "shared/field_search.h"
#include "vrpd/sizing.h"

using namespace vrpd;

namespace {

// A search as the probe kernel takes it: the block [a, b], its reach and the flag it needs.
struct Query {
    glm::uvec2 a, b;
    std::uint32_t reach, need;
};
static_assert(sizeof(Query) == 24);

// A tree whose tiles are partly flat (read as windows by the host) and partly mixed, with samples
// in about a third of its leaves and fresh marks on a third of those.
struct Forest {
    detail::FieldTable table;
    detail::ThreadPool pool{2};
    detail::FieldQuadtree tree;
    explicit Forest(const Box& box) : table(tabulate(box)), tree(table, 1u << 26, pool) {
        REQUIRE(tree.flat_tiles() > 0);
        REQUIRE(tree.flat_tiles() < tree.tiles());
        std::vector<glm::uvec2> corners(tree.leaves());
        tree.each_leaf([&](std::uint32_t leaf, glm::uvec2 corner, std::uint32_t) { corners[leaf] = corner; });
        std::mt19937_64 rng(5);
        for (std::uint32_t leaf = 0; leaf < tree.leaves(); leaf += 1 + std::uint32_t(rng() % 5)) {
            tree.set_sample(leaf, corners[leaf], leaf);
            if (rng() % 3 != 0) tree.settle(corners[leaf]);
        }
    }
    static detail::FieldTable tabulate(const Box& box) {
        Sizing s;
        s.expression = "0.0045 + (0.0015 - 0.0045)*abs(sin(5*pi*d))";
        return detail::tabulate(s, box);
    }
    // Random blocks, from a point to a few of the largest leaves, with reaches up to three times
    // the field's largest r, a tenth of them past the whole box; each asked for all three flags.
    std::vector<Query> queries(std::size_t n, std::uint64_t seed) const {
        const shared::Lattice& l = table.lattice;
        std::mt19937_64 rng(seed);
        std::vector<Query> out;
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t w = i % 2 == 0 ? 0 : std::uint32_t(rng() % (4 * std::uint64_t(table.r_hi)));
            const glm::uvec2 a(std::uint32_t(rng() % (l.extent_x - w)), std::uint32_t(rng() % (l.extent_y - w)));
            const glm::uvec2 b = a + glm::uvec2(w, std::uint32_t(rng() % (w + 1)));
            const std::uint32_t reach =
                i % 10 == 9 ? l.extent_x : std::uint32_t(rng() % (3 * std::uint64_t(table.r_hi)));
            for (const std::uint32_t need : {0u, shared::FIELD_OCCUPIED, shared::FIELD_FRESH})
                out.push_back({a, b, reach, need});
        }
        return out;
    }
    // The host's search for the query: the leaves it visits, in order.
    std::vector<std::uint32_t> host(const Query& q) const {
        std::vector<std::uint32_t> got;
        auto visit = [&](std::uint32_t leaf) { return got.push_back(leaf), false; };
        if (q.need == 0) tree.near(q.a, q.b, q.reach, visit);
        if (q.need == shared::FIELD_OCCUPIED) tree.near_samples(q.a, q.b, q.reach, visit);
        if (q.need == shared::FIELD_FRESH) tree.near_fresh(q.a, q.b, q.reach, visit);
        return got;
    }
};

const Box kBoxes[] = {Box{1, 1, Boundary::Periodic}, Box{1.3, 1, Boundary::Free}};

// The probe kernel's answer to a query, from the shared search compiled for the host.
glm::uvec4 fingerprint(const Forest& f, const Query& q, std::uint32_t budget) {
    const shared::FieldTreeView v = f.tree.view();
    shared::FieldSearch s = shared::field_search_begin(v, f.table.lattice, q.a, q.b, q.reach, q.need, budget);
    glm::uvec4 r(0);
    for (std::uint32_t leaf; (leaf = shared::field_search_next(v, s)) != shared::FIELD_SEARCH_DONE;) {
        if (leaf == shared::FIELD_SEARCH_OVERFLOW) return {shared::FIELD_SEARCH_OVERFLOW, r.x, 0, 0};
        ++r.x;
        r.y += shared::hash32(leaf);
        r.z += shared::hash_mix(leaf, 0x5bd1e995u);
        r.w ^= shared::hash32(leaf + 1);
    }
    return r;
}

}  // namespace

TEST_CASE("the shared leaf search meets the leaves the host's search meets", "[field]") {
    for (const Box& box : kBoxes) {
        const Forest f(box);
        INFO((box.boundary == Boundary::Periodic ? "periodic" : "free"));
        const shared::FieldTreeView v = f.tree.view();
        std::size_t met = 0;
        for (const Query& q : f.queries(300, 2)) {
            std::vector<std::uint32_t> want = f.host(q), got;
            shared::FieldSearch s =
                shared::field_search_begin(v, f.table.lattice, q.a, q.b, q.reach, q.need, UINT32_MAX);
            for (std::uint32_t leaf; (leaf = shared::field_search_next(v, s)) != shared::FIELD_SEARCH_DONE;)
                got.push_back(leaf);
            std::sort(want.begin(), want.end());
            std::sort(got.begin(), got.end());
            INFO("block (" << q.a.x << ", " << q.a.y << ") to (" << q.b.x << ", " << q.b.y << "), reach " << q.reach
                           << ", flag " << q.need);
            REQUIRE(got == want);
            met += got.size();
        }
        CHECK(met > 10000);
    }
}

TEST_CASE("a search's gate of reach skips only leaves none of whose points is within f of the point", "[field]") {
    // From random points, a search of reach 4 r_hi with the gate against one without: the gated
    // leaves are among the others, and a leaf it skips lies farther from the point than the rule's
    // f with the greatest r over the leaf (the table's), by the leaf's nearest lattice point.
    for (const Box& box : kBoxes) {
        const Forest f(box);
        INFO((box.boundary == Boundary::Periodic ? "periodic" : "free"));
        const shared::FieldTreeView v = f.tree.view();
        const shared::FieldTableView& tv = f.table.view();
        const shared::Lattice& l = f.table.lattice;
        std::vector<std::pair<glm::uvec2, glm::uvec2>> blocks(f.tree.leaves());
        f.tree.each_leaf([&](std::uint32_t leaf, glm::uvec2 corner, std::uint32_t bits) {
            blocks[leaf] = {corner, shared::field_far_corner(l, corner, bits)};
        });
        // The least gap along an axis from v to [lo, hi], over v's images on a torus.
        auto gap = [&](std::int64_t v, std::int64_t lo, std::int64_t hi, std::int64_t extent) {
            std::int64_t best = INT64_MAX;
            for (std::int64_t shift : {std::int64_t(0), extent, -extent}) {
                if (shift != 0 && l.periodic == 0) continue;
                best = std::min(best, std::abs(std::clamp(v + shift, lo, hi) - (v + shift)));
            }
            return std::uint64_t(best);
        };
        auto leaves = [&](shared::FieldSearch s) {
            std::vector<std::uint32_t> got;
            for (std::uint32_t leaf; (leaf = shared::field_search_next(v, s)) != shared::FIELD_SEARCH_DONE;)
                got.push_back(leaf);
            std::sort(got.begin(), got.end());
            return got;
        };
        const std::uint32_t reach = 4 * f.table.r_hi;
        std::mt19937_64 rng(7);
        std::size_t skipped = 0, kept = 0;
        for (int i = 0; i < 100; ++i) {
            const glm::uvec2 p(std::uint32_t(rng() % l.extent_x), std::uint32_t(rng() % l.extent_y));
            const std::uint32_t r = shared::field_radius(tv, p);
            for (std::uint32_t rule = shared::RULE_PRIOR; rule <= shared::RULE_SMALLER; ++rule)
                for (std::uint32_t later : {0u, 1u}) {
                    INFO("point (" << p.x << ", " << p.y << "), rule " << rule << ", later " << later);
                    const std::vector<std::uint32_t> all =
                        leaves(shared::field_search_begin(v, l, p, p, reach, 0, UINT32_MAX));
                    shared::FieldSearch s = shared::field_search_begin(v, l, p, p, reach, 0, UINT32_MAX);
                    shared::field_search_gate_reach(s, tv, l, rule, f.table.r_hi, p, r, later);
                    const std::vector<std::uint32_t> gated = leaves(s);
                    REQUIRE(std::includes(all.begin(), all.end(), gated.begin(), gated.end()));
                    std::size_t wrong = 0;
                    for (const std::uint32_t leaf : all) {
                        if (std::binary_search(gated.begin(), gated.end(), leaf)) continue;
                        const auto [a, b] = blocks[leaf];
                        const std::uint32_t hi = shared::field_max_over(tv, a, b);
                        const std::uint32_t fmax =
                            later != 0 ? shared::rule_f(rule, r, hi) : shared::rule_f(rule, hi, r);
                        const std::uint64_t gx = gap(p.x, a.x, b.x, l.extent_x), gy = gap(p.y, a.y, b.y, l.extent_y);
                        wrong += gx * gx + gy * gy < std::uint64_t(fmax) * fmax;
                    }
                    REQUIRE(wrong == 0);
                    kept += gated.size();
                    skipped += all.size() - gated.size();
                }
        }
        // Most leaves of the square lie beyond every f from its centre.
        INFO("skipped " << skipped << ", kept " << kept);
        CHECK(skipped > 20 * kept);
        CHECK(kept > 5000);
    }
}

TEST_CASE("the device's leaf search meets the leaves the host's search meets, or stops at its budget", "[field][gpu]") {
    // The budget the field kernels give a search on lavapipe: the searches past the whole box
    // (a tenth of them) pass it and must say so, on the device as on the host.
    constexpr std::uint32_t kBudget = 8000;
    detail::VulkanContext ctx("");
    detail::Kernel probe(ctx, "field_search_probe", {spirv_field_search_probe, std::size(spirv_field_search_probe)}, 72,
                         64);
    for (const Box& box : kBoxes) {
        const Forest f(box);
        INFO((box.boundary == Boundary::Periodic ? "periodic" : "free"));
        const shared::FieldTreeView v = f.tree.view();
        const std::vector<Query> queries = f.queries(2000, 3);
        test::DeviceCopies upload{ctx, {}};
        struct {
            std::uint32_t tile_bits, tiles_x, tiles_y;
            std::uint64_t roots, nodes;
            shared::Lattice lattice;
            std::uint64_t queries, results;
            std::uint32_t count, budget;
        } push{v.tile_bits,
               v.tiles_x,
               v.tiles_y,
               upload(f.tree.root_words().data(), f.tree.root_words().size_bytes()),
               upload(f.tree.node_words().data(), f.tree.node_words().size_bytes()),
               f.table.lattice,
               upload(queries.data(), queries.size() * sizeof(Query)),
               0,
               std::uint32_t(queries.size()),
               kBudget};
        static_assert(offsetof(decltype(push), lattice) == 32 && offsetof(decltype(push), budget) == 68);
        detail::Buffer out(ctx, queries.size() * 16, true);
        push.results = out.address();
        test::run_probe(ctx, probe, &push, queries.size());
        const auto* got = static_cast<const glm::uvec4*>(out.mapped());
        std::size_t met = 0, whole = 0, overflows = 0;
        for (std::size_t i = 0; i < queries.size(); ++i) {
            const Query& q = queries[i];
            const glm::uvec4 want = fingerprint(f, q, kBudget);
            INFO("block (" << q.a.x << ", " << q.a.y << ") to (" << q.b.x << ", " << q.b.y << "), reach " << q.reach
                           << ", flag " << q.need);
            REQUIRE(got[i] == want);
            // A search of the whole box, thousands of leaves, passes the budget.
            const bool all = q.reach == f.table.lattice.extent_x;
            whole += all;
            if (all && q.need == 0) REQUIRE(want.x == shared::FIELD_SEARCH_OVERFLOW);
            if (want.x == shared::FIELD_SEARCH_OVERFLOW) {
                overflows += !all;
                continue;
            }
            // Within its budget, the search meets the host's leaves (the whole multiset: above).
            REQUIRE(want == fingerprint(f, q, UINT32_MAX));
            REQUIRE(want.x == f.host(q).size());
            met += want.x;
        }
        CHECK(met > 50000);
        CHECK(whole >= queries.size() / 20);
        CHECK(overflows <= queries.size() / 100);
    }
}
