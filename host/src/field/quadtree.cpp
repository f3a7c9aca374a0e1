// The quadtree of a sizing field's base cells (quadtree.h): its leaves and the marks on its nodes.
#include <algorithm>

#include <fmt/format.h>

#include "quadtree.h"
#include "vrpd/vrpd.h"

namespace vrpd::detail {

FieldQuadtree::FieldQuadtree(const FieldTable& t, std::uint64_t max_leaves) : t_(t) {
    roots_.resize(std::size_t(t.tiles_x) * t.tiles_y);
    for (std::uint32_t j = 0; j < t.tiles_y; ++j)
        for (std::uint32_t i = 0; i < t.tiles_x; ++i)
            roots_[std::size_t(j) * t.tiles_x + i] =
                build({i << t.tile_bits, j << t.tile_bits}, t.tile_bits, max_leaves);
    // The arrays grew by doubling; they keep their size for the whole run.
    nodes_.shrink_to_fit();
    corner_.shrink_to_fit();
    bits_.shrink_to_fit();
    sample_.assign(corner_.size(), kNone);
}

std::uint32_t FieldQuadtree::build(glm::uvec2 c, std::uint32_t bits, std::uint64_t max_leaves) {
    if (c.x >= t_.lattice.extent_x || c.y >= t_.lattice.extent_y) return kOutside;
    const std::uint64_t side = std::uint64_t(1) << bits;
    const glm::uvec2 b(std::uint32_t(std::min<std::uint64_t>(c.x + side - 1, t_.lattice.extent_x - 1)),
                       std::uint32_t(std::min<std::uint64_t>(c.y + side - 1, t_.lattice.extent_y - 1)));
    const std::uint64_t r = t_.min_over(c, b);
    if (2 * (side - 1) * (side - 1) < r * r) {
        // Leaf indices fit the node word's index bits.
        if (const std::uint64_t most = std::min<std::uint64_t>(max_leaves, kIndex); corner_.size() >= most)
            throw Error(fmt::format("the field needs more than {} base cells, past {}", most,
                                    most == max_leaves ? "the memory this machine allows"
                                                       : "the quadtree's 29-bit leaf index"));
        depth_ = std::max(depth_, t_.tile_bits - bits);
        corner_.push_back(c);
        bits_.push_back(std::uint8_t(bits));
        return kLeaf | std::uint32_t(corner_.size() - 1);
    }
    const std::uint32_t first = std::uint32_t(nodes_.size());
    nodes_.resize(nodes_.size() + 4);
    const std::uint32_t half = 1u << (bits - 1);
    for (std::uint32_t k = 0; k < 4; ++k) {
        const std::uint32_t child = build({c.x + (k & 1) * half, c.y + (k >> 1) * half}, bits - 1, max_leaves);
        nodes_[first + k] = child;
    }
    return first;
}

void FieldQuadtree::set_sample(std::uint32_t leaf, std::uint32_t s) {
    sample_[leaf] = s;
    mark(corner_[leaf], kOccupied | kFresh, true);
}

void FieldQuadtree::mark(glm::uvec2 c, std::uint32_t flag, bool on) {
    std::uint32_t* node = &roots_[std::size_t(c.y >> t_.tile_bits) * t_.tiles_x + (c.x >> t_.tile_bits)];
    for (std::uint32_t bits = t_.tile_bits;; --bits) {
        *node = on ? *node | flag : *node & ~flag;
        if (*node & kLeaf) return;
        const std::uint32_t k = ((c.x >> (bits - 1)) & 1) | ((c.y >> (bits - 1)) & 1) << 1;
        node = &nodes_[(*node & kIndex) + k];
    }
}

}  // namespace vrpd::detail
