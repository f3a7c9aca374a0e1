// The sizing-field sampler's tests against the samples (sampler.h): the rule's reaches, a point's
// conflicts, whether a block is covered, and which children of a split cell stay open. Each
// bound is derived in docs/design.md, "Sizing fields".
#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>

#include "sampler.h"

namespace vrpd::detail::field {

std::uint64_t FieldSampler::reach(uvec2 a, uvec2 b, std::uint32_t r_hi) const {
    // current, smaller: f <= r(y) <= r_hi.
    if (rule_ == shared::RULE_CURRENT || rule_ == shared::RULE_SMALLER) return r_hi;
    return t_.grown_reach(a, b, r_hi, 1);
}

std::uint64_t FieldSampler::cover_reach(uvec2 x, std::uint32_t r) const {
    // prior, smaller: f <= r(x); current, bigger: f <= max(r(x), r(y)), with y within the reach.
    if (rule_ == shared::RULE_PRIOR || rule_ == shared::RULE_SMALLER) return r;
    return t_.grown_reach(x, x, r, 4);
}

bool FieldSampler::conflicts_with(std::uint32_t s, uvec2 p, std::uint32_t r) const {
    return shared::field_conflict(shared::rule_f(rule_, radii_[s], r), shared::distance2(t_.lattice, lattice_[s], p));
}

std::uint32_t FieldSampler::conflicting(uvec2 p, std::uint32_t r) const {
    const std::uint64_t f = reach(p, p, r);
    if (steep(f, r)) [[unlikely]]
        return steep_conflicting(p, r, f);
    std::uint32_t found = FieldQuadtree::kNone;
    auto test = [&](std::uint32_t leaf) { return conflicts_with(found = tree_.sample(leaf), p, r); };
    return tree_.near_samples(p, p, f, test) ? found : FieldQuadtree::kNone;
}

std::uint32_t FieldSampler::steep_conflicting(uvec2 p, std::uint32_t r, std::uint64_t f) const {
    // An earlier sample in a block conflicts with p only within f(r over the block, r).
    std::uint32_t found = FieldQuadtree::kNone;
    auto test = [&](std::uint32_t leaf) { return conflicts_with(found = tree_.sample(leaf), p, r); };
    return tree_.near_samples(p, p, f, test, within(p, p, r, true)) ? found : FieldQuadtree::kNone;
}

bool FieldSampler::conflicts_fresh(uvec2 p, std::uint32_t r, std::uint32_t leaf) const {
    if (!stamped(leaf)) return false;
    if (const std::uint32_t s = stamp(leaf); s != FieldQuadtree::kNone) return conflicts_with(s, p, r);
    const std::uint64_t f = reach(p, p, r);
    auto test = [&](std::uint32_t l) { return conflicts_with(tree_.sample(l), p, r); };
    return search_within(steep(f, r), p, p, r, true,
                         [&](auto enter) { return tree_.near_fresh(p, p, f, test, enter); });
}

void FieldSampler::gather(const Cell& c, std::vector<std::uint32_t>& out) const {
    out.clear();
    const uvec2 a = c.corner, b = far_corner(c);
    const std::uint32_t hi = t_.max_over(a, b);
    const std::uint64_t f = reach(a, b, hi);  // bounds the f of any sample covering a child
    // The samples are in acceptance order, random in space: each one's point and r are fetched
    // as it is found, for open_children, which reads them once the search ends.
    auto keep = [&](std::uint32_t leaf) {
        const std::uint32_t s = tree_.sample(leaf);
        __builtin_prefetch(&lattice_[s]);
        __builtin_prefetch(&radii_[s]);
        out.push_back(s);
        return false;
    };
    // A sample in a block covers a child only within f(r over the block, hi) of the cell.
    const bool prune = steep(f, hi);
    auto search = [&](uvec2 from, uvec2 to, std::uint64_t reach) {
        search_within(prune, a, b, hi, true,
                      [&](auto enter) { return tree_.near_samples(from, to, reach, keep, enter); });
    };
    if (wraps(a, b, f)) {
        search(a, b, f);
        return;
    }
    // A cover of child k lies within f - 1 - ceil(w / 2) of the child's middle points
    // (covered_by_fresh): search around the box of the children's middles. The children split
    // each axis of the cell at a + side, the second part clipped to the cell.
    const std::uint32_t side = 1u << (c.bits - 1);
    uvec2 from(UINT32_MAX), to(0);
    std::uint32_t half = UINT32_MAX;
    for (std::uint32_t k = 0; k < 4; ++k) {
        const uvec2 ka(a.x + (k & 1) * side, a.y + (k >> 1) * side);
        if (ka.x > b.x || ka.y > b.y) continue;
        const Middle mx = middle(ka.x, std::min(ka.x + side - 1, b.x)),
                     my = middle(ka.y, std::min(ka.y + side - 1, b.y));
        from = glm::min(from, uvec2(mx.from, my.from));
        to = glm::max(to, uvec2(mx.to, my.to));
        half = std::min({half, mx.half, my.half});
    }
    if (half >= f) return;
    search(from, to, f - 1 - half);
}

bool FieldSampler::covered_by_fresh(uvec2 a, uvec2 b, std::uint32_t leaf, bool whole) const {
    if (!stamped(leaf)) return false;
    // Each of the round's samples that stamped the leaf tested it whole (touch).
    if (whole) return covered_whole(leaf);
    if (const std::uint32_t one = stamp(leaf); one != FieldQuadtree::kNone) return covers(one, a, b);
    // For the search, r's least value over the block (unread under prior, whose f is the
    // sample's own radius) and, under prior and bigger, its largest.
    const bool own = rule_ == shared::RULE_CURRENT || rule_ == shared::RULE_SMALLER;
    std::uint32_t lo = 0, hi = 0;
    if (rule_ == shared::RULE_PRIOR)
        hi = t_.max_over(a, b);
    else if (!own)
        std::tie(lo, hi) = t_.extremes_over(a, b);
    else
        lo = t_.min_over(a, b);
    auto test = [&](std::uint32_t leaf) { return covers(tree_.sample(leaf), lo, a, b); };
    // A covering sample's f: at most lo under current and smaller; under prior and bigger at
    // most the reach, which bounds r(x) for each x within it (the largest r over its square, or
    // the Lipschitz growth).
    const std::uint64_t f = own ? lo : reach(a, b, hi);
    // A sample in a block covers [a, b] only within f(r over the block, lo) of it.
    const bool prune = !own && steep(f, hi);
    auto find = [&](uvec2 from, uvec2 to, std::uint64_t reach) {
        return search_within(prune, a, b, lo, true,
                             [&](auto enter) { return tree_.near_fresh(from, to, reach, test, enter); });
    };
    if (wraps(a, b, f)) return find(a, b, f);
    // Along each axis the farther end of [a, b] lies ceil(w / 2) beyond a sample's gap to the
    // middle lattice points (on a torus too: the block and the reach are under half of it, a line
    // there). So a cover's gap to them is below f - ceil(w / 2), and none covers a block whose
    // half-width reaches f.
    const Middle mx = middle(a.x, b.x), my = middle(a.y, b.y);
    if (std::max(mx.half, my.half) >= f) return false;
    return find({mx.from, my.from}, {mx.to, my.to}, f - 1 - std::min(mx.half, my.half));
}

std::uint64_t FieldSampler::far_distance2(std::uint32_t s, uvec2 a, uvec2 b) const {
    return shared::far_distance2(t_.lattice, lattice_[s], a, b);
}

bool FieldSampler::covers(std::uint32_t s, std::uint32_t lo, uvec2 a, uvec2 b) const {
    return shared::field_conflict(shared::rule_f(rule_, radii_[s], lo), far_distance2(s, a, b));
}

bool FieldSampler::covers(std::uint32_t s, uvec2 a, uvec2 b) const {
    return covers_far(radii_[s], far_distance2(s, a, b), [&] { return t_.min_over(a, b); });
}

std::uint8_t FieldSampler::open_children(const std::vector<std::uint32_t>& near, const Cell& c) const {
    // The children split each axis of [a, b] at m = a + half: [a, min(m - 1, b)] and, where m <= b,
    // [m, b]. A sample's farther gap to either part is taken once per axis, for the two children
    // on that side. Under prior f is the sample's own radius: the children's least r goes unread.
    const shared::Lattice& l = t_.lattice;
    const uvec2 a = c.corner, b = far_corner(c);
    const uvec2 m = a + uvec2(1u << (c.bits - 1));
    const uvec2 e = glm::min(m - uvec2(1), b);  // the first parts' last points
    std::uint8_t open = 0;
    for (std::uint32_t k = 0; k < 4; ++k)
        if (child_corner(c, k)) open |= std::uint8_t(1u << k);
    if (near.empty()) return open;
    const std::array<std::uint32_t, 4> lo =
        rule_ == shared::RULE_PRIOR ? std::array<std::uint32_t, 4>{} : t_.children_min(a, e, m, b, open);
    // A sample's farther gap to each part along one axis. Off a torus, or on one where o, the
    // offset from a to the image of v nearest a (o <= extent / 2), is at least w - extent / 2 so
    // that the image lies within half the torus of every end of the cell, the gaps to [from, to]
    // are max(o - from, to - o) in that image; else axis_far_gap's.
    auto gaps = [&](std::uint32_t v, std::uint32_t a, std::uint32_t e, std::uint32_t m, std::uint32_t b,
                    std::uint32_t extent, std::uint64_t out[2]) {
        const std::int64_t o = l.periodic ? shared::axis_offset(a, v, extent, 1u) : std::int64_t(v) - std::int64_t(a);
        const std::int64_t w = std::int64_t(b) - std::int64_t(a), half = std::int64_t(extent / 2);
        if (!l.periodic || o - w >= -half) {
            const std::int64_t ea = std::int64_t(e) - std::int64_t(a), ma = std::int64_t(m) - std::int64_t(a);
            out[0] = std::uint64_t(std::max(o, ea - o));
            out[1] = std::uint64_t(std::max(o - ma, w - o));
            return;
        }
        out[0] = shared::axis_far_gap(v, a, e, extent, 1u);
        out[1] = shared::axis_far_gap(v, m, b, extent, 1u);
    };
    // The rule is fixed for the run: each rule's loop has its f known, and tests the four children
    // without a branch (a child already covered stays covered).
    auto scan = [&](auto rule) {
        for (std::uint32_t s : near) {
            const uvec2 x = lattice_[s];
            std::uint64_t gx[2], gy[2];
            gaps(x.x, a.x, e.x, m.x, b.x, l.extent_x, gx);
            gaps(x.y, a.y, e.y, m.y, b.y, l.extent_y, gy);
            const std::uint32_t r = radii_[s];
            std::uint32_t covered = 0;
            for (std::uint32_t k = 0; k < 4; ++k)
                covered |= std::uint32_t(shared::field_conflict(shared::rule_f(rule(), r, lo[k]),
                                                                gx[k & 1] * gx[k & 1] + gy[k >> 1] * gy[k >> 1]))
                           << k;
            open &= std::uint8_t(~covered);
            if (open == 0) break;
        }
    };
    switch (rule_) {
        case shared::RULE_PRIOR:
            scan([] { return shared::RULE_PRIOR; });
            break;
        case shared::RULE_CURRENT:
            scan([] { return shared::RULE_CURRENT; });
            break;
        case shared::RULE_BIGGER:
            scan([] { return shared::RULE_BIGGER; });
            break;
        default:
            scan([] { return shared::RULE_SMALLER; });
            break;
    }
    return open;
}

}  // namespace vrpd::detail::field
