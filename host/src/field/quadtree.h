// The base cells of a sizing-field run: a quadtree under each tile whose leaves follow the local
// radius (a leaf's diagonal is shorter than the least r over it, so it holds at most one sample,
// which covers it under every rule), and the neighbour search over them.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "table.h"
#include "shared/field_tree.h"
#include "../cpu/thread_pool.h"

namespace vrpd::detail {

class FieldQuadtree {
public:
    static constexpr std::uint32_t kNone = UINT32_MAX;
    // A tile holds many leaves: the loops over tiles go to the threads from two tiles on.
    static constexpr std::size_t kTileGrain = 2;

    // Builds the tiles' trees on the pool's threads. Throws Error if the leaves would pass
    // `max_leaves` or the node words' index.
    FieldQuadtree(const FieldTable& table, std::uint64_t max_leaves, ThreadPool& pool);

    std::size_t leaves() const { return sample_.size(); }
    // Calls visit(leaf, corner, bits) for every leaf, in index order (tiles in order, each depth
    // first with children in order: the order the build numbers them in). A leaf's corner and
    // side are found by descent, not stored.
    template <typename Visit>
    void each_leaf(Visit&& visit) const {
        each_leaf(0, roots_.size(), visit);
    }
    // The same over the leaves of tiles [first, end) (row by row): a run of leaf indices.
    template <typename Visit>
    void each_leaf(std::size_t first, std::size_t end, Visit&& visit) const;
    std::size_t tiles() const { return roots_.size(); }
    // A leaf: its index, corner and side 2^bits.
    struct Leaf {
        std::uint32_t index, bits;
        glm::uvec2 corner;
        bool holds(glm::uvec2 p) const {
            return (p.x >> bits) == (corner.x >> bits) && (p.y >> bits) == (corner.y >> bits);
        }
    };
    // The tree's words as the shared descent reads them (shared/field_tree.h), and the arrays
    // they point into.
    shared::FieldTreeView view() const {
        return {t_.tile_bits, t_.tiles_x, t_.tiles_y, {roots_.data()}, {nodes_.data()}};
    }
    // The leaf holding lattice point p, found by descent from its tile's root (inline: the hot
    // loops find a leaf per dart and per cell).
    Leaf leaf_at(glm::uvec2 p) const {
        const glm::uvec2 leaf = shared::field_leaf_at(view(), p);
        const std::uint32_t mask = ~((std::uint32_t(1) << leaf.y) - 1);  // bits < 32: a leaf is within a tile
        return {leaf.x, leaf.y, {p.x & mask, p.y & mask}};
    }
    std::span<const std::uint32_t> root_words() const { return roots_; }
    std::span<const std::uint32_t> node_words() const { return nodes_; }
    std::uint32_t leaf_of(glm::uvec2 p) const { return leaf_at(p).index; }
    std::uint32_t sample(std::uint32_t leaf) const { return sample_[leaf]; }
    // A leaf with darts of the round holds no sample: while a resolution runs, its sample's slot
    // holds its first dart instead, until cleared (back to kNone).
    void set_first_dart(std::uint32_t leaf, std::uint32_t dart) { sample_[leaf] = dart; }
    std::uint32_t first_dart(std::uint32_t leaf) const { return sample_[leaf]; }
    void clear_first_dart(std::uint32_t leaf) { sample_[leaf] = kNone; }
    void prefetch(std::uint32_t leaf) const { __builtin_prefetch(&sample_[leaf]); }
    // The marks below (set_sample, mark_fresh, settle) may run on several threads at once, for
    // distinct leaves, while no search runs.
    // Gives the leaf holding point p its sample s, and marks the nodes above it as holding one,
    // and a fresh one.
    void set_sample(std::uint32_t leaf, glm::uvec2 p, std::uint32_t s);
    // Marks the leaf holding point p, and the nodes above it, fresh: it holds a dart (during
    // resolution) or a sample (set_sample) of this round.
    void mark_fresh(glm::uvec2 p) { mark(p, kFresh, true); }
    // Clears the fresh marks on the path to the leaf holding point p; called for every fresh
    // leaf, it ends their freshness.
    void settle(glm::uvec2 p) { mark(p, kFresh, false); }
    std::uint32_t depth() const { return depth_; }
    // The tiles whose leaves a plain search reads as a window (all of one side).
    std::size_t flat_tiles() const {
        return std::size_t(
            std::count_if(flat_bits_.begin(), flat_bits_.end(), [](std::uint8_t b) { return b != kMixed; }));
    }
    // The most the build held at once (the chunks' arrays and the tree they are copied into).
    std::uint64_t build_bytes() const { return build_bytes_; }
    std::uint64_t bytes() const {
        return nodes_.capacity() * 4 + sample_.capacity() * 4 + roots_.capacity() * 4 + flat_bits_.capacity() +
               flat_first_.capacity() * 4;
    }

    // The gaps along each axis from the block of side 2^bits met at `image` (an `enter` test's
    // argument: its place in the query's unwrapped coordinates) to [a, b]; on a torus, from the
    // nearest image of the block.
    glm::u64vec2 image_gaps(glm::i64vec2 image, std::uint32_t bits, glm::uvec2 a, glm::uvec2 b) const {
        const shared::Lattice& l = t_.lattice;
        const std::int64_t side = std::int64_t(1) << bits;
        auto gap = [&](std::int64_t at, std::int64_t from, std::int64_t to, std::int64_t extent) {
            std::int64_t g = INT64_MAX;
            for (const std::int64_t shift : {std::int64_t(0), extent, -extent}) {
                if (shift != 0 && !l.periodic) break;
                const std::int64_t lo = at + shift, hi = lo + side - 1;
                g = std::min(g, to < lo ? lo - to : from > hi ? from - hi : 0);
            }
            return std::uint64_t(g);
        };
        return {gap(image.x, a.x, b.x, l.extent_x), gap(image.y, a.y, b.y, l.extent_y)};
    }
    // A search's test before it enters a subtree (see near): this one enters every subtree.
    struct EnterAll {
        bool operator()(glm::i64vec2, glm::uvec2, std::uint32_t) const { return true; }
    };
    // Calls visit(leaf) for each leaf that meets the square `reach` around [a, b] (inclusive), so
    // every leaf holding a point within `reach` of a point of [a, b]; on a torus, of any of its
    // images; visit(leaf, corner, bits, image) where it takes the leaf's lattice corner, side and
    // the corner's image too (its place in the query's unwrapped coordinates, as `enter` has it).
    // Stops at a call that returns true and returns true. `enter`, where given, is asked before a subtree is
    // entered: enter(image, corner, bits) for the block of side 2^bits at lattice corner `corner`, met at `image` (the
    // corner's place in the query's unwrapped coordinates, on a torus one period off where the query crosses).
    template <typename Visit, typename Enter = EnterAll>
    bool near(glm::uvec2 a, glm::uvec2 b, std::uint64_t reach, Visit&& visit, Enter enter = {}) const {
        return search<0>(a, b, reach, visit, enter);
    }
    // The same over the leaves that hold a sample only: subtrees without one are not entered. Not
    // while a resolution holds first darts in the leaves' sample slots: a flat tile reads them.
    template <typename Visit, typename Enter = EnterAll>
    bool near_samples(glm::uvec2 a, glm::uvec2 b, std::uint64_t reach, Visit&& visit, Enter enter = {}) const {
        return search<kOccupied>(a, b, reach, visit, enter);
    }
    // The same over the fresh leaves (marked, not yet settled).
    template <typename Visit, typename Enter = EnterAll>
    bool near_fresh(glm::uvec2 a, glm::uvec2 b, std::uint64_t reach, Visit&& visit, Enter enter = {}) const {
        return search<kFresh>(a, b, reach, visit, enter);
    }

private:
    // A run of tiles' nodes and leaves, indexed from 0.
    struct Arrays {
        std::vector<std::uint32_t> nodes;
        std::uint32_t leaves = 0;
        std::uint32_t depth = 0;
        std::uint32_t uncounted = 0;  // leaves not yet added to the shared count
    };
    struct Limits {
        std::uint64_t leaves, memory;  // the leaves allowed, and those the memory allows
    };
    // Builds the subtree of the block at `corner` (side 2^bits) into `out`; returns its node word.
    // `floor` is at most the least r over the block; `leaves` counts every chunk's leaves, each
    // chunk's added in batches (count_leaves).
    // Adds out's uncounted leaves to `leaves`; throws Error if they pass the limit.
    static void count_leaves(Arrays& out, const Limits& limits, std::atomic<std::uint64_t>& leaves);
    std::uint32_t build(Arrays& out, glm::uvec2 corner, std::uint32_t bits, std::uint32_t floor, const Limits& limits,
                        std::atomic<std::uint64_t>& leaves) const;
    // Sets or clears `flag` on the nodes from the tile root down to the leaf holding point p. Safe
    // from several threads at once (and not beside a search).
    void mark(glm::uvec2 p, std::uint32_t flag, bool on);

    const FieldTable& t_;
    // The node words (shared/field_tree.h): a root per tile, and the inner nodes' children.
    std::vector<std::uint32_t> roots_, nodes_;
    std::vector<std::uint32_t> sample_;
    // Per tile whose leaves are all of one side, none outside the lattice: that side's bits, and
    // its first leaf (the leaves follow in Morton order: x in the even bits); kMixed elsewhere.
    static constexpr std::uint8_t kMixed = 0xFF;
    std::vector<std::uint8_t> flat_bits_;
    std::vector<std::uint32_t> flat_first_;
    std::uint32_t depth_ = 0;
    std::uint64_t build_bytes_ = 0;

    // The node words' layout (shared/field_tree.h).
    static constexpr std::uint32_t kLeaf = shared::FIELD_LEAF;
    static constexpr std::uint32_t kOccupied = shared::FIELD_OCCUPIED;
    static constexpr std::uint32_t kFresh = shared::FIELD_FRESH;
    static constexpr std::uint32_t kIndex = shared::FIELD_INDEX;
    static constexpr std::uint32_t kOutside = shared::FIELD_OUTSIDE;
    static constexpr std::uint32_t kLeafBatch = 4096;  // leaves a chunk counts before adding them
    static_assert((kOutside & (kOccupied | kFresh)) == 0);
    // Query bounds: the lattice square [lo, hi] per axis (unwrapped), or the whole axis.
    struct Query {
        std::int64_t lo[2], hi[2];
        bool all[2];
    };
    // kNeed: the flag a subtree must carry to be entered (0: every subtree).
    template <std::uint32_t kNeed, typename Visit, typename Enter>
    bool search(glm::uvec2 a, glm::uvec2 b, std::uint64_t reach, Visit& visit, Enter& enter) const;
    // visit(leaf), or visit(leaf, corner, bits, image) where it takes them (near).
    template <typename Visit>
    static bool visit_leaf(Visit& visit, std::uint32_t leaf, glm::uvec2 corner, std::uint32_t bits,
                           glm::i64vec2 image) {
        if constexpr (std::is_invocable_v<Visit&, std::uint32_t, glm::uvec2, std::uint32_t, glm::i64vec2>)
            return visit(leaf, corner, bits, image);
        else
            return visit(leaf);
    }
    // `tile`: the root's lattice corner (ox, oy: its image).
    template <std::uint32_t kNeed, typename Visit, typename Enter>
    bool descend(std::uint32_t node, std::int64_t ox, std::int64_t oy, std::uint32_t bits, const Query& q, Visit& visit,
                 Enter& enter, glm::uvec2 tile) const;
};

template <typename Visit>
void FieldQuadtree::each_leaf(std::size_t first, std::size_t end, Visit&& visit) const {
    struct Item {
        std::uint32_t node, bits;
        glm::uvec2 corner;
    };
    std::vector<Item> stack;
    for (std::size_t k = first; k < end; ++k) {
        const glm::uvec2 tile(std::uint32_t(k % t_.tiles_x), std::uint32_t(k / t_.tiles_x));
        stack.push_back({roots_[k], t_.tile_bits, {tile.x << t_.tile_bits, tile.y << t_.tile_bits}});
        while (!stack.empty()) {
            const Item it = stack.back();
            stack.pop_back();
            if (it.node == kOutside) continue;
            if (it.node & kLeaf) {
                visit(it.node & kIndex, it.corner, it.bits);
                continue;
            }
            const std::uint32_t half = 1u << (it.bits - 1);
            for (std::uint32_t c = 4; c-- > 0;)  // child 0 on top
                stack.push_back({nodes_[(it.node & kIndex) + c], it.bits - 1,
                                 {it.corner.x + (c & 1) * half, it.corner.y + (c >> 1) * half}});
        }
    }
}

template <std::uint32_t kNeed, typename Visit, typename Enter>
bool FieldQuadtree::descend(std::uint32_t root, std::int64_t root_x, std::int64_t root_y, std::uint32_t root_bits,
                            const Query& q, Visit& visit, Enter& enter, glm::uvec2 tile) const {
    // search() passes only tiles that meet the query's square.
    const std::int64_t root_side = std::int64_t(1) << root_bits;
    if ((kNeed != 0 ? !(root & kNeed) : root == kOutside) || !enter(glm::i64vec2(root_x, root_y), tile, root_bits))
        return false;
    // Below the root, coordinates are offsets from its corner, and the query is clipped to it
    // (the whole root where it spans the axis): what meets a node is unchanged, and so is which
    // child holds the query's middle, clipped as well.
    const std::int64_t last = root_side - 1;
    auto clip = [&](std::int64_t v, std::int64_t origin) {
        return std::uint32_t(std::clamp<std::int64_t>(v - origin, 0, last));
    };
    const std::uint32_t lo_x = q.all[0] ? 0 : clip(q.lo[0], root_x), hi_x = q.all[0] ? last : clip(q.hi[0], root_x);
    const std::uint32_t lo_y = q.all[1] ? 0 : clip(q.lo[1], root_y), hi_y = q.all[1] ? last : clip(q.hi[1], root_y);
    const std::uint32_t mid_x = clip((q.lo[0] + q.hi[0]) / 2, root_x), mid_y = clip((q.lo[1] + q.hi[1]) / 2, root_y);
    // A plain search of a tile whose leaves are all of one side reads the leaves that meet the
    // query as a window, row by row, not by descent.
    if constexpr (std::is_same_v<Enter, EnterAll> && kNeed != kFresh) {
        const std::size_t k = std::size_t(tile.y >> t_.tile_bits) * t_.tiles_x + (tile.x >> t_.tile_bits);
        if (const std::uint32_t b = flat_bits_[k]; b != kMixed) {
            auto spread = [](std::uint32_t v) {
                v = (v | v << 8) & 0x00FF00FFu;
                v = (v | v << 4) & 0x0F0F0F0Fu;
                v = (v | v << 2) & 0x33333333u;
                return (v | v << 1) & 0x55555555u;
            };
            const std::uint32_t first = flat_first_[k], i0 = lo_x >> b, i1 = hi_x >> b;
            for (std::uint32_t j = lo_y >> b; j <= hi_y >> b; ++j) {
                const std::uint32_t row = first + (spread(j) << 1);
                for (std::uint32_t i = i0; i <= i1; ++i) {
                    const std::uint32_t leaf = row + spread(i);
                    if (kNeed == kOccupied && sample_[leaf] == kNone) continue;
                    if (visit_leaf(visit, leaf, tile + glm::uvec2(i << b, j << b), b,
                                   glm::i64vec2(root_x + (i << b), root_y + (j << b))))
                        return true;
                }
            }
            return false;
        }
    }
    struct Item {
        std::uint32_t node, bits, x, y;
    };
    // Each level pushes at most 3 siblings beside the child it goes on with.
    Item stack[4 * 32];
    int top = 0;
    stack[top++] = {root, root_bits, 0, 0};
    while (top > 0) {
        const Item it = stack[--top];
        if (it.node & kLeaf) {
            if (visit_leaf(visit, it.node & kIndex, tile + glm::uvec2(it.x, it.y), it.bits,
                           glm::i64vec2(root_x + it.x, root_y + it.y)))
                return true;
            continue;
        }
        // The children that meet the query, as bit c for child c: in x, the left ones (bits 0
        // and 2) unless the query starts right of the middle, the right ones (1 and 3) unless it
        // ends left of it; the same in y with the low (0, 1) and high (2, 3) ones.
        const std::uint32_t half = 1u << (it.bits - 1), mx = it.x + half, my = it.y + half;
        const std::uint32_t in_x = (lo_x < mx ? 0x5u : 0u) | (hi_x >= mx ? 0xAu : 0u);
        const std::uint32_t in_y = (lo_y < my ? 0x3u : 0u) | (hi_y >= my ? 0xCu : 0u);
        const std::uint32_t meets = in_x & in_y;
        const std::uint32_t* children = &nodes_[it.node & kIndex];
        // A plain search takes the children in a fixed order, so the loop unrolls with each
        // child's offsets known: that saves more than taking first the child that holds the
        // query's middle, where a search for one hit mostly ends. A steep search (one with an
        // `enter` test) takes that child first, then its row neighbour, column neighbour and
        // diagonal: its square is wide, and a hit near its middle ends it early.
        constexpr bool kMiddleFirst = !std::is_same_v<Enter, EnterAll>;
        const std::uint32_t first = kMiddleFirst ? std::uint32_t(mid_x >= mx) | std::uint32_t(mid_y >= my) << 1 : 0;
        for (std::uint32_t k = 4; k-- > 0;) {
            const std::uint32_t c = first ^ k, child = children[c];
            if (!(meets >> c & 1u) || (kNeed != 0 ? !(child & kNeed) : child == kOutside)) continue;
            const Item kid{child, it.bits - 1, it.x + (c & 1) * half, it.y + (c >> 1) * half};
            if constexpr (!std::is_same_v<Enter, EnterAll>)
                if (!enter(glm::i64vec2(root_x + kid.x, root_y + kid.y), tile + glm::uvec2(kid.x, kid.y), kid.bits))
                    continue;
            stack[top++] = kid;
        }
    }
    return false;
}

template <std::uint32_t kNeed, typename Visit, typename Enter>
bool FieldQuadtree::search(glm::uvec2 a, glm::uvec2 b, std::uint64_t reach, Visit& visit, Enter& enter) const {
    const std::int64_t tile = std::int64_t(1) << t_.tile_bits;
    const std::int64_t q[4] = {a.x, a.y, b.x, b.y};
    const bool periodic = t_.lattice.periodic != 0;
    std::int64_t lo[2], hi[2];
    bool all[2];
    const std::int64_t tiles[2] = {t_.tiles_x, t_.tiles_y};
    const std::int64_t extent[2] = {t_.lattice.extent_x, t_.lattice.extent_y};
    for (int k = 0; k < 2; ++k) {
        const std::int64_t from = q[k] - std::int64_t(reach), to = q[k + 2] + std::int64_t(reach);
        all[k] = periodic && to - from + 1 >= extent[k];
        if (all[k]) {
            lo[k] = 0, hi[k] = tiles[k] - 1;
        } else if (periodic) {
            lo[k] = from >> t_.tile_bits;  // rounds down, negative values too
            hi[k] = to >> t_.tile_bits;
        } else {
            lo[k] = std::max<std::int64_t>(0, from) >> t_.tile_bits;
            hi[k] = std::min(tiles[k] - 1, std::max<std::int64_t>(0, to) >> t_.tile_bits);
            if (to < 0) return false;
        }
    }
    Query query;
    for (int k = 0; k < 2; ++k) {
        query.lo[k] = q[k] - std::int64_t(reach);
        query.hi[k] = q[k + 2] + std::int64_t(reach);
        query.all[k] = all[k];
    }
    auto search_tile = [&](std::int64_t tx, std::int64_t ty) {
        // A query narrower than the torus meets its tiles' images one period either side at most.
        const std::int64_t wx = tx < 0 ? tx + tiles[0] : tx >= tiles[0] ? tx - tiles[0] : tx,
                           wy = ty < 0 ? ty + tiles[1] : ty >= tiles[1] ? ty - tiles[1] : ty;
        const std::uint32_t root = roots_[std::size_t(wy * tiles[0] + wx)];
        return descend<kNeed>(root, tx * tile, ty * tile, t_.tile_bits, query, visit, enter,
                              glm::uvec2(std::uint32_t(wx * tile), std::uint32_t(wy * tile)));
    };
    // The tile holding the query's middle first: a search for one hit mostly ends there.
    std::int64_t mid[2];
    for (int k = 0; k < 2; ++k)
        mid[k] = std::clamp<std::int64_t>((query.lo[k] + query.hi[k]) >> 1 >> t_.tile_bits, lo[k], hi[k]);
    if (search_tile(mid[0], mid[1])) return true;
    for (std::int64_t ty = lo[1]; ty <= hi[1]; ++ty)
        for (std::int64_t tx = lo[0]; tx <= hi[0]; ++tx)
            if ((tx != mid[0] || ty != mid[1]) && search_tile(tx, ty)) return true;
    return false;
}

}  // namespace vrpd::detail
