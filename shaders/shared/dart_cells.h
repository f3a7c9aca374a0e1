// Two radii (paper section 3): the base cells that get darts in a round. Darts go to the
// sample-free base cells within Rc of the active cells, a superset of T, and are kept iff in T.
#ifndef VRPD_DART_CELLS_H
#define VRPD_DART_CELLS_H
#include "bridge.h"
#include "active_cells.h"
#include "kernels.h"
#include "neighbourhood.h"
#ifdef __cplusplus
#include <vector>
#endif

VRPD_BEGIN

// Two radii. The active cells track where U (points >= Rc from every sample) may remain; the darts
// go to base cells instead. For the active cells [e, end_cell) of one base cell (group_end): flags
// every base cell that holds no sample and lies within Rc of them. Each point of T is free, so
// its base cell holds no sample, and within Rc of U, which lies in the active cells: the flagged
// cells cover T, and darts uniform over them, kept iff in T (exact test), are uniform over T.
// The gap along one axis from the group's bounding box [lo, hi] (lattice units from its base
// cell's corner, base cells of side `side`) to the base cell k cells away: no point of the two is
// nearer. It grows with |k|.
VRPD_FN int64_t dart_cell_gap(int k, int side, uint lo, uint hi) {
    return k > 0 ? int64_t(k * side - int(hi)) : (k < 0 ? int64_t(int(lo) - (k + 1) * side + 1) : int64_t(0));
}

// Does a base cell whose gaps from the group are gx and gy (dart_cell_gap) get flagged by
// distance: is some point of it within Rc of the group?
VRPD_FN bool dart_gaps_reach(Radii r, int64_t gx, int64_t gy) { return reaches(r, uint64_t(gx * gx + gy * gy)); }

// The bounding box of the active cells [e, end_cell) of one base cell, in lattice units from the
// base cell's corner: [lo, hi], each cell a closed square (surviving_children's cells).
VRPD_FN void dart_group_box(CellArgs a, Cells cells, uint e, uint end_cell, uvec2 origin, VRPD_OUT(uvec2) lo,
                            VRPD_OUT(uvec2) hi) {
    int side = 1 << a.domain.cell_bits;
    lo = uvec2(uint(side), uint(side));
    hi = uvec2(0u, 0u);
    for (uint i = e; i < end_cell; i++) {
        uvec2 c = cells.cell[i] - origin;
        lo = min(lo, c);
        hi = max(hi, c + uvec2(a.side, a.side));
    }
}

// The squared radius of flag_dart_cells's scan: the cells some point of which lies within Rc
// of the base cell (reaches: gap^2 <= Rc^2).
VRPD_FN uint64_t dart_scan_limit2(Radii r) { return r.coverage2 + uint64_t(1); }

VRPD_FN void flag_dart_cells(CellArgs a, Cells cells, Uints flags, Grid grid, uint e, uint end_cell) {
    Domain dom = a.domain;
    uvec2 base = base_cell_of(dom, cells.cell[e]);
    int side = 1 << dom.cell_bits;
    uvec2 lo;
    uvec2 hi;
    dart_group_box(a, cells, e, end_cell, uvec2(base.x << dom.cell_bits, base.y << dom.cell_bits), lo, hi);
    int reach = cover_reach(dom.radii);
    VRPD_FOR_EACH_NEIGHBOUR(dom, base, reach, dart_scan_limit2(dom.radii), dx, dy, nb) {
        if (dart_gaps_reach(dom.radii, dart_cell_gap(dx, side, lo.x, hi.x), dart_cell_gap(dy, side, lo.y, hi.y)) &&
            !grid_is_sample(grid.word[nb]))
            set_flag(flags, nb);
    }
}

#ifdef __cplusplus
// flag_dart_cells's scan's row_reach for rows |dy| = 0 to cover_reach, for flag_dart_runs.
inline std::vector<int> dart_scan_rows(const Domain& dom) {
    const int reach = cover_reach(dom.radii);
    std::vector<int> rows(std::size_t(reach) + 1);
    for (int dy = 0; dy <= reach; ++dy) rows[dy] = computed_row_reach(dom, dy, reach, dart_scan_limit2(dom.radii));
    return rows;
}

// The host's flag_dart_cells. Where the base cell's neighbourhood is plain offsets (inner_cell),
// the gap grows with |dx| either side of a row's centre column, so the cells a row flags are one
// run of columns: its ends are found from the scan's own ends inward, and the cells between take
// no test. `rows` is dart_scan_rows's table (one a round).
inline void flag_dart_runs(const CellArgs& a, const int* rows, Cells cells, Uints flags, Grid grid, uint e,
                           uint end_cell) {
    const Domain& dom = a.domain;
    const uvec2 base = base_cell_of(dom, cells.cell[e]);
    if (!inner_cell(dom, base)) return flag_dart_cells(a, cells, flags, grid, e, end_cell);
    const int side = 1 << dom.cell_bits, reach = cover_reach(dom.radii);
    uvec2 lo, hi;
    dart_group_box(a, cells, e, end_cell, uvec2(base.x << dom.cell_bits, base.y << dom.cell_bits), lo, hi);
    const int centre = int(base_index(dom, base));
    for (int dy = -reach; dy <= reach; dy++) {
        const int64_t gy = dart_cell_gap(dy, side, lo.y, hi.y);
        const int width = rows[dy < 0 ? -dy : dy];
        if (width < 0 || !dart_gaps_reach(dom.radii, 0, gy)) continue;  // not even the centre column
        const auto reached = [&](int dx) {
            return dart_gaps_reach(dom.radii, dart_cell_gap(dx, side, lo.x, hi.x), gy);
        };
        int right = width, left = width;
        while (right > 0 && !reached(right)) right--;
        while (left > 0 && !reached(-left)) left--;
        const int row = centre + dy * int(dom.cells_x);
        for (int nb = row - left; nb <= row + right; nb++)
            if (!grid_is_sample(grid.word[nb])) set_flag(flags, uint(nb));
    }
}
#endif

// Two radii, while U is still nearly everywhere: every base cell without a sample gets darts (a
// superset of the flagged cells, so still a superset of T, and cheaper to find).
VRPD_FN void flag_free_cell(Grid grid, Uints flags, uint b) { flags.value[b] = grid_is_sample(grid.word[b]) ? 0u : 1u; }

// Two radii, for base cell b: after the flags' exclusive scan, a flagged cell joins the list of
// cells that get darts (in base cell order, as the kernels from count_darts on require).
VRPD_FN void list_dart_cell(Domain dom, Uints ranks, Cells cells_out, uint b) {
    uint rank = ranks.value[b];
    if (ranks.value[b + 1u] != rank)
        cells_out.cell[rank] = base_corner(dom, b);
}

VRPD_END
#endif
