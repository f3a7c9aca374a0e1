// Mask mode (one radius, quadtree levels 0 to MASK_LEVELS - 1): the active cells live in the
// grid words as masks instead of a list; the darts and samples are the list's, bit for bit.
#ifndef VRPD_MASK_MODE_H
#define VRPD_MASK_MODE_H
#include "bridge.h"
#include "darts.h"
#include "kernels.h"
#include "quadtree.h"
#include "throw.h"

VRPD_BEGIN

// Mask mode (one radius, levels 0 to MASK_LEVELS - 1): there is no list of active cells. The grid
// word of a base cell without a sample holds the mask of its active sub-cells at the current
// level (GRID_MASK_BITS: at most 16 sub-cells, level 2), and the kernels run over base cells.
// Bit k is the sub-cell the explicit list would hold at that place: k's base-4 digits, most
// significant first, are the child indices (child_corner) taken at each level, so the darts,
// their indices and the samples are the explicit mode's, bit for bit. (MASK_LEVELS: kernels.h.)

// Corner of sub-cell k (< 64: MASK_LEVELS levels at most) of side `side` of the base cell at
// `corner`. Digit i of k (from the least significant, the finest level) is child_corner's child
// index at side 2^i side: its low bit moves x by that side, its high bit y, so x gathers k's
// even bits and y its odd bits.
VRPD_FN uvec2 subcell_corner(uvec2 corner, uint k, uint side) {
#ifdef __cplusplus
    // The host reads the two coordinates from a table of k's gathered bits, x in the low nibble.
    static constexpr auto kXy = [] {
        std::array<std::uint8_t, 64> t{};
        for (uint i = 0u; i < 64u; i++)
            t[i] = std::uint8_t((i & 1u) | ((i >> 1u) & 2u) | ((i >> 2u) & 4u) |
                                (((i >> 1u) & 1u) | ((i >> 2u) & 2u) | ((i >> 3u) & 4u)) << 4u);
        return t;
    }();
    uint x = kXy[k] & 15u;
    uint y = uint(kXy[k]) >> 4u;
#else
    uint x = (k & 1u) | ((k >> 1u) & 2u) | ((k >> 2u) & 4u);
    uint y = ((k >> 1u) & 1u) | ((k >> 2u) & 2u) | ((k >> 3u) & 4u);
#endif
    return corner + uvec2(x, y) * side;
}

VRPD_FN bool masked_active(uvec2 w) { return !grid_is_sample(w) && (w.y & GRID_MASK_BITS) != 0u; }

// The loops over a mask's set bits visit them in ascending order (findLSB, then clear the bit),
// each bit once: a loop over every bit position ran each SIMD batch of llvmpipe up to the
// highest bit of any of its lanes.

// Mask mode: the darts of base cell b (word w, active) this round (a.side: the sub-cells' side;
// a.param: exp(-lambda) as in count_darts).
VRPD_FN uint masked_dart_count(CellArgs a, uvec2 w, uint b) {
    uvec2 corner = base_corner(a.domain, b);
    uint count = 0u;
    for (uint mask = w.y & GRID_MASK_BITS; mask != 0u; mask &= mask - 1u) {
        uvec2 cc = subcell_corner(corner, uint(findLSB(mask)), a.side);
        count += dart_count(cell_stream(a.round_key, cc), a.param);
    }
    return count;
}

// A base cell's word with its new mask of active sub-cells (a sample's word stays).
VRPD_FN uvec2 masked_word(uvec2 w, uint mask) { return grid_is_sample(w) ? w : uvec2(GRID_EMPTY, mask); }

// Mask mode: an active word with its round's dart count (< 2^16; the engines check), then with
// the index of its first dart: a packed darts word (domain.h).
VRPD_FN uvec2 counted_word(uvec2 w, uint count) { return uvec2(w.x, (count << 16u) | (w.y & GRID_MASK_BITS)); }
VRPD_FN uvec2 numbered_word(uvec2 w, uint first) { return uvec2(GRID_TAG | GRID_PACKED | first, w.y); }

#ifdef __cplusplus
// Mask mode, the host's count pass over base cells [b, e): each active word gets its round's dart
// count (counted_word), masked_dart_count's sum, with the sub-cells (up to 16 a base cell) of
// kBatch base cells at a time counted together by cell_dart_counts. With `masks` (the last
// refinement's, refine_masked_base's .x), each word first takes its new mask (masked_word).
// Returns the range's darts; sets `crowded` if a base cell got more than a word holds.
inline uint64_t count_masked_range(CellArgs a, uvec2* words, const uint* masks, uint b, uint e, bool& crowded) {
    constexpr uint kBatch = 64u;
    std::array<uvec2, kBatch * 16u> corners;
    std::array<uint, kBatch * 16u> counts;
    std::array<std::uint8_t, kBatch> subcells;  // each base cell's, none if it is not active
    uint64_t sum = 0u;
    for (uint i = b; i < e;) {
        uint end = e - i < kBatch ? e : i + kBatch;
        uint n = 0u;
        const uint base_side = 1u << a.domain.cell_bits, row_end = a.domain.cells_x << a.domain.cell_bits;
        uvec2 corner = base_corner(a.domain, i);
        for (uint j = i; j < end; j++) {
            uvec2 w = words[j];
            if (masks != nullptr) words[j] = w = masked_word(w, masks[j]);
            uint m = 0u;
            if (a.side == base_side) {  // level 0: an active base cell is its one sub-cell
                corners[n] = corner;
                m = masked_active(w) ? 1u : 0u;
            } else {
                for (uint mask = masked_active(w) ? w.y & GRID_MASK_BITS : 0u; mask != 0u; mask &= mask - 1u)
                    corners[n + m++] = subcell_corner(corner, uint(findLSB(mask)), a.side);
            }
            subcells[j - i] = std::uint8_t(m);
            n += m;
            corner.x += base_side;
            if (corner.x == row_end) corner = uvec2(0u, corner.y + base_side);
        }
        cell_dart_counts(a.round_key, corners.data(), n, a.param, counts.data());
        n = 0u;
        for (uint j = i; j < end; j++) {
            if (subcells[j - i] == 0u) continue;
            uint count = 0u;
            for (uint k = subcells[j - i]; k > 0u; k--) count += counts[n++];
            crowded = crowded || count > GRID_MASK_BITS;
            words[j] = counted_word(words[j], count);
            sum += count;
        }
        i = end;
    }
    return sum;
}
#endif

// Mask mode, the host's throw: writes the darts of base cell b, from `first` on, in the order of
// its sub-cells, each rejected if it lies in the disk of a sample of an earlier round (as
// throw_base_cell; no_samples as throw_cell's). Returns how many are still undecided.
VRPD_FN uint throw_masked_base(VRPD_IN(CellArgs) a, Darts darts, Grid grid, uint b, uint first, bool no_samples) {
    uvec2 w = grid.word[b];
    uvec2 base = uvec2(b % a.domain.cells_x, b / a.domain.cells_x);
    Domain dom = local_domain(a.domain, base);
    uvec2 corner = base_corner(a.domain, b);
    uint j = first;
    uint end = grid_darts(w).y;
    uint undecided = 0u;
    StateBits states = no_state_bits(first);
    // The sub-cells' counts sum to the word's (masked_dart_count): the last sub-cell with darts
    // takes what is left, uncounted, and once none is left the rest have none. At level 0, where
    // a base cell is one sub-cell, no count is drawn twice.
    for (uint mask = w.y & GRID_MASK_BITS; mask != 0u && j < end; mask &= mask - 1u) {
        uvec2 cc = subcell_corner(corner, uint(findLSB(mask)), a.side);
        uint stream = cell_stream(a.round_key, cc);
        uint count = (mask & (mask - 1u)) == 0u ? end - j : dart_count(stream, a.param);
        throw_cell(dom, grid, base, darts, stream, cc, a.side, j, count, states, undecided, no_samples);
        j += count;
    }
    or_dart_states(darts, states.word, states.bits);
    return undecided;
}

// Mask mode: the sites of base cell b's darts (word w, numbered from `first` on) for the device's
// throw_sited (throw.h), in throw_masked_base's order and counts.
VRPD_FN void site_masked_darts(CellArgs a, Darts darts, uvec2 w, uint b, uint first) {
    uvec2 corner = base_corner(a.domain, b);
    uint j = first;
    uint end = first + packed_dart_count(w);
    for (uint mask = w.y & GRID_MASK_BITS; mask != 0u && j < end; mask &= mask - 1u) {
        uvec2 cc = subcell_corner(corner, uint(findLSB(mask)), a.side);
        uint count = (mask & (mask - 1u)) == 0u ? end - j : dart_count(cell_stream(a.round_key, cc), a.param);
        for (uint i = 0u; i < count; i++) write_site(darts, j + i, cc, i);
        j += count;
    }
}

#ifdef VRPD_HOST_AVX2
// The host's body of refine_masked_base where the sub-cells split and vector_refinement holds:
// the gather (window_gather), then each active sub-cell's children tested as
// uncovered_children tests them (inner_child_boxes). `centre` is the base cell's grid word, at
// `corner`; `side` the children's.
[[gnu::target("avx2")]] inline uvec2 refine_masked_inner(Domain dom, const uvec2* centre, uvec2 corner, uint mask,
                                                         uint side) {
    ivec2 at[MAX_CELL_SAMPLES];
    uint samples = window_gather(centre, int(dom.cells_x), cover_reach(dom.radii), corner, 1 << dom.cell_bits,
                                 dom.radii.coverage2, at);
    uvec2 kept = uvec2(0u, 0u);
    for (; mask != 0u; mask &= mask - 1u) {
        uint k = uint(findLSB(mask));
        ivec2 lo = ivec2(subcell_corner(uvec2(0u, 0u), k, 2u * side));
        uint children = uncovered_children(inner_child_boxes(lo, int(side), 4u), at, samples, dom.radii.coverage2, 15u);
        if (k < 8u)
            kept.x |= children << (4u * k);
        else
            kept.y |= children << (4u * k - 32u);
    }
    return kept;
}
#endif

// Mask mode: the surviving children of base cell b's active sub-cells (a.side: the children's
// side; a.param: 4 children, or 1: the cell itself), sub-cell k's as bits a.param * k + c, up to
// 16 sub-cells: bits 0-31 in .x and 32-63 in .y, so that level 2's sub-cells may split too.
VRPD_FN uvec2 refine_masked_base(VRPD_IN(CellArgs) a, Grid grid, uint b) {
    uvec2 w = grid.word[b];
    uvec2 kept = uvec2(0u, 0u);
    if (grid_is_sample(w) || (w.y & GRID_MASK_BITS) == 0u) return kept;
    uvec2 base = uvec2(b % a.domain.cells_x, b / a.domain.cells_x);
    Domain dom = local_domain(a.domain, base);
    uvec2 corner = base_corner(a.domain, b);
#ifdef VRPD_HOST_AVX2
    if (a.param == 4u && vector_refinement(dom, base))
        return refine_masked_inner(dom, grid.word + b, corner, w.y & GRID_MASK_BITS, a.side);
#endif
    uint samples = cover_tested(dom, a.param, a.side) ? gather_cell_samples(dom, grid, base) : 0u;
    uint parent_side = a.param == 4u ? 2u * a.side : a.side;
    for (uint mask = w.y & GRID_MASK_BITS; mask != 0u; mask &= mask - 1u) {
        uint k = uint(findLSB(mask));
        uvec2 cc = subcell_corner(corner, k, parent_side);
        uint children = surviving_children(dom, grid, base, cc, a.side, a.param, samples);
        uint bit = a.param * k;
        if (bit < 32u) kept.x |= children << bit;
        else kept.y |= children << (bit - 32u);
    }
    return kept;
}

// Mask mode's scattered refinement, one radius, where cells split into 4 or 16 sub-cells (not
// the last mask level's): a sample clears the children its disk covers from the masks of the
// base cells around it, instead of each base cell gathering the samples around it. The first
// refinement keeps about three active base cells a sample, so a pass over the samples does a
// fraction of the gathers' work; the masks are refine_masked_base's, bit for bit. It serves the
// base cells of a box of the grid (none where x0 > x1): those whose window neither wraps nor
// meets a free boundary and that lie whole on the lattice, so that no child is clipped and every
// sample that can cover a child lies at a straight offset within cover_reach.
struct ScatterBox {
    int x0;
    int y0;
    int x1;
    int y1;
};

VRPD_FN ScatterBox scatter_box(Domain dom, uint side, uint fanout) {
    ScatterBox none = ScatterBox(0, 0, -1, -1);
    if (fanout != 4u || masked_leaves(dom, side, fanout) || two_radii(dom.radii) ||
        cover_reach(dom.radii) > int(MAX_REACH) || (dom.lattice.periodic != 0u && !straight_inner_cells(dom)))
        return none;
    int inner = int(influence_reach(dom.radii));
    return ScatterBox(inner, inner, min(int(dom.cells_x) - 1 - inner, int(dom.lattice.extent_x >> dom.cell_bits) - 1),
                      min(int(dom.cells_y) - 1 - inner, int(dom.lattice.extent_y >> dom.cell_bits) - 1));
}

VRPD_FN bool box_holds(ScatterBox box, int x, int y) {
    return x >= box.x0 && x <= box.x1 && y >= box.y0 && y <= box.y1;
}
VRPD_FN bool box_any(ScatterBox box) { return box.x0 <= box.x1 && box.y0 <= box.y1; }

// The base cells outside a box that holds some (its border), which the device's scattered
// refinement gathers for alone: their count, and the i-th of them in base cell order (the rows
// above the box, then each box row's cells left and right of it, then the rows below).
VRPD_FN uint border_count(Domain dom, ScatterBox box) {
    return dom.cells_x * dom.cells_y - uint(box.x1 - box.x0 + 1) * uint(box.y1 - box.y0 + 1);
}

VRPD_FN uint border_base(Domain dom, ScatterBox box, uint i) {
    uint above = uint(box.y0) * dom.cells_x;
    if (i < above) return i;
    uint width = uint(box.x1 - box.x0 + 1), beside = dom.cells_x - width;
    uint rows = uint(box.y1 - box.y0 + 1);
    i -= above;
    if (i >= rows * beside) return (uint(box.y1) + 1u) * dom.cells_x + (i - rows * beside);
    uint row = i / beside, k = i % beside;
    return (uint(box.y0) + row) * dom.cells_x + (k < uint(box.x0) ? k : k + width);
}

// A boxed base cell's mask before the samples' covers: every child of its active sub-cells, at
// most level 1's four (the children of sub-cell k are sub-cells 4 k to 4 k + 3; at level 0 the
// base cell is sub-cell 0): bit k moves to bit 4 k, and times 15 fills its four.
VRPD_FN uint all_children(uvec2 w) {
    uint m = masked_active(w) ? w.y & 15u : 0u;
    return ((m & 1u) | (m & 2u) << 3u | (m & 4u) << 6u | (m & 8u) << 9u) * 15u;
}

// far2's gaps from offset o to the rows (or columns) of a base cell's children of side h, 2 or 4
// a side (`four`); past the children the gap `none` (Rc²), which covers nothing. Plain fields,
// not an array: llvmpipe keeps a lane's arrays in memory.
struct ChildGaps {
    uint64_t g0;
    uint64_t g1;
    uint64_t g2;
    uint64_t g3;
};

VRPD_FN ChildGaps child_gaps(int o, int h, bool four, uint64_t none) {
    return ChildGaps(far2(o, 0, h - 1), far2(o, h, 2 * h - 1), four ? far2(o, 2 * h, 3 * h - 1) : none,
                     four ? far2(o, 3 * h, 4 * h - 1) : none);
}

VRPD_FN uint64_t least_gap(ChildGaps g) { return min(min(g.g0, g.g1), min(g.g2, g.g3)); }

// A base cell's children given row by row, column ix of row iy at bit 4 iy + ix, as mask bits:
// sub-cell k's even bits are x's and its odd bits y's (subcell_corner's numbering).
VRPD_FN uint children_of_rows(uint rows) {
    return (rows & 0x0303u) | (rows & 0x0C0Cu) << 2u | (rows & 0x3030u) >> 2u | (rows & 0xC0C0u);
}

// The columns of a row of children (y gap gy) that a disk at x gaps gx covers wholly, bit ix.
VRPD_FN uint row_covered(Radii r, uint64_t gy, ChildGaps gx) {
    return (covers(r, gy + gx.g0) ? 1u : 0u) | (covers(r, gy + gx.g1) ? 2u : 0u) | (covers(r, gy + gx.g2) ? 4u : 0u) |
           (covers(r, gy + gx.g3) ? 8u : 0u);
}

// Clears from the masks of the boxed base cells around sample p the children (side `side`, 2 or 4
// a side) that its disk covers wholly: the exact corner test of cover_children, a child's
// farthest point strictly within Rc, from the gaps along each axis to the children's rows and
// columns.
VRPD_FN void scatter_cover(Domain dom, ScatterBox box, uint side, uvec2 p, Uints masks) {
    int reach = cover_reach(dom.radii);
    int base_side = 1 << dom.cell_bits;
    bool four = uint(base_side) / side == 4u;
    int h = int(side);
    uvec2 s = base_cell_of(dom, p);
    int px = int(p.x & uint(base_side - 1)), py = int(p.y & uint(base_side - 1));
    for (int dy = -reach; dy <= reach; dy++) {
        int y = int(s.y) + dy;
        if (y < box.y0 || y > box.y1) continue;
        ChildGaps gy = child_gaps(py - dy * base_side, h, four, dom.radii.coverage2);
        uint64_t nearest_y = least_gap(gy);
        if (!covers(dom.radii, nearest_y)) continue;
        for (int dx = -reach; dx <= reach; dx++) {
            int x = int(s.x) + dx;
            if (x < box.x0 || x > box.x1) continue;
            ChildGaps gx = child_gaps(px - dx * base_side, h, four, dom.radii.coverage2);
            if (!covers(dom.radii, nearest_y + least_gap(gx))) continue;
            uint covered =
                children_of_rows(row_covered(dom.radii, gy.g0, gx) | row_covered(dom.radii, gy.g1, gx) << 4u |
                                 row_covered(dom.radii, gy.g2, gx) << 8u | row_covered(dom.radii, gy.g3, gx) << 12u);
            if (covered != 0u) and_mask(masks, uint(y) * dom.cells_x + uint(x), ~covered);
        }
    }
}

#ifdef VRPD_HOST_AVX2
inline constexpr int kScatterWidth = 2 * int(MAX_REACH) + 1;

// A sample's squared farthest gaps, per axis, to the children's intervals (N a side, side h) of
// the base cells d - reach cells away, d in [0, 2 reach]; and the d where some child's gap is
// below the limit, [x0, x1] along x and [y0, y1] along y (none beyond can hold a covered child).
template <uint N>
struct ScatterGaps {
    alignas(32) int64_t x[kScatterWidth][4], y[kScatterWidth][4];  // 4 a row for the vector loads
    int x0 = kScatterWidth, x1 = -1, y0 = kScatterWidth, y1 = -1;
};

// The host's scatter_cover on processors with AVX2: a base cell's gaps along x and y in one
// vector, and a row of children's gaps compared with the room a row's y gap leaves at once.
template <uint N>
[[gnu::target("avx2")]] inline void scatter_cover_avx2(const Domain& dom, const ScatterBox& box, uint h, uvec2 p,
                                                       bool fast, uint* masks) {
    const int64_t limit = int64_t(dom.radii.coverage2);
    const int reach = cover_reach(dom.radii), side = 1 << dom.cell_bits;
    const int px = int(p.x & uint(side - 1)), py = int(p.y & uint(side - 1));
    const int step = int(h);
    // Lanes 0-3: the children's intervals along x, 4-7 along y (with N = 2, lanes 2, 3, 6 and 7
    // lie past the cell and are not read).
    const __m256i lo = _mm256_setr_epi32(0, step, 2 * step, 3 * step, 0, step, 2 * step, 3 * step);
    const __m256i hi = _mm256_add_epi32(lo, _mm256_set1_epi32(step - 1));
    const __m256i bound = _mm256_set1_epi64x(limit);
    const int lanes = (1 << N) - 1;
    ScatterGaps<N> g;
    for (int d = 0; d <= 2 * reach; ++d) {
        const int ox = px - (d - reach) * side, oy = py - (d - reach) * side;
        const __m256i o = _mm256_setr_epi32(ox, ox, ox, ox, oy, oy, oy, oy);
        const __m256i f = _mm256_max_epi32(_mm256_sub_epi32(o, lo), _mm256_sub_epi32(hi, o));
        const __m256i odd = _mm256_srli_epi64(f, 32);
        const __m256i even2 = _mm256_mul_epi32(f, f), odd2 = _mm256_mul_epi32(odd, odd);  // x0 x2 y0 y2, x1 x3 y1 y3
        const __m256i low = _mm256_unpacklo_epi64(even2, odd2), high = _mm256_unpackhi_epi64(even2, odd2);
        const __m256i gx = _mm256_permute2x128_si256(low, high, 0x20), gy = _mm256_permute2x128_si256(low, high, 0x31);
        _mm256_store_si256(reinterpret_cast<__m256i*>(g.x[d]), gx);
        _mm256_store_si256(reinterpret_cast<__m256i*>(g.y[d]), gy);
        if ((_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpgt_epi64(bound, gx))) & lanes) != 0)
            g.x0 = std::min(g.x0, d), g.x1 = d;
        if ((_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpgt_epi64(bound, gy))) & lanes) != 0)
            g.y0 = std::min(g.y0, d), g.y1 = d;
    }
    // The base cells within the gaps' ranges, the box's alone unless `fast` (all of them are).
    const uvec2 s = base_cell_of(dom, p);
    for (int dy = g.y0; dy <= g.y1; ++dy) {
        const int y = int(s.y) + dy - reach;
        if (!fast && (y < box.y0 || y > box.y1)) continue;
        uint* row = masks + std::size_t(y) * dom.cells_x;
        __m256i room[N];
        for (uint iy = 0u; iy < N; ++iy) room[iy] = _mm256_set1_epi64x(limit - g.y[dy][iy]);
        for (int dx = g.x0; dx <= g.x1; ++dx) {
            const int x = int(s.x) + dx - reach;
            if (!fast && !box_holds(box, x, y)) continue;
            const __m256i gx = _mm256_load_si256(reinterpret_cast<const __m256i*>(g.x[dx]));
            uint rows = 0u;
            for (uint iy = 0u; iy < N; ++iy)
                rows |= uint(_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpgt_epi64(room[iy], gx))) & lanes)
                        << (4u * iy);
            const uint covered = children_of_rows(rows);
            row[x] &= ~covered;
        }
    }
}
#endif

// The number of sub-cells in a mask of refine_masked_base.
VRPD_FN uint subcell_count(uvec2 kept) { return uint(bitCount(kept.x) + bitCount(kept.y)); }

// Writes the children in `kept` (refine_masked_base, children of side `side`) of base cell b to
// an explicit active list, from `rank` on, in the explicit list's order.
VRPD_FN void scatter_subcells(Domain dom, Cells cells_out, uint rank, uvec2 kept, uint b, uint side) {
    uvec2 corner = base_corner(dom, b);
    for (uint bits = kept.x; bits != 0u; bits &= bits - 1u)
        cells_out.cell[rank++] = subcell_corner(corner, uint(findLSB(bits)), side);
    for (uint bits = kept.y; bits != 0u; bits &= bits - 1u)
        cells_out.cell[rank++] = subcell_corner(corner, uint(findLSB(bits)) + 32u, side);
}

VRPD_END
#endif
