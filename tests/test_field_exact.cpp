// Sizing fields decided exactly at the boundary of Eq. 10 and Eq. 11: whole runs on a table whose
// radii are a few lattice units, where samples often lie exactly f apart. Such a pair is no
// conflict (Eq. 10 asks |x - y| < f), and a lattice point exactly f from its nearest sample is not
// covered (Eq. 11 asks the same), so no run may end with one. The judge below is written from the
// equations, with none of the samplers' predicates.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "cpu/thread_pool.h"
#include "field/field.h"
#include "field/table.h"
#include "support.h"
#include "vrpd/sizing.h"

using namespace vrpd;

namespace {

constexpr std::uint32_t kExtent = 256;  // lattice points a side of the unit torus

// A table over the torus: 8 x 8 cells of 32 lattice units, its nodes from 5 to 10 units (L about
// 0.2, within every rule's bound), so that f is a small whole number at most lattice points.
detail::FieldTable coarse_table() {
    detail::FieldTable t;
    t.lattice = {kExtent, kExtent, 1u};
    t.quantum = 1.0 / kExtent;
    t.cell_bits = t.tile_bits = 5;
    t.cells_x = t.cells_y = t.tiles_x = t.tiles_y = kExtent >> 5;
    t.nodes.resize(std::size_t(t.cells_x + 1) * (t.cells_y + 1));
    for (std::uint32_t j = 0; j <= t.cells_y; ++j)
        for (std::uint32_t i = 0; i <= t.cells_x; ++i)  // the last row and column repeat the first
            t.nodes[std::size_t(j) * (t.cells_x + 1) + i] = 5 + ((i % t.cells_x) * 3 + (j % t.cells_y) * 5) % 6;
    detail::ThreadPool pool(1);
    detail::complete_bounds(t, pool);
    return t;
}

// f(x, y) of Table 1 for an earlier sample x and a later point y.
std::uint64_t f_of(SizingRule rule, std::uint64_t r_earlier, std::uint64_t r_later) {
    switch (rule) {
        case SizingRule::Prior:
            return r_earlier;
        case SizingRule::Current:
            return r_later;
        case SizingRule::Bigger:
            return std::max(r_earlier, r_later);
        case SizingRule::Smaller:
            return std::min(r_earlier, r_later);
    }
    return 0;
}

// The squared distance on the torus, the shorter way round each axis.
std::uint64_t torus_d2(glm::uvec2 a, glm::uvec2 b) {
    auto gap = [](std::uint32_t u, std::uint32_t v) {
        const std::uint64_t d = u > v ? u - v : v - u;
        return std::min<std::uint64_t>(d, kExtent - d);
    };
    const std::uint64_t dx = gap(a.x, b.x), dy = gap(a.y, b.y);
    return dx * dx + dy * dy;
}

struct Judged {
    std::uint64_t conflicts = 0, ties = 0, uncovered = 0, exactly_f = 0;
};

// Every pair in acceptance order against Eq. 10, and every lattice point against Eq. 11 (through
// buckets of 16 x 16 points: f is at most 10).
Judged judge(const Sampling& s, const detail::FieldTable& t, SizingRule rule) {
    Judged out;
    const std::size_t n = s.size();
    std::vector<std::uint32_t> r(n);
    for (std::size_t i = 0; i < n; ++i) r[i] = t.radius(s.lattice[i]);
    constexpr std::uint32_t kBucket = 16, kBuckets = kExtent / kBucket;
    std::vector<std::vector<std::uint32_t>> buckets(kBuckets * kBuckets);
    for (std::uint32_t i = 0; i < n; ++i)
        buckets[(s.lattice[i].y / kBucket) * kBuckets + s.lattice[i].x / kBucket].push_back(i);
    auto near = [&](glm::uvec2 p, auto&& visit) {
        for (std::uint32_t dy = kBuckets - 1; dy <= kBuckets + 1; ++dy)
            for (std::uint32_t dx = kBuckets - 1; dx <= kBuckets + 1; ++dx)
                for (std::uint32_t i :
                     buckets[((p.y / kBucket + dy) % kBuckets) * kBuckets + (p.x / kBucket + dx) % kBuckets])
                    visit(i);
    };
    for (std::uint32_t j = 0; j < n; ++j)
        near(s.lattice[j], [&](std::uint32_t i) {
            if (i >= j) return;
            const std::uint64_t f = f_of(rule, r[i], r[j]), d2 = torus_d2(s.lattice[i], s.lattice[j]);
            out.conflicts += d2 < f * f;
            out.ties += d2 == f * f;
        });
    for (std::uint32_t y = 0; y < kExtent; ++y)
        for (std::uint32_t x = 0; x < kExtent; ++x) {
            const glm::uvec2 p(x, y);
            const std::uint64_t rp = t.radius(p);
            bool covered = false, tie = false;
            near(p, [&](std::uint32_t i) {
                const std::uint64_t f = f_of(rule, r[i], rp), d2 = torus_d2(s.lattice[i], p);
                covered = covered || d2 < f * f;
                tie = tie || d2 == f * f;
            });
            out.uncovered += !covered;
            out.exactly_f += !covered && tie;
        }
    return out;
}

}  // namespace

TEST_CASE("sizing fields: pairs exactly f apart are kept, and no lattice point exactly f from the samples is left",
          "[field][gpu]") {
    const detail::FieldTable t = coarse_table();
    REQUIRE(t.r_lo == 5);
    REQUIRE(t.r_hi == 10);
    std::uint64_t ties = 0;
    for (const SizingRule rule : {SizingRule::Prior, SizingRule::Current, SizingRule::Bigger, SizingRule::Smaller})
        for (std::uint32_t seed = 1; seed <= 2; ++seed) {
            std::vector<glm::uvec2> first;
            for (const Backend b : {Backend::Serial, Backend::Cpu, Backend::Gpu}) {
                SampleOptions o;
                o.seed = seed;
                o.backend = b;
                o.threads = 2;
                o.sizing = Sizing{.expression = "1", .rule = rule};
                const Sampling s = detail::sample_field(o, t);
                INFO("rule " << sizing_rule_name(rule) << ", seed " << seed << ", backend " << int(b) << ", "
                             << s.size() << " samples");
                REQUIRE(s.size() > 500);
                if (first.empty()) {
                    first = s.lattice;
                    const Judged j = judge(s, t, rule);
                    CHECK(j.conflicts == 0);
                    CHECK(j.uncovered == 0);
                    CHECK(j.exactly_f == 0);
                    ties += j.ties;
                } else {
                    CHECK(s.lattice == first);
                }
            }
        }
    CHECK(ties > 0);
}
