// The base cells of a sizing-field run: a quadtree under each tile whose leaves follow the local
// radius (a leaf's diagonal is shorter than the least r over it, so it holds at most one sample,
// which covers it under every rule), and the neighbour search over them.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "table.h"

namespace vrpd::detail {

class FieldQuadtree {
public:
    static constexpr std::uint32_t kNone = UINT32_MAX;

    // Throws Error if the leaves would pass `max_leaves`.
    FieldQuadtree(const FieldTable& table, std::uint64_t max_leaves);

    std::size_t leaves() const { return corner_.size(); }
    glm::uvec2 corner(std::uint32_t leaf) const { return corner_[leaf]; }
    std::uint32_t bits(std::uint32_t leaf) const { return bits_[leaf]; }
    std::uint32_t sample(std::uint32_t leaf) const { return sample_[leaf]; }
    void set_sample(std::uint32_t leaf, std::uint32_t s) { sample_[leaf] = s; }
    std::uint32_t depth() const { return depth_; }
    std::uint64_t bytes() const { return nodes_.capacity() * 4 + corner_.capacity() * 13 + roots_.capacity() * 4; }

    // Calls visit(leaf) for each leaf that may hold a point within `reach` of some lattice point
    // of [a, b] (inclusive); on a torus, of any of its images, until a call returns true. Leaves
    // past the reach are skipped by their rectangle's gap to [a, b]; the nearer children of a
    // node go first, so that a search for any one hit ends early.
    template <typename Visit>
    bool near(glm::uvec2 a, glm::uvec2 b, std::uint64_t reach, Visit&& visit) const;

private:
    std::uint32_t build(glm::uvec2 corner, std::uint32_t bits, std::uint64_t max_leaves);

    const FieldTable& t_;
    std::vector<std::uint32_t> roots_, nodes_;  // a node: kLeaf | leaf, kOutside, or its first child
    std::vector<glm::uvec2> corner_;
    std::vector<std::uint8_t> bits_;
    std::vector<std::uint32_t> sample_;
    std::uint32_t depth_ = 0;

    static constexpr std::uint32_t kLeaf = 0x80000000u;
    static constexpr std::uint32_t kOutside = 0xFFFFFFFFu;
    template <typename Visit>
    bool descend(std::uint32_t node, std::int64_t ox, std::int64_t oy, std::uint32_t bits, const std::int64_t q[4],
                 bool all_x, bool all_y, std::uint64_t reach2, Visit& visit) const;
};

template <typename Visit>
bool FieldQuadtree::descend(std::uint32_t node, std::int64_t ox, std::int64_t oy, std::uint32_t bits,
                            const std::int64_t q[4], bool all_x, bool all_y, std::uint64_t reach2,
                            Visit& visit) const {
    if (node == kOutside) return false;
    const std::int64_t side = std::int64_t(1) << bits;
    auto gap = [](std::int64_t lo, std::int64_t hi, std::int64_t a, std::int64_t b) {
        return lo > b ? lo - b : (a > hi ? a - hi : 0);
    };
    const std::uint64_t gx = all_x ? 0 : std::uint64_t(gap(ox, ox + side - 1, q[0], q[2]));
    const std::uint64_t gy = all_y ? 0 : std::uint64_t(gap(oy, oy + side - 1, q[1], q[3]));
    if (gx * gx + gy * gy > reach2) return false;
    if (node & kLeaf) return visit(node & ~kLeaf);
    std::int64_t half = side / 2;
    // While the query and its reach lie within one child, go down to it without testing the others.
    while (!all_x && !all_y && !(node & kLeaf) && half > 0) {
        const std::int64_t r = std::int64_t(std::sqrt(double(reach2))) + 1;
        const bool right = q[0] - r >= ox + half, left = q[2] + r < ox + half;
        const bool top = q[1] - r >= oy + half, bottom = q[3] + r < oy + half;
        if (!(right || left) || !(top || bottom)) break;
        const std::uint32_t c = std::uint32_t(right) | std::uint32_t(top) << 1;
        node = nodes_[node + c];
        if (node == kOutside) return false;
        ox += (c & 1) * half;
        oy += (c >> 1) * half;
        half /= 2;
    }
    if (node & kLeaf) return visit(node & ~kLeaf);
    // The child holding the query's middle first, then its row neighbour, column neighbour, diagonal.
    const std::uint32_t first = std::uint32_t((q[0] + q[2]) / 2 >= ox + half) | std::uint32_t((q[1] + q[3]) / 2 >= oy + half) << 1;
    for (std::uint32_t k = 0; k < 4; ++k) {
        const std::uint32_t c = first ^ k;
        if (descend(nodes_[node + c], ox + (c & 1) * half, oy + (c >> 1) * half, std::uint32_t(std::countr_zero(std::uint64_t(half))), q, all_x, all_y, reach2,
                    visit))
            return true;
    }
    return false;
}

template <typename Visit>
bool FieldQuadtree::near(glm::uvec2 a, glm::uvec2 b, std::uint64_t reach, Visit&& visit) const {
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
            lo[k] = from >= 0 ? from / tile : -((-from + tile - 1) / tile);
            hi[k] = to / tile;
        } else {
            lo[k] = std::max<std::int64_t>(0, from) / tile;
            hi[k] = std::min(tiles[k] - 1, std::max<std::int64_t>(0, to) / tile);
            if (to < 0) return false;
        }
    }
    const std::uint64_t reach2 = reach * reach;
    for (std::int64_t ty = lo[1]; ty <= hi[1]; ++ty)
        for (std::int64_t tx = lo[0]; tx <= hi[0]; ++tx) {
            const std::int64_t wx = ((tx % tiles[0]) + tiles[0]) % tiles[0], wy = ((ty % tiles[1]) + tiles[1]) % tiles[1];
            if (descend(roots_[std::size_t(wy * tiles[0] + wx)], tx * tile, ty * tile, t_.tile_bits, q, all[0],
                        all[1], reach2, visit))
                return true;
        }
    return false;
}

}  // namespace vrpd::detail
