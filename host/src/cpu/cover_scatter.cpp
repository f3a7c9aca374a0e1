#include "cover_scatter.h"

#include <algorithm>
#include <array>

#include "shared/mask_mode.h"

namespace vrpd::detail {
using namespace shared;

namespace {

#ifdef VRPD_HOST_AVX2
constexpr int kWidth = 2 * int(MAX_REACH) + 1;

// Two rows of 4 x 4 children as mask bits, from their bits row by row (bit 4 iy + ix): k's even
// bits are x's, its odd bits y's (subcell_corner's numbering). Rows 2 and 3 take the same bits 8
// places up.
constexpr auto kRowsToMask = [] {
    std::array<std::uint8_t, 256> t{};
    for (uint rows = 0u; rows < 256u; rows++)
        for (uint iy = 0u; iy < 2u; iy++)
            for (uint ix = 0u; ix < 4u; ix++)
                if ((rows >> (4u * iy + ix) & 1u) != 0u)
                    t[rows] |= std::uint8_t(1u << ((ix & 1u) | iy << 1u | (ix & 2u) << 1u));
    return t;
}();

// The children of N x N (N = 2 or 4) whose bits row by row are `rows` (bit N iy + ix), as mask bits.
template <uint N>
uint children_mask(uint rows) {
    if (N == 2u) return rows;  // 2 x 2: the mask's own order
    return kRowsToMask[rows & 255u] | uint(kRowsToMask[rows >> 8u]) << 8u;
}

// A sample's squared farthest gaps, per axis, to the children's intervals (N a side, side h) of
// the base cells d - reach cells away, d in [0, 2 reach]; and the d where some child's gap is
// below the limit, [x0, x1] along x and [y0, y1] along y (none beyond can hold a covered child).
template <uint N>
struct Gaps {
    alignas(32) int64_t x[kWidth][4], y[kWidth][4];  // 4 a row for the vector bodies' loads
    int x0 = kWidth, x1 = -1, y0 = kWidth, y1 = -1;
};

// scatter_sample on processors with AVX2: a base cell's gaps along x and y in one vector, and a
// row of children's gaps compared with the room a row's y gap leaves at once.
template <uint N>
[[gnu::target("avx2")]] void scatter_sample_avx2(const Domain& dom, const ScatterBox& box, uint h, uvec2 p, bool fast,
                                                 uint* masks) {
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
    Gaps<N> g;
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
    // each_near_cell's loop, written out: a lambda's body would not be built for AVX2.
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
                        << (N * iy);
            row[x] &= ~children_mask<N>(rows);
        }
    }
}
#endif

}  // namespace

std::uint64_t refine_masked_scattered(ThreadPool& pool, const CellArgs& a, Grid grid, uint* masks,
                                      [[maybe_unused]] bool vector_bodies) {
    const Domain& dom = a.domain;
    const uint bases = dom.cells_x * dom.cells_y;
    const ScatterBox box = scatter_box(dom, a.side, a.param);
    // Every child of an active sub-cell of a scattered base cell, then the samples' covers taken
    // from them; the other base cells refined as refine_masked_base refines them.
    pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned) {
        // A row's part in [b, e): the box's cells [x0, x1] if the row is the box's, the others
        // each by refine_masked_base.
        for (std::size_t i = b; i < e;) {
            const std::size_t y = i / dom.cells_x, row = y * dom.cells_x, stop = std::min(row + dom.cells_x, e);
            const bool boxed = box_holds(box, box.x0, int(y));
            const std::size_t from = boxed ? std::clamp(row + std::size_t(box.x0), i, stop) : stop,
                              to = boxed ? std::clamp(row + std::size_t(box.x1) + 1u, i, stop) : stop;
            for (; i < from; ++i) masks[i] = refine_masked_base(a, grid, uint(i)).x;
            for (; i < to; ++i) masks[i] = all_children(grid.word[i]);
            for (; i < stop; ++i) masks[i] = refine_masked_base(a, grid, uint(i)).x;
        }
    });
    if (box_any(box)) {
        const uint h = a.side;
        const int reach = cover_reach(dom.radii);
        // The body, chosen once: the kernels' (scatter_cover), or with AVX2 the one for the
        // children's count a side (2 or 4).
        using Body = void (*)(const Domain&, const ScatterBox&, uint, uvec2, bool, uint*);
        Body scatter = [](const Domain& d, const ScatterBox& b, uint side, uvec2 p, bool, uint* m) {
            scatter_cover(d, b, side, p, Uints{m});
        };
#ifdef VRPD_HOST_AVX2
        const bool quarters = (1u << dom.cell_bits) / h == 4u;
        if (vector_bodies && host_has_avx2()) scatter = quarters ? scatter_sample_avx2<4> : scatter_sample_avx2<2>;
#endif
        // The samples in grid order, so that neighbouring samples meet the same masks in cache, in
        // bands of rows at least 2 reach high: a sample's writes reach the bands beside its own at
        // most, so the even bands and then the odd ones run in parallel without sharing a mask.
        auto scatter_row = [&](std::size_t first) {
            for (std::size_t i = first; i < first + dom.cells_x; ++i) {
                const uvec2 p = grid.word[i];
                if (!grid_is_sample(p)) continue;
                const uvec2 s = base_cell_of(dom, p);
                const bool fast = box_holds(box, int(s.x) - reach, int(s.y) - reach) &&
                                  box_holds(box, int(s.x) + reach, int(s.y) + reach);
                scatter(dom, box, h, p, fast, masks);
            }
        };
        const uint band = std::max(2u * uint(reach), 8u), bands = (dom.cells_y + band - 1u) / band;
        for (uint parity = 0u; parity < 2u; ++parity)
            pool.parallel_for((bands + 1u - parity) / 2u,
                              [&](std::size_t b, std::size_t e, unsigned) {
                                  for (std::size_t k = b; k < e; ++k) {
                                      const uint first = (2u * uint(k) + parity) * band,
                                                 end = std::min(first + band, dom.cells_y);
                                      for (uint y = first; y < end; ++y) scatter_row(std::size_t(y) * dom.cells_x);
                                  }
                              },
                              1);
    }
    std::vector<std::uint64_t> active(pool.chunks(bases), 0);
    pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
        std::uint64_t sum = 0;
        for (std::size_t i = b; i < e; ++i) sum += uint(bitCount(masks[i]));
        active[w] = sum;
    });
    std::uint64_t total = 0;
    for (const std::uint64_t c : active) total += c;
    return total;
}

}  // namespace vrpd::detail
