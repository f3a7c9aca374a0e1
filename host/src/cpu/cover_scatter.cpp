#include "cover_scatter.h"

#include <algorithm>

#include "shared/mask_mode.h"

namespace vrpd::detail {
using namespace shared;

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
        if (vector_bodies && host_has_avx2()) scatter = quarters ? scatter_cover_avx2<4> : scatter_cover_avx2<2>;
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
