// The quadtree of a sizing field's base cells (quadtree.h): its leaves and the marks on its nodes.
#include <algorithm>
#include <atomic>
#include <utility>

#include <fmt/format.h>

#include "quadtree.h"
#include "vrpd/vrpd.h"

namespace vrpd::detail {

FieldQuadtree::FieldQuadtree(const FieldTable& t, std::uint64_t max_leaves, ThreadPool& pool) : t_(t) {
    // Each chunk of tiles is built into arrays of its own, indexed from 0; appended in chunk
    // order, then offset, they are the arrays one thread would build tile by tile.
    struct Part {
        std::size_t first_tile = 0, end_tile = 0;
        Arrays arrays;
    };
    const std::size_t tiles = std::size_t(t.tiles_x) * t.tiles_y;
    roots_.resize(tiles);
    const Limits limits{std::min<std::uint64_t>(max_leaves, kIndex), max_leaves};
    std::atomic<std::uint64_t> leaves = 0;
    std::vector<Part> parts(pool.chunks(tiles, kTileGrain));
    pool.parallel_for(
        tiles,
        [&](std::size_t begin, std::size_t end, unsigned c) {
            Part part{begin, end, {}};
            for (std::size_t k = begin; k < end; ++k)
                roots_[k] =
                    build(part.arrays,
                          {std::uint32_t(k % t.tiles_x) << t.tile_bits, std::uint32_t(k / t.tiles_x) << t.tile_bits},
                          t.tile_bits, 0, limits, leaves);
            count_leaves(part.arrays, limits, leaves);
            parts[c] = std::move(part);
        },
        kTileGrain);
    std::size_t nodes = 0, leaf_count = 0;
    for (const Part& part : parts) nodes += part.arrays.nodes.size(), leaf_count += part.arrays.leaves;
    if (nodes > kIndex) throw Error("the field needs more quadtree nodes than the quadtree's 29-bit node index holds");
    nodes_.reserve(nodes);
    build_bytes_ = 2 * nodes * 4;  // the parts and their copy
    std::uint32_t leaves_so_far = 0;
    for (Part& part : parts) {
        const std::uint32_t node_base = std::uint32_t(nodes_.size()), leaf_base = leaves_so_far;
        auto offset = [&](std::uint32_t word) {
            return word == kOutside ? word : word & kLeaf ? word + leaf_base : word + node_base;
        };
        for (std::uint32_t word : part.arrays.nodes) nodes_.push_back(offset(word));
        for (std::size_t k = part.first_tile; k < part.end_tile; ++k) roots_[k] = offset(roots_[k]);
        leaves_so_far += part.arrays.leaves;
        depth_ = std::max(depth_, part.arrays.depth);
        part.arrays = {};
    }
    sample_.assign(leaf_count, kNone);
    flat_bits_.assign(tiles, kMixed);
    flat_first_.assign(tiles, 0);
    pool.parallel_for(
        tiles,
        [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t k = begin; k < end; ++k) {
                std::uint32_t first = kNone, bits = kNone, count = 0;
                bool one_side = true;
                each_leaf(k, k + 1, [&](std::uint32_t leaf, glm::uvec2, std::uint32_t b) {
                    if (first == kNone) first = leaf, bits = b;
                    one_side &= b == bits;
                    ++count;
                });
                const std::uint32_t span = t.tile_bits - bits;
                if (first != kNone && one_side && span < 16 && count == 1u << (2 * span)) {
                    flat_bits_[k] = std::uint8_t(bits);
                    flat_first_[k] = first;
                }
            }
        },
        kTileGrain);
}

std::uint32_t FieldQuadtree::build(Arrays& out, glm::uvec2 c, std::uint32_t bits, std::uint32_t floor,
                                   const Limits& limits, std::atomic<std::uint64_t>& leaves) const {
    if (c.x >= t_.lattice.extent_x || c.y >= t_.lattice.extent_y) return kOutside;
    const std::uint64_t side = std::uint64_t(1) << bits;
    // A leaf's diagonal is shorter than the least r over it: known without the table where the
    // parent's least r is already enough (for most leaves), else read from it.
    auto short_enough = [&](std::uint64_t r) { return 2 * (side - 1) * (side - 1) < r * r; };
    std::uint32_t r = floor;
    if (!short_enough(r)) {
        const glm::uvec2 b(std::uint32_t(std::min<std::uint64_t>(c.x + side - 1, t_.lattice.extent_x - 1)),
                           std::uint32_t(std::min<std::uint64_t>(c.y + side - 1, t_.lattice.extent_y - 1)));
        r = t_.min_over(c, b);
    }
    if (short_enough(r)) {
        // Counted in batches: one shared counter per leaf costs more than the build on many cores.
        if (++out.uncounted == kLeafBatch) count_leaves(out, limits, leaves);
        out.depth = std::max(out.depth, t_.tile_bits - bits);
        return kLeaf | out.leaves++;
    }
    const std::uint32_t first = std::uint32_t(out.nodes.size());
    out.nodes.resize(out.nodes.size() + 4);
    const std::uint32_t half = 1u << (bits - 1);
    for (std::uint32_t k = 0; k < 4; ++k) {
        const std::uint32_t child =
            build(out, {c.x + (k & 1) * half, c.y + (k >> 1) * half}, bits - 1, r, limits, leaves);
        out.nodes[first + k] = child;
    }
    return first;
}

void FieldQuadtree::count_leaves(Arrays& out, const Limits& limits, std::atomic<std::uint64_t>& leaves) {
    // Leaf indices fit the node word's index bits. Every leaf is counted by the end of its chunk,
    // so the run fails exactly when the leaves pass the limit, whatever the threads.
    const std::uint64_t n = std::exchange(out.uncounted, 0);
    if (leaves.fetch_add(n, std::memory_order_relaxed) + n > limits.leaves)
        throw Error(fmt::format(
            "the field needs more than {} base cells, past {}", limits.leaves,
            limits.leaves == limits.memory ? "the memory this machine allows" : "the quadtree's 29-bit leaf index"));
}

void FieldQuadtree::set_sample(std::uint32_t leaf, glm::uvec2 p, std::uint32_t s) {
    sample_[leaf] = s;
    mark(p, kOccupied | kFresh, true);
}

void FieldQuadtree::mark(glm::uvec2 c, std::uint32_t flag, bool on) {
    // A node's flags change by atomic or and and, written only where they change (the nodes near
    // the root are on most paths); its index never changes.
    std::uint32_t* node = &roots_[std::size_t(c.y >> t_.tile_bits) * t_.tiles_x + (c.x >> t_.tile_bits)];
    for (std::uint32_t bits = t_.tile_bits;; --bits) {
        std::atomic_ref<std::uint32_t> word(*node);
        const std::uint32_t w = word.load(std::memory_order_relaxed);
        if (on && (w & flag) != flag) word.fetch_or(flag, std::memory_order_relaxed);
        if (!on && (w & flag) != 0) word.fetch_and(~flag, std::memory_order_relaxed);
        if (w & kLeaf) return;
        node = &nodes_[(w & kIndex) + shared::field_child_of(c, bits)];
    }
}

}  // namespace vrpd::detail
