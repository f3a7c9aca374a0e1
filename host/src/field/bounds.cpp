// The bounds of r over blocks of the lattice (field/table.h): exact inside one table cell, where
// the bilinear interpolant's extremes lie at a block's corners, and from the min/max pyramids
// beyond it; and the table's bounds as a whole (complete_bounds).
#include "table.h"

#include "patches.h"

#include <algorithm>
#include <cmath>

namespace vrpd::detail {

namespace {
// The rows of table cells or nodes from which the bounds' loops go to the pool's threads (a row
// holds hundreds of cells or more).
constexpr std::size_t kRowGrain = 2;

// Level 0 (one table cell) is read from the cell's range (shared/field_table.h); level k >= 1
// holds the least and greatest node over blocks of 2^k x 2^k cells, each row of blocks made on
// one of the pool's threads.
void build_pyramids(FieldTable& t, ThreadPool& pool) {
    // Level k's blocks, ceil(cells / 2^k) a side, one after another from level 1.
    t.pyramid_start.assign(2, 0);
    for (std::uint32_t k = 1; (t.cells_x - 1) >> (k - 1) > 0 || (t.cells_y - 1) >> (k - 1) > 0; ++k) {
        const std::uint64_t w = (std::uint64_t(t.cells_x) + (1u << k) - 1) >> k,
                            h = (std::uint64_t(t.cells_y) + (1u << k) - 1) >> k;
        t.pyramid_start.push_back(std::uint32_t(t.pyramid_start.back() + w * h));
    }
    t.pyramid_lo.assign(t.pyramid_start.back(), UINT32_MAX);
    t.pyramid_hi.assign(t.pyramid_start.back(), 0);
    std::uint32_t w = t.cells_x, h = t.cells_y;
    for (std::size_t k = 1; k + 1 < t.pyramid_start.size(); ++k) {
        const std::uint32_t pw = w, ph = h, nw = (w + 1) / 2;
        std::uint32_t* const nlo = t.pyramid_lo.data() + t.pyramid_start[k];
        std::uint32_t* const nhi = t.pyramid_hi.data() + t.pyramid_start[k];
        const std::uint32_t* const plo = t.pyramid_lo.data() + t.pyramid_start[k - 1];
        const std::uint32_t* const phi = t.pyramid_hi.data() + t.pyramid_start[k - 1];
        // Level 1 from the cells' ranges, the others from the level below.
        auto range = [&](std::uint32_t i, std::uint32_t j) {
            if (k == 1) return shared::field_cell_range(t.view(), i, j);
            const std::size_t from = std::size_t(j) * pw + i;
            return glm::uvec2(plo[from], phi[from]);
        };
        pool.parallel_for((h + 1) / 2,
                          [&](std::size_t begin, std::size_t end, unsigned) {
                              for (std::size_t row = begin; row < end; ++row)
                                  for (std::uint32_t j = std::uint32_t(2 * row);
                                       j < std::min<std::uint32_t>(ph, 2 * row + 2); ++j)
                                      for (std::uint32_t i = 0; i < pw; ++i) {
                                          const std::size_t to = row * nw + i / 2;
                                          const glm::uvec2 r = range(i, j);
                                          nlo[to] = std::min(nlo[to], r.x);
                                          nhi[to] = std::max(nhi[to], r.y);
                                      }
                          },
                          kRowGrain);
        w = nw;
        h = (h + 1) / 2;
    }
}

// Joins kinked cell k, table cell (i, j), into `part`: each branch's gradients at the corners
// (the join's gradient is one of theirs wherever it has one), and r where the kink crosses the
// cell's edges inside the box (the corners come as nodes): the ridge or valley of a join lies
// along the kink, between the corners.
void kink_bounds(const FieldTable& t, std::uint32_t k, std::uint32_t i, std::uint32_t j, BoundsPart& part) {
    const glm::uvec4 a = shared::field_kink_branch(t.view(), k, 0), b = shared::field_kink_branch(t.view(), k, 1);
    raise_steepest(part.steepest, a.x, a.y, a.z, a.w, 1);
    raise_steepest(part.steepest, b.x, b.y, b.z, b.w, 1);
    const std::int64_t d[4] = {std::int64_t(a.x) - b.x, std::int64_t(a.y) - b.y, std::int64_t(a.z) - b.z,
                               std::int64_t(a.w) - b.w};
    const std::uint64_t side = std::uint64_t(1) << t.cell_bits, x0 = std::uint64_t(i) << t.cell_bits,
                        y0 = std::uint64_t(j) << t.cell_bits;
    // The edges as (from, to) corners, and where along x or y each runs.
    constexpr int kEdges[4][2] = {{0, 1}, {2, 3}, {0, 2}, {1, 3}};
    for (const auto& e : kEdges) {
        const std::int64_t d0 = d[e[0]], d1 = d[e[1]];
        if ((d0 < 0) == (d1 < 0)) continue;
        const std::uint64_t at = std::uint64_t(d0 * std::int64_t(side) / (d0 - d1));  // in [0, side]
        const bool along_x = e[1] - e[0] == 1;
        for (std::uint64_t f : {at, std::min(at + 1, side)}) {
            std::uint64_t x = x0 + (along_x ? f : (e[0] & 1) * side), y = y0 + (along_x ? (e[0] >> 1) * side : f);
            if (x >= t.lattice.extent_x || y >= t.lattice.extent_y) continue;
            const std::uint32_t r = t.radius({std::uint32_t(x), std::uint32_t(y)});
            part.lo = std::min(part.lo, r);
            part.hi = std::max(part.hi, r);
        }
    }
}
}  // namespace

void complete_bounds(FieldTable& t, ThreadPool& pool) {
    t.refresh_view();
    t.r_lo = *std::min_element(t.nodes.begin(), t.nodes.end());
    t.r_hi = *std::max_element(t.nodes.begin(), t.nodes.end());
    for (std::uint32_t q = 0; q < t.patch_count; ++q)
        t.r_lo = std::min(t.r_lo, t.splits[q].lo), t.r_hi = std::max(t.r_hi, t.splits[q].hi);
    for (std::uint32_t k = 0; k < t.kink_count; ++k) {
        const glm::uvec2 e =
            shared::field_kink_extremes(t.view(), k, t.cell_bits, {0, 0}, glm::uvec2(1u << t.cell_bits));
        t.r_lo = std::min(t.r_lo, e.x), t.r_hi = std::max(t.r_hi, e.y);
    }
    // Over the box, r's extremes are at the corners of the table cells clipped to it: the nodes
    // inside, the points where node lines meet the far edges, and the far corner. The
    // interpolant's L: its steepest gradient over the cells (patch_bounds takes a patched cell's).
    // Both by rows of nodes on the pool's threads, each chunk's joined after.
    const std::size_t rows = std::size_t(t.cells_y) + 1;
    std::vector<BoundsPart> parts(pool.chunks(rows, kRowGrain));
    const std::uint32_t last_x = t.lattice.extent_x - 1, last_y = t.lattice.extent_y - 1;
    pool.parallel_for(
        rows,
        [&](std::size_t begin, std::size_t end, unsigned chunk) {
            BoundsPart part;
            for (std::uint32_t j = std::uint32_t(begin); j < end; ++j) {
                for (std::uint32_t i = 0; i <= t.cells_x; ++i) {
                    const std::uint64_t x = std::uint64_t(i) << t.cell_bits, y = std::uint64_t(j) << t.cell_bits;
                    if ((x > last_x && i > 0 && (std::uint64_t(i - 1) << t.cell_bits) > last_x) ||
                        (y > last_y && j > 0 && (std::uint64_t(j - 1) << t.cell_bits) > last_y))
                        continue;
                    const std::uint32_t r = t.radius({std::uint32_t(std::min<std::uint64_t>(x, last_x)),
                                                      std::uint32_t(std::min<std::uint64_t>(y, last_y))});
                    part.lo = std::min(part.lo, r);
                    part.hi = std::max(part.hi, r);
                }
                if (j == t.cells_y) continue;
                for (std::uint32_t i = 0; i < t.cells_x; ++i) {
                    if (const int k = shared::field_kink(t.view(), i, j); k >= 0) {
                        kink_bounds(t, std::uint32_t(k), i, j, part);
                        continue;
                    }
                    if (!t.patch(i, j))
                        raise_steepest(part.steepest, t.node(i, j), t.node(i + 1, j), t.node(i, j + 1),
                                       t.node(i + 1, j + 1), 1);
                }
            }
            parts[chunk] = part;
        },
        kRowGrain);
    BoundsPart bounds;
    for (const BoundsPart& part : parts) bounds.join(part);
    patch_bounds(t, bounds, pool);
    t.box_lo = bounds.lo;
    t.box_hi = bounds.hi;
    t.lipschitz = bounds.steepest / double(1u << t.cell_bits);
    build_pyramids(t, pool);
    t.refresh_view();
}

std::uint32_t FieldTable::min_over(glm::uvec2 a, glm::uvec2 b) const { return shared::field_min_over(view(), a, b); }

std::uint32_t FieldTable::max_over(glm::uvec2 a, glm::uvec2 b) const { return shared::field_max_over(view(), a, b); }

std::pair<std::uint32_t, std::uint32_t> FieldTable::extremes_over(glm::uvec2 a, glm::uvec2 b) const {
    const glm::uvec2 e = shared::field_extremes_over(view(), a, b);
    return {e.x, e.y};
}

std::array<std::uint32_t, 4> FieldTable::children_min(glm::uvec2 a, glm::uvec2 e, glm::uvec2 m, glm::uvec2 b,
                                                      std::uint32_t open) const {
    const glm::uvec4 least = shared::field_children_min(view(), a, e, m, b, open);
    return {least.x, least.y, least.z, least.w};
}

int FieldTable::axis_ranges(std::uint32_t c, std::uint64_t reach, std::uint32_t extent, std::uint64_t lo[2],
                            std::uint64_t hi[2]) const {
    const std::int64_t a = std::int64_t(c) - std::int64_t(reach), b = std::int64_t(c) + std::int64_t(reach);
    if (!lattice.periodic || b - a + 1 >= std::int64_t(extent)) {
        lo[0] = std::uint64_t(std::max<std::int64_t>(a, 0));
        hi[0] = std::uint64_t(std::min<std::int64_t>(b, std::int64_t(extent) - 1));
        if (lattice.periodic) lo[0] = 0, hi[0] = extent - 1;
        return 1;
    }
    if (a < 0) {
        lo[0] = 0, hi[0] = std::uint64_t(b);
        lo[1] = std::uint64_t(a + std::int64_t(extent)), hi[1] = extent - 1;
        return 2;
    }
    if (b >= std::int64_t(extent)) {
        lo[0] = std::uint64_t(a), hi[0] = extent - 1;
        lo[1] = 0, hi[1] = std::uint64_t(b - std::int64_t(extent));
        return 2;
    }
    lo[0] = std::uint64_t(a), hi[0] = std::uint64_t(b);
    return 1;
}

std::uint32_t FieldTable::max_near(glm::uvec2 p, std::uint64_t reach) const {
    std::uint64_t xl[2], xh[2], yl[2], yh[2];
    const int nx = axis_ranges(p.x, reach, lattice.extent_x, xl, xh),
              ny = axis_ranges(p.y, reach, lattice.extent_y, yl, yh);
    std::uint32_t m = 0;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            m = std::max(m, max_over({std::uint32_t(xl[i]), std::uint32_t(yl[j])},
                                     {std::uint32_t(xh[i]), std::uint32_t(yh[j])}));
    return m;
}

std::uint64_t FieldTable::grown_reach(glm::uvec2 a, glm::uvec2 b, std::uint32_t r_hi, int steps, double scale) const {
    std::uint64_t rho = std::max(this->r_hi, r_hi);
    if (const double slope = scale * lipschitz; slope < 1)
        rho = std::min<std::uint64_t>(rho, std::uint64_t(std::ceil((r_hi + 1.0) / (1 - slope))) + 1);
    const glm::uvec2 centre((a.x + b.x) / 2, (a.y + b.y) / 2);
    const std::uint64_t half = std::max(b.x - a.x, b.y - a.y) / 2 + 1;
    for (int i = 0; i < steps; ++i) {
        const std::uint64_t m =
            std::max<std::uint64_t>(max_near(centre, std::uint64_t(std::ceil(scale * double(rho))) + half), r_hi);
        if (m >= rho) break;
        rho = m;
    }
    return rho;
}

}  // namespace vrpd::detail
