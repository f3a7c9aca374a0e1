// Coverage by the samples of earlier rounds, read from the grid: is a point in a sample's disk
// (throwing), which samples may cover a base cell's quadtree cells (refinement), and with two
// radii which samples' Rc-disks meet a box (the exact cell test of t_membership.h).
#ifndef VRPD_COVER_H
#define VRPD_COVER_H
#include "bridge.h"
#include "neighbourhood.h"
#include "kernels.h"
#include "t_membership.h"

VRPD_BEGIN

#ifdef VRPD_HOST_AVX2
// The host's body of the scans of near_sample and base_covered where they neither wrap nor meet
// a free boundary and reach at most MAX_REACH cells, on processors with AVX2: does a sample in the
// (2 reach + 1)^2 window of base cells around `centre` lie closer than sqrt(limit2), from `at`
// (near_sample's point) or, with kFarthest, at its farthest from the cell [0, far.x] x [0, far.y]
// with corner `at` (base_covered's cover)? Each row is two masked loads of four grid words; each
// lane's offset o from `at` in 32 bits (coordinates within the window differ by less than 2^31:
// distance2's value on a straight domain), or per axis max(o, far - o) >= 0, squared and summed in
// 64. A sample in a cell the rows' reaches leave out lies at least sqrt(limit2) from every point
// of the centre cell, so testing it changes no answer.
// The reach is a template parameter, so that the rows' loops unroll.
template <bool kFarthest, int kReach>
[[gnu::target("avx2")]] inline bool window_holds_within_at(const uvec2* centre, int stride, uvec2 at, uint64_t limit2,
                                                           ivec2 far) {
    constexpr int width = 2 * kReach + 1;  // 3, 5 or 7 words a row
    const int low_lanes = (1 << (width < 4 ? width : 4)) - 1, high_lanes = width > 4 ? (1 << (width - 4)) - 1 : 0;
    const __m256i lane = _mm256_setr_epi64x(0, 1, 2, 3);
    const __m256i low = _mm256_cmpgt_epi64(_mm256_set1_epi64x(width), lane);
    const __m256i high = _mm256_cmpgt_epi64(_mm256_set1_epi64x(width - 4), lane);
    const __m256i from = _mm256_set1_epi64x(int64_t(uint64_t(at.y) << 32 | at.x));
    const __m256i far_side = _mm256_set1_epi64x(int64_t(uint64_t(uint(far.y)) << 32 | uint(far.x)));
    const __m256i limit = _mm256_set1_epi64x(int64_t(limit2));
    // The centre row first, then the rows either side outwards: a hit, which ends the scan, lies
    // mostly near the centre.
    for (int k = 0; k < width; k++) {
        const int dy = (k & 1) != 0 ? -(k + 1) / 2 : k / 2;
        const auto* row = reinterpret_cast<const long long*>(centre + dy * stride - kReach);
        for (int half = 0; half < (width > 4 ? 2 : 1); half++) {
            const __m256i w = _mm256_maskload_epi64(row + 4 * half, half == 0 ? low : high);
            __m256i d = _mm256_sub_epi32(w, from);
            if constexpr (kFarthest) d = _mm256_max_epi32(d, _mm256_sub_epi32(far_side, d));
            const __m256i d_y = _mm256_srli_epi64(d, 32);
            const __m256i d2 = _mm256_add_epi64(_mm256_mul_epi32(d, d), _mm256_mul_epi32(d_y, d_y));
            const int close = _mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpgt_epi64(limit, d2)));
            const int tagged = _mm256_movemask_pd(_mm256_castsi256_pd(_mm256_slli_epi64(w, 32)));  // GRID_TAG
            if ((close & ~tagged & (half == 0 ? low_lanes : high_lanes)) != 0) return true;
        }
    }
    return false;
}
template <bool kFarthest>
[[gnu::target("avx2")]] inline bool window_holds_within(const uvec2* centre, int stride, int reach, uvec2 at,
                                                        uint64_t limit2, ivec2 far = ivec2(0)) {
    switch (reach) {
        case 1:
            return window_holds_within_at<kFarthest, 1>(centre, stride, at, limit2, far);
        case 2:
            return window_holds_within_at<kFarthest, 2>(centre, stride, at, limit2, far);
        default:
            return window_holds_within_at<kFarthest, int(MAX_REACH)>(centre, stride, at, limit2, far);
    }
}
// Whether a vector body may scan the window around base cell `base`: it neither wraps nor meets a
// free boundary, and the processor has AVX2.
[[gnu::always_inline]] inline bool vector_window(const Domain& dom, uvec2 base) {
    return dom.lattice.periodic == 0u && inner_cell(dom, base) && host_has_avx2();
}
#endif

// Is point p inhibited (INHIBITION: closer than Rf) or covered (COVERAGE: closer than Rc) by a
// sample of an earlier round? The samples near base cell `base` are read from the grid; dom is
// local_domain(base).
VRPD_FN bool near_sample(VRPD_IN(Domain) dom, Grid grid, uvec2 base, uvec2 p, uint which) {
    int reach = radius_reach(dom.radii, which);
#ifdef VRPD_HOST_AVX2
    if (reach <= int(MAX_REACH) && vector_window(dom, base))
        return window_holds_within<false>(grid.word + base_index(dom, base), int(dom.cells_x), reach, p,
                                          radius2(dom.radii, which));
#endif
    VRPD_FOR_EACH_NEIGHBOUR(dom, base, reach, radius2(dom.radii, which), dx, dy, nb) {
        uvec2 w = grid.word[nb];
        if (grid_is_sample(w) && within(dom.radii, which, distance2(dom.lattice, w, p))) return true;
    }
    return false;
}

// Is point p off the domain or inhibited by a sample of an earlier round? Then a dart there is
// rejected when thrown.
VRPD_FN bool inhibited(VRPD_IN(Domain) dom, Grid grid, uvec2 base, uvec2 p) {
    return !in_lattice(dom.lattice, p) || near_sample(dom, grid, base, p, INHIBITION);
}

#ifdef VRPD_HOST_AVX2
// The host's gathers of the (2 reach + 1)^2 window of base cells around `centre` (any reach), on
// processors with AVX2: writes to `out` the offsets from `at` of the samples closer than
// sqrt(limit2) to `at` or, with kBox, to the box [at, at + box] (per axis max(-o, o - box, 0)),
// in the order VRPD_FOR_EACH_NEIGHBOUR visits them (rows, then columns); returns their count, or
// `most` + 1 once more than `most` are found. Lanes as window_holds_within reads them; a sample
// in a cell the rows' reaches leave out lies at least sqrt(limit2) from the centre cell.
// kReach > 0 is the reach as a template parameter, so that the rows' loads unroll; 0 takes
// `reach`.
template <bool kBox, int kReach>
[[gnu::target("avx2")]] inline uint window_gather_within_at(const uvec2* centre, int stride, int any_reach, uvec2 at,
                                                            uint64_t limit2, ivec2* out, uint most, ivec2 box) {
    const int reach = kReach > 0 ? kReach : any_reach;
    const int width = 2 * reach + 1, last = (width - 1) & ~3;  // the last load's first word
    const __m256i all = _mm256_set1_epi64x(-1);
    const __m256i tail = _mm256_cmpgt_epi64(_mm256_set1_epi64x(width - last), _mm256_setr_epi64x(0, 1, 2, 3));
    const uint tail_lanes = (1u << (width - last)) - 1u;
    const __m256i from = _mm256_set1_epi64x(int64_t(uint64_t(at.y) << 32 | at.x));
    const __m256i far_side = _mm256_set1_epi64x(int64_t(uint64_t(uint(box.y)) << 32 | uint(box.x)));
    const __m256i zero = _mm256_setzero_si256();
    const __m256i limit = _mm256_set1_epi64x(int64_t(limit2));
    uint n = 0u;
    for (int dy = -reach; dy <= reach; dy++) {
        const auto* row = reinterpret_cast<const long long*>(centre + dy * stride - reach);
        for (int x = 0; x <= last; x += 4) {
            const __m256i w = _mm256_maskload_epi64(row + x, x == last ? tail : all);
            const __m256i d = _mm256_sub_epi32(w, from);
            __m256i g = d;
            if constexpr (kBox)
                g = _mm256_max_epi32(_mm256_max_epi32(_mm256_sub_epi32(zero, d), _mm256_sub_epi32(d, far_side)), zero);
            const __m256i g_y = _mm256_srli_epi64(g, 32);
            const __m256i g2 = _mm256_add_epi64(_mm256_mul_epi32(g, g), _mm256_mul_epi32(g_y, g_y));
            const uint close = uint(_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpgt_epi64(limit, g2))));
            const uint tagged = uint(_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_slli_epi64(w, 32))));  // GRID_TAG
            uint kept = close & ~tagged & (x == last ? tail_lanes : 15u);
            if (kept == 0u) continue;
            alignas(32) ivec2 offset[4];
            _mm256_store_si256(reinterpret_cast<__m256i*>(offset), d);
            for (; kept != 0u; kept &= kept - 1u) {
                if (n == most) return most + 1u;
                out[n++] = offset[std::countr_zero(kept)];
            }
        }
    }
    return n;
}
template <bool kBox>
[[gnu::target("avx2")]] inline uint window_gather_within(const uvec2* centre, int stride, int reach, uvec2 at,
                                                         uint64_t limit2, ivec2* out, uint most, ivec2 box = ivec2(0)) {
    switch (reach) {
        case 3:
            return window_gather_within_at<kBox, 3>(centre, stride, reach, at, limit2, out, most, box);
        case 4:
            return window_gather_within_at<kBox, 4>(centre, stride, reach, at, limit2, out, most, box);
        case 5:
            return window_gather_within_at<kBox, 5>(centre, stride, reach, at, limit2, out, most, box);
        case 6:
            return window_gather_within_at<kBox, 6>(centre, stride, reach, at, limit2, out, most, box);
        default:
            return window_gather_within_at<kBox, 0>(centre, stride, reach, at, limit2, out, most, box);
    }
}
#endif

// Two radii: fills disk_at with the samples whose Rc-disk meets the box [cc, cc + hi] (hi >= 0),
// as offsets from cc: only they can cover a point of it or cross inside it. Returns the count,
// MAX_DISKS + 1 if they do not fit.
VRPD_OUTLINED_FN uint gather_near_box(Domain dom, Grid grid, uvec2 base, uvec2 cc, ivec2 hi) {
    uint n = 0u;
    int reach = cover_reach(dom.radii);
#ifdef VRPD_HOST_AVX2
    if (vector_window(dom, base))
        return window_gather_within<true>(grid.word + base_index(dom, base), int(dom.cells_x), reach, cc,
                                          dom.radii.coverage2 + uint64_t(1), disk_at, MAX_DISKS, hi);
#endif
    VRPD_FOR_EACH_NEIGHBOUR(dom, base, reach, dom.radii.coverage2 + uint64_t(1), dx, dy, nb) {
        uvec2 w = grid.word[nb];
        if (!grid_is_sample(w)) continue;
        ivec2 o = offset_to(dom.lattice, cc, w);
        int64_t gx = int64_t(max(max(-o.x, o.x - hi.x), 0));
        int64_t gy = int64_t(max(max(-o.y, o.y - hi.y), 0));
        if (!reaches(dom.radii, uint64_t(gx * gx + gy * gy))) continue;
        if (n == MAX_DISKS) return MAX_DISKS + 1u;
        disk_at[n++] = o;
    }
    return n;
}

// The samples of earlier rounds in the cover neighbourhood of a base cell, gathered once for all
// of its active cells, as offsets from the base cell's corner: each cell's cover test then reads
// this short list, not the grid, and needs no torus arithmetic. The offset of a sample is taken
// through the neighbour cell it was found in. On a torus at least 2 reach + 1 cells wide, a
// sample whose offset is not the shortest one lies at least reach * side + 1 >= Rc from every
// point of the base cell along that axis, so it covers none of them either way: the tests below
// are exact. MAX_CELL_SAMPLES holds any one-radius neighbourhood (a base cell holds at most one
// sample and cover_reach <= MAX_REACH); a two-radii one that does not fit is scanned per cell.
const uint MAX_CELL_SAMPLES = (2u * MAX_REACH + 1u) * (2u * MAX_REACH + 1u);
VRPD_PRIVATE ivec2 cell_sample_at[MAX_CELL_SAMPLES];

// Clamps the last lattice coordinate of an interval to a free boundary's last lattice point.
VRPD_FN uint clip_hi(uint hi, uint extent, uint periodic) { return periodic != 0u || hi < extent ? hi : extent - 1u; }

// The offset from the corner of base cell `base` to sample p, found in the cell (dx, dy) from it.
VRPD_FN ivec2 sample_offset(Domain dom, int dx, int dy, uvec2 p) {
    int side = 1 << dom.cell_bits;
    uint low = uint(side) - 1u;
    return ivec2(dx * side + int(p.x & low), dy * side + int(p.y & low));
}

// (a - b)^2 for offsets of points of the domain: less than 2^31 apart, so two squares sum below
// 2^63. The square needs no absolute value.
VRPD_FN uint64_t square_gap(int a, int b) {
    int64_t d = int64_t(a) - int64_t(b);
    return uint64_t(d * d);
}

// The larger squared distance from coordinate c to the ends of [lo, hi] (lo <= hi): the cell is
// convex, so its farthest corner pairs the farthest x with the farthest y. The farther end is lo
// if c - lo >= hi - c, else hi, and that difference is the distance (>= (hi - lo) / 2 >= 0).
VRPD_FN uint64_t far2(int c, int lo, int hi) {
    uint m = uint(max(c - lo, hi - c));
    return uint64_t(m) * uint64_t(m);
}

// Two radii: does one sample cover every point of base cell `base` (its closed square, clipped
// to a free boundary)? Then it covers every cell of the base cell and every child, and their
// cover tests need no gather: most base cells of a run's first refinement end here. Such a sample
// lies within Rc of the cell's far corners, so the scan is narrower than the gather's. A base
// cell past a free boundary (a hierarchy's step may keep some) holds no point to test.
VRPD_FN bool base_covered(Domain dom, Grid grid, uvec2 base) {
    uvec2 origin = uvec2(base.x << dom.cell_bits, base.y << dom.cell_bits);
    if (!in_lattice(dom.lattice, origin)) return false;
    uint side = 1u << dom.cell_bits;
    int hx = int(clip_hi(origin.x + side, dom.lattice.extent_x, dom.lattice.periodic) - origin.x);
    int hy = int(clip_hi(origin.y + side, dom.lattice.extent_y, dom.lattice.periodic) - origin.y);
    // A cover in a base cell dx != 0 columns across lies at least |dx| sides from the far column
    // of corners, and at least half a side from the far row: the reach is the largest |dx| with
    // (|dx| side)^2 + (side / 2)^2 < Rc^2 (at least 1, at most cover_reach).
    uint64_t half2 = uint64_t(side / 2u) * uint64_t(side / 2u);
    int reach = 1;
    while (uint64_t(reach + 1) * uint64_t(side) * (uint64_t(reach + 1) * uint64_t(side)) + half2 < dom.radii.coverage2)
        reach++;
#ifdef VRPD_HOST_AVX2
    if (reach <= int(MAX_REACH) && vector_window(dom, base))
        return window_holds_within<true>(grid.word + base_index(dom, base), int(dom.cells_x), reach, origin,
                                         dom.radii.coverage2, ivec2(hx, hy));
#endif
    VRPD_FOR_EACH_NEIGHBOUR(dom, base, reach, dom.radii.coverage2, dx, dy, nb) {
        uvec2 p = grid.word[nb];
        if (!grid_is_sample(p)) continue;
        ivec2 o = sample_offset(dom, dx, dy, p);
        if (covers(dom.radii, far2(o.x, 0, hx) + far2(o.y, 0, hy))) return true;
    }
    return false;
}

#ifdef VRPD_HOST_AVX2
// The host's body of gather_cell_samples where the scan neither wraps nor meets a free boundary and
// reaches at most MAX_REACH cells, on processors with AVX2, as window_holds_within reads it: each
// sample's offset from the base cell's corner `origin` (side `side`) in 32 bits, kept if its
// squared gap to the closed base cell is below limit2 (Rc^2; an adjacent cell's sample always is,
// and one in a cell the rows' reaches leave out never). Writes the kept offsets to `out`, the 3 x 3
// adjacent cells' first, each group in row order; returns their count.
template <int kReach>
[[gnu::target("avx2")]] inline uint window_gather_at(const uvec2* centre, int stride, uvec2 origin, int side,
                                                     uint64_t limit2, ivec2* out) {
    constexpr int width = 2 * kReach + 1;
    const uint low_lanes = (1u << (width < 4 ? width : 4)) - 1u, high_lanes = width > 4 ? (1u << (width - 4)) - 1u : 0u;
    const __m256i lane = _mm256_setr_epi64x(0, 1, 2, 3);
    const __m256i low = _mm256_cmpgt_epi64(_mm256_set1_epi64x(width), lane);
    const __m256i high = _mm256_cmpgt_epi64(_mm256_set1_epi64x(width - 4), lane);
    const __m256i corner = _mm256_set1_epi64x(int64_t(uint64_t(origin.y) << 32 | origin.x));
    const __m256i far_side = _mm256_set1_epi32(side);
    const __m256i zero = _mm256_setzero_si256();
    const __m256i limit = _mm256_set1_epi64x(int64_t(limit2));
    ivec2 offset[8 * (2 * MAX_REACH + 1)];  // row r's lane k at 8 r + k
    uint64_t kept = 0u;                     // the same bits
    for (int r = 0; r < width; r++) {
        const auto* row = reinterpret_cast<const long long*>(centre + (r - kReach) * stride - kReach);
        for (int half = 0; half < (width > 4 ? 2 : 1); half++) {
            const __m256i w = _mm256_maskload_epi64(row + 4 * half, half == 0 ? low : high);
            const __m256i o = _mm256_sub_epi32(w, corner);
            const __m256i gap =
                _mm256_max_epi32(_mm256_max_epi32(_mm256_sub_epi32(zero, o), _mm256_sub_epi32(o, far_side)), zero);
            const __m256i gap_y = _mm256_srli_epi64(gap, 32);
            const __m256i g2 = _mm256_add_epi64(_mm256_mul_epi32(gap, gap), _mm256_mul_epi32(gap_y, gap_y));
            const int close = _mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpgt_epi64(limit, g2)));
            const int tagged = _mm256_movemask_pd(_mm256_castsi256_pd(_mm256_slli_epi64(w, 32)));  // GRID_TAG
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(&offset[8 * r + 4 * half]), o);
            kept |= uint64_t(uint(close & ~tagged) & (half == 0 ? low_lanes : high_lanes)) << (8 * r + 4 * half);
        }
    }
    // The 3 x 3 adjacent cells: lanes kReach - 1 to kReach + 1 of rows kReach - 1 to kReach + 1.
    const uint64_t adjacent =
        uint64_t(7u << (kReach - 1)) *
        ((uint64_t(1) << (8 * (kReach - 1))) | (uint64_t(1) << (8 * kReach)) | (uint64_t(1) << (8 * (kReach + 1))));
    uint n = 0u;
    for (uint64_t m = kept & adjacent; m != 0u; m &= m - 1u) out[n++] = offset[std::countr_zero(m)];
    for (uint64_t m = kept & ~adjacent; m != 0u; m &= m - 1u) out[n++] = offset[std::countr_zero(m)];
    return n;
}
[[gnu::target("avx2")]] inline uint window_gather(const uvec2* centre, int stride, int reach, uvec2 origin, int side,
                                                  uint64_t limit2, ivec2* out) {
    switch (reach) {
        case 1:
            return window_gather_at<1>(centre, stride, origin, side, limit2, out);
        case 2:
            return window_gather_at<2>(centre, stride, origin, side, limit2, out);
        default:
            return window_gather_at<int(MAX_REACH)>(centre, stride, origin, side, limit2, out);
    }
}
#endif

// Fills cell_sample_at with the samples near base cell `base`, those of the 8 adjacent cells
// first (the likeliest to cover a cell wholly, so that cover tests stop early); returns their
// count, or MAX_CELL_SAMPLES + 1 if they do not fit.
VRPD_FN uint gather_cell_samples(Domain dom, Grid grid, uvec2 base) {
#ifdef VRPD_HOST_AVX2
    if (cover_reach(dom.radii) <= int(MAX_REACH) && vector_window(dom, base))
        return window_gather(grid.word + base_index(dom, base), int(dom.cells_x), cover_reach(dom.radii),
                             uvec2(base.x << dom.cell_bits, base.y << dom.cell_bits), 1 << dom.cell_bits,
                             dom.radii.coverage2, cell_sample_at);
#endif
    uint near = 0u;
    uint far = 0u;  // stored from the end of the array down
    int side = 1 << dom.cell_bits;  // the base cell, closed: [0, side]^2 from its corner
    int reach = cover_reach(dom.radii);
    VRPD_FOR_EACH_NEIGHBOUR(dom, base, reach, dom.radii.coverage2, dx, dy, nb) {
        uvec2 p = grid.word[nb];
        if (!grid_is_sample(p)) continue;
        if (near + far == MAX_CELL_SAMPLES) return MAX_CELL_SAMPLES + 1u;
        ivec2 o = sample_offset(dom, dx, dy, p);
        // A sample of the 8 adjacent cells lies within a base cell's diagonal, shorter than Rf,
        // of the base cell's nearest corner. Another that covers no point of the base cell
        // covers none of its cells.
        if (dx >= -1 && dx <= 1 && dy >= -1 && dy <= 1) {
            cell_sample_at[near++] = o;
        } else if (covers(dom.radii, square_gap(clamp(o.x, 0, side), o.x) + square_gap(clamp(o.y, 0, side), o.y))) {
            far++;
            cell_sample_at[MAX_CELL_SAMPLES - far] = o;
        }
    }
    for (uint k = 0u; k < far; k++) cell_sample_at[near + k] = cell_sample_at[MAX_CELL_SAMPLES - 1u - k];
    return near + far;
}

VRPD_END
#endif
