// Refinement of the flat quadtree (Ebeida et al. 2012): after a level's rounds, each active cell
// keeps the children (or, between the rounds of a level, itself) that may still hold uncovered
// points; a child one disk covers wholly is dropped (exact corner test), and with two radii a
// child no single disk covers is tested exactly for U.
#ifndef VRPD_QUADTREE_H
#define VRPD_QUADTREE_H
#include "bridge.h"
#include "active_cells.h"
#include "cover.h"
#include "kernels.h"
#include "t_membership.h"

VRPD_BEGIN

// The children of one active cell as closed lattice intervals, as offsets from the base cell's
// corner: x in [lo0.x, hi0.x] or [lo1.x, hi1.x], the same in y. A second child off a free
// boundary (dropped already) repeats the first's intervals.
struct ChildBoxes {
    ivec2 lo0;
    ivec2 hi0;
    ivec2 lo1;
    ivec2 hi1;
};

// Clears from `mask` the children that the disk of the sample at offset o covers wholly (exact
// corner test), and from `open_corners` (two radii) the corners of the children it covers: the
// 3 x 3 corners of four children, or of a cell that does not split (fanout 1) its corners, its
// edges' midpoints and its centre.
VRPD_FN void cover_children(Domain dom, ChildBoxes b, uint fanout, ivec2 o, VRPD_INOUT(uint) mask,
                            VRPD_INOUT(uint) open_corners) {
    uint64_t fx0 = far2(o.x, b.lo0.x, b.hi0.x);
    uint64_t fy0 = far2(o.y, b.lo0.y, b.hi0.y);
    if (covers(dom.radii, fx0 + fy0)) mask &= ~1u;
    if (fanout == 4u) {
        uint64_t fx1 = far2(o.x, b.lo1.x, b.hi1.x);
        uint64_t fy1 = far2(o.y, b.lo1.y, b.hi1.y);
        if (covers(dom.radii, fx1 + fy0)) mask &= ~2u;
        if (covers(dom.radii, fx0 + fy1)) mask &= ~4u;
        if (covers(dom.radii, fx1 + fy1)) mask &= ~8u;
    }
#ifndef VRPD_ONE_RADIUS
    if (open_corners != 0u && two_radii(dom.radii)) {
        uint64_t gx[3];
        uint64_t gy[3];
        gx[0] = square_gap(o.x, b.lo0.x);
        gx[1] = square_gap(o.x, b.hi0.x);
        gx[2] = square_gap(o.x, fanout == 4u ? b.hi1.x : (b.lo0.x + b.hi0.x) / 2);
        gy[0] = square_gap(o.y, b.lo0.y);
        gy[1] = square_gap(o.y, b.hi0.y);
        gy[2] = square_gap(o.y, fanout == 4u ? b.hi1.y : (b.lo0.y + b.hi0.y) / 2);
        for (uint k = 0u; k < 9u; k++)
            if (covers(dom.radii, gx[k % 3u] + gy[k / 3u])) open_corners &= ~(1u << k);
    }
#endif
}

#ifdef VRPD_HOST_AVX2
// The host's body of cover_children for one radius over `count` gathered samples, on processors
// with AVX2: four samples a step, each lane's farthest gaps to the children's intervals along
// x and y (far2's) in 32 bits, the four corners' squared distances in 64; ends once no child is
// left. Returns `mask` less the children some sample covers wholly.
[[gnu::target("avx2")]] inline uint uncovered_children(ChildBoxes b, const ivec2* at, uint count, uint64_t limit2,
                                                       uint mask) {
    auto pair = [](ivec2 v) { return int64_t(uint64_t(uint(v.y)) << 32 | uint(v.x)); };
    const __m256i lo0 = _mm256_set1_epi64x(pair(b.lo0)), hi0 = _mm256_set1_epi64x(pair(b.hi0));
    const __m256i lo1 = _mm256_set1_epi64x(pair(b.lo1)), hi1 = _mm256_set1_epi64x(pair(b.hi1));
    const __m256i limit = _mm256_set1_epi64x(int64_t(limit2));
    const __m256i lane = _mm256_setr_epi64x(0, 1, 2, 3);
    for (uint k = 0u; k < count && mask != 0u; k += 4u) {
        const __m256i valid = _mm256_cmpgt_epi64(_mm256_set1_epi64x(int64_t(count - k)), lane);
        const __m256i o = _mm256_maskload_epi64(reinterpret_cast<const long long*>(at + k), valid);
        const __m256i f0 = _mm256_max_epi32(_mm256_sub_epi32(o, lo0), _mm256_sub_epi32(hi0, o));
        const __m256i f1 = _mm256_max_epi32(_mm256_sub_epi32(o, lo1), _mm256_sub_epi32(hi1, o));
        const __m256i f0_y = _mm256_srli_epi64(f0, 32), f1_y = _mm256_srli_epi64(f1, 32);
        const __m256i x0 = _mm256_mul_epi32(f0, f0), x1 = _mm256_mul_epi32(f1, f1);
        const __m256i y0 = _mm256_mul_epi32(f0_y, f0_y), y1 = _mm256_mul_epi32(f1_y, f1_y);
        const int lanes = _mm256_movemask_pd(_mm256_castsi256_pd(valid));
        const __m256i corner2[4] = {_mm256_add_epi64(x0, y0), _mm256_add_epi64(x1, y0), _mm256_add_epi64(x0, y1),
                                    _mm256_add_epi64(x1, y1)};
        for (uint c = 0u; c < 4u; c++)
            if ((_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpgt_epi64(limit, corner2[c]))) & lanes) != 0)
                mask &= ~(1u << c);
    }
    return mask;
}
#endif

// Does refinement into `fanout` children of side `side` test which of them disks cover? When
// cells split (fanout 4), and at the deepest level (side 1), where that test is what ends the
// run. Between the rounds of a coarser level (fanout 1), one radius keeps every cell whose base
// cell holds no sample, covered or not: the next round's darts in a covered cell are rejected at
// throw by the same sample scan that the cover test would have run for every cell, and only the
// darts are random, so the samples are the same, for less work (docs/performance.md). Two radii
// test: their active cells also say which base cells get darts, and each T test costs far more
// than a scan.
VRPD_FN bool cover_tested(Domain dom, uint fanout, uint side) {
    return fanout == 4u || side == 1u || two_radii(dom.radii);
}

// Two radii: do the open disks of cell_sample_at[0, samples) (offsets from the base cell's corner)
// cover the closed box [lo, hi], each of its quarters by one disk, or else each quarter of that
// quarter by one? Then no point of the box lies in U, as the exact test (t_membership.h) would
// find at many times the cost: most cells that a union of disks covers are covered so, and only
// the quarters that a boundary between two disks crosses need their own quarters.
VRPD_FN bool covered_in_parts(Domain dom, ivec2 lo, ivec2 hi, uint samples) {
    ivec2 mid = lo + (hi - lo) / 2;
    for (int part = 0; part < 4; part++) {
        ivec2 a = ivec2((part & 1) == 0 ? lo.x : mid.x, (part & 2) == 0 ? lo.y : mid.y);
        ivec2 b = ivec2((part & 1) == 0 ? mid.x : hi.x, (part & 2) == 0 ? mid.y : hi.y);
        ivec2 m = a + (b - a) / 2;
        // The quarter itself (-1), then its own quarters while each is covered.
        for (int quarter = -1; quarter < 4; quarter++) {
            ivec2 qa = quarter < 0 ? a : ivec2((quarter & 1) == 0 ? a.x : m.x, (quarter & 2) == 0 ? a.y : m.y);
            ivec2 qb = quarter < 0 ? b : ivec2((quarter & 1) == 0 ? m.x : b.x, (quarter & 2) == 0 ? m.y : b.y);
            bool covered = false;
            for (uint k = 0u; k < samples && !covered; k++)
                covered =
                    covers(dom.radii, far2(cell_sample_at[k].x, qa.x, qb.x) + far2(cell_sample_at[k].y, qa.y, qb.y));
            if (covered && quarter < 0) break;
            if (!covered && quarter >= 0) return false;
        }
    }
    return true;
}

// Which of the `fanout` children (4, or 1: the cell itself) of the active cell at `corner` stay
// active, as a bit mask. A child is dropped if it lies off the domain or (cover_tested) one
// sample's disk covers it wholly (exact corner test, see far2). Children covered only by a union
// of disks stay, and are split until they are single lattice points, where the test is exact.
// A child's x and y intervals are shared in pairs: 2 + 2 far offsets per sample rather than 4
// corner tests.
// `samples` is gather_cell_samples's count for the base cell (past MAX_CELL_SAMPLES: the grid is
// scanned instead).
//
// Two radii: a cell is the closed square [corner, corner + side]^2 (continuous: T's test is), and
// a child that no single disk covers is tested exactly (t_membership.h): it stays iff it still holds
// a point of U. So the cells track U exactly, and vanish as soon as U does. Two cheap tests come
// first: a child with an open corner (or, not splitting, an open midpoint) holds a point of U, and
// one covered_in_parts covers holds none. Should the exact test run past its bounds, the child
// stays; at the deepest level it then falls back to its lattice point.
VRPD_FN uint surviving_children(VRPD_IN(Domain) dom, Grid grid, uvec2 base, uvec2 corner, uint side, uint fanout,
                                uint samples) {
    // Child 0 shares the cell's corner; the others' corners lie side further along x, y or both.
    uint x1 = corner.x + side;
    uint y1 = corner.y + side;
    bool x1_in = fanout == 4u && x1 < dom.lattice.extent_x;
    bool y1_in = fanout == 4u && y1 < dom.lattice.extent_y;
    uint mask =
        !in_lattice(dom.lattice, corner) ? 0u : 1u | (x1_in ? 2u : 0u) | (y1_in ? 4u : 0u) | (x1_in && y1_in ? 8u : 0u);
    if (!cover_tested(dom, fanout, side)) return mask;
    uint pad = two_radii(dom.radii) ? 0u : 1u;  // one radius: the cell's lattice points
    // The children's intervals, as offsets from the base cell's corner (clipped to a free boundary).
    uvec2 origin = uvec2(base.x << dom.cell_bits, base.y << dom.cell_bits);
    ChildBoxes b;
    b.lo0 = ivec2(corner - origin);
    b.hi0 = ivec2(uvec2(clip_hi(x1 - pad, dom.lattice.extent_x, dom.lattice.periodic),
                        clip_hi(y1 - pad, dom.lattice.extent_y, dom.lattice.periodic)) -
                  origin);
    b.lo1 = ivec2(x1_in ? int(x1 - origin.x) : b.lo0.x, y1_in ? int(y1 - origin.y) : b.lo0.y);
    b.hi1 =
        ivec2(x1_in ? int(clip_hi(x1 + side - pad, dom.lattice.extent_x, dom.lattice.periodic) - origin.x) : b.hi0.x,
              y1_in ? int(clip_hi(y1 + side - pad, dom.lattice.extent_y, dom.lattice.periodic) - origin.y) : b.hi0.y);
    // Two radii: bit 3 j + i stays set while no sample covers the lattice point (x_i, y_j) of the
    // 3 x 3 corners of the children (x_0 = lo0.x, x_1 = hi0.x, x_2 = hi1.x): a child with an
    // uncovered corner holds a point of U and stays without the exact test.
    uint open_corners = 0x1FFu;
    if (samples <= MAX_CELL_SAMPLES) {
#ifdef VRPD_HOST_AVX2
        if (!two_radii(dom.radii) && host_has_avx2())
            return uncovered_children(b, cell_sample_at, samples, dom.radii.coverage2, mask);
#endif
        for (uint k = 0u; k < samples && mask != 0u; k++)
            cover_children(dom, b, fanout, cell_sample_at[k], mask, open_corners);
    }
#ifndef VRPD_GATHERED  // a kernel whose tests always gather (refine_masked) leaves the scan out
    else {
        int reach = cover_reach(dom.radii);
        VRPD_FOR_EACH_NEIGHBOUR(dom, base, reach, dom.radii.coverage2, dx, dy, nb) {
            if (mask == 0u) return 0u;
            uvec2 p = grid.word[nb];
            if (grid_is_sample(p)) cover_children(dom, b, fanout, sample_offset(dom, dx, dy, p), mask, open_corners);
        }
    }
#endif
#ifndef VRPD_ONE_RADIUS
    for (uint c = 0u; c < fanout && two_radii(dom.radii); c++) {
        if ((mask & (1u << c)) == 0u) continue;
        uint k = 3u * (c >> 1u) + (c & 1u);
        if ((open_corners & (fanout == 4u ? (3u << k) | (3u << (k + 3u)) : 0x1FFu)) != 0u) continue;
        uvec2 cc = child_corner(corner, side, c);
        ivec2 hi = ivec2(int(side), int(side));
        if (dom.lattice.periodic == 0u)
            hi = min(hi, ivec2(int(dom.lattice.extent_x - 1u - cc.x), int(dom.lattice.extent_y - 1u - cc.y)));
        ivec2 lo = ivec2(cc - origin);
        if (samples <= MAX_CELL_SAMPLES && covered_in_parts(dom, lo, lo + hi, samples)) {
            mask &= ~(1u << c);
            continue;
        }
        uint n = gather_near_box(dom, grid, base, cc, hi);
        if (n > MAX_DISKS) continue;
        uint t = reaches_uncovered(n, dom.radii.coverage2, ivec2(0, 0), hi, false);
        if (t == T_UNKNOWN && side == 1u) t = near_sample(dom, grid, base, cc, COVERAGE) ? T_OUTSIDE : T_INSIDE;
        if (t == T_OUTSIDE) mask &= ~(1u << c);
    }
#endif
    return mask;
}

#ifdef VRPD_HOST_AVX2
// Do the host's vector bodies refine the cells of base cell `base` (one radius)? Where its window
// neither wraps nor meets a free boundary (vector_window) and the base cell lies whole on the
// lattice (a hierarchy's step may keep base cells past a free boundary), so that no child is
// clipped or off the lattice.
inline bool vector_refinement(Domain dom, uvec2 base) {
    return !two_radii(dom.radii) && cover_reach(dom.radii) <= int(MAX_REACH) &&
           ((base.x + 1u) << dom.cell_bits) <= dom.lattice.extent_x &&
           ((base.y + 1u) << dom.cell_bits) <= dom.lattice.extent_y && vector_window(dom, base);
}

// One radius: the intervals of the `fanout` children of side `side` of the cell at offset lo from
// its base cell's corner, where vector_refinement holds: surviving_children's intervals, which no
// boundary clips there.
inline ChildBoxes inner_child_boxes(ivec2 lo, int side, uint fanout) {
    ivec2 lo1 = fanout == 4u ? lo + side : lo;
    return ChildBoxes{lo, lo + side - 1, lo1, lo1 + side - 1};
}

// The host's body of refine_cells_of_base where vector_refinement holds and the children are
// cover-tested: the gather (window_gather), then each cell's children tested by
// uncovered_children. `centre` is the base cell's grid word, at `origin`.
[[gnu::target("avx2")]] inline void refine_cells_inner(CellArgs a, Cells cells, Uints counts, Uints masks,
                                                       const uvec2* centre, uvec2 origin, uint first, uint end) {
    ivec2 at[MAX_CELL_SAMPLES];
    uint samples = window_gather(centre, int(a.domain.cells_x), cover_reach(a.domain.radii), origin,
                                 1 << a.domain.cell_bits, a.domain.radii.coverage2, at);
    uint all = a.param == 4u ? 15u : 1u;
    for (uint i = first; i < end; i++) {
        ChildBoxes b = inner_child_boxes(ivec2(cells.cell[i] - origin), int(a.side), a.param);
        uint mask = uncovered_children(b, at, samples, a.domain.radii.coverage2, all);
        masks.value[i] = mask;
        counts.value[i] = uint(bitCount(mask));
    }
}
#endif

// A base cell that holds a sample, or (two radii) that one sample covers, keeps no cell.
VRPD_FN bool base_spent(Domain dom, Grid grid, uvec2 base) {
    return grid_is_sample(grid.word[base_index(dom, base)]) || (two_radii(dom.radii) && base_covered(dom, grid, base));
}

// For the active cells [first, end) of one base cell: masks[i] has bit c set for the children c
// of cell i that stay active (none if the base cell holds a sample or one covers it), and
// counts[i] their number, for the scan that places them in the next active list. The samples
// near the base cell are gathered once for the range. The host passes each base cell's whole group (group_end), the
// Vulkan kernel one cell per invocation: with two radii a base cell may hold hundreds of active
// cells (driver.cpp, kCrowded), and llvmpipe ends a loop once 65 535 iterations have run in one
// SIMD batch, which a group's T tests in one invocation passed, leaving cells unrefined.
VRPD_FN void refine_cells_of_base(VRPD_IN(CellArgs) a, Cells cells, Uints counts, Uints masks, Grid grid, uint first,
                                  uint end) {
    uvec2 base = base_cell_of(a.domain, cells.cell[first]);
    Domain dom = local_domain(a.domain, base);
    bool spent = base_spent(dom, grid, base);
    // Most spent groups are one cell (two radii's first refinement: one a base cell); written
    // here, its two words are two stores, where the loop below becomes two calls of memset.
    if (spent && end - first == 1u) {
        masks.value[first] = 0u;
        counts.value[first] = 0u;
        return;
    }
#ifdef VRPD_HOST_AVX2
    if (!spent && cover_tested(dom, a.param, a.side) && vector_refinement(dom, base))
        return refine_cells_inner(a, cells, counts, masks, grid.word + base_index(dom, base),
                                  uvec2(base.x << dom.cell_bits, base.y << dom.cell_bits), first, end);
#endif
    // One radius, one cell (the Vulkan kernel's): its test reads the samples from the grid as it
    // meets them (MAX_CELL_SAMPLES + 1), as there is no other cell to share a gather, which
    // llvmpipe keeps in memory.
    uint samples = spent || !cover_tested(dom, a.param, a.side) ? 0u
                   : end - first == 1u && !two_radii(dom.radii) ? MAX_CELL_SAMPLES + 1u
                                                                : gather_cell_samples(dom, grid, base);
    for (uint i = first; i < end; i++) {
        uint mask = spent ? 0u : surviving_children(dom, grid, base, cells.cell[i], a.side, a.param, samples);
        masks.value[i] = mask;
        counts.value[i] = uint(bitCount(mask));
    }
}

// Two radii: refine_cells_of_base for the one cell e, whose base cell is not spent (base_spent),
// as the two-radii kernel tests such cells.
VRPD_FN void refine_unspent_cell(VRPD_IN(CellArgs) a, Cells cells, Uints counts, Uints masks, Grid grid, uint e) {
    uvec2 base = base_cell_of(a.domain, cells.cell[e]);
    Domain dom = local_domain(a.domain, base);
    uint samples = cover_tested(dom, a.param, a.side) ? gather_cell_samples(dom, grid, base) : 0u;
    uint mask = surviving_children(dom, grid, base, cells.cell[e], a.side, a.param, samples);
    masks.value[e] = mask;
    counts.value[e] = uint(bitCount(mask));
}

// Writes the surviving children of active cell i to the next active list, from its rank on.
VRPD_FN void scatter_children(CellArgs a, Cells cells, Uints ranks, Uints masks, Cells cells_out, uint i) {
    uint mask = masks.value[i];
    uint rank = ranks.value[i];
    for (uint c = 0u; c < a.param; c++)
        if ((mask & (1u << c)) != 0u) cells_out.cell[rank++] = child_corner(cells.cell[i], a.side, c);
}

VRPD_END
#endif
