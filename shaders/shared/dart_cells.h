// Two radii (paper section 3): the base cells that get darts in a round. Darts go to the
// sample-free base cells within Rc of the active cells, a superset of T, and are kept iff in T.
#ifndef VRPD_DART_CELLS_H
#define VRPD_DART_CELLS_H
#include "bridge.h"
#include "active_cells.h"
#include "kernels.h"
#include "neighbourhood.h"

VRPD_BEGIN

// Two radii. The active cells track where U (points >= Rc from every sample) may remain; the darts
// go to base cells instead. For the active cells [e, end_cell) of one base cell (group_end): flags
// every base cell that holds no sample and lies within Rc of them. Each point of T is free, so
// its base cell holds no sample, and within Rc of U, which lies in the active cells: the flagged
// cells cover T, and darts uniform over them, kept iff in T (exact test), are uniform over T.
VRPD_FN void flag_dart_cells(CellArgs a, Cells cells, Uints flags, Grid grid, uint e, uint end_cell) {
    Domain dom = a.domain;
    uvec2 base = base_cell_of(dom, cells.cell[e]);
    int side = 1 << dom.cell_bits;
    uvec2 origin = uvec2(base.x << dom.cell_bits, base.y << dom.cell_bits);
    // The group's bounding box, in lattice units from the base cell's corner: [lo, hi].
    uvec2 lo = uvec2(uint(side), uint(side));
    uvec2 hi = uvec2(0u, 0u);
    for (uint i = e; i < end_cell; i++) {
        uvec2 c = cells.cell[i] - origin;
        lo = min(lo, c);
        hi = max(hi, c + uvec2(a.side, a.side));  // the closed square: surviving_children's cells
    }
    int reach = cover_reach(dom.radii);
    VRPD_FOR_EACH_NEIGHBOUR(dom, base, reach, dom.radii.coverage2 + uint64_t(1), dx, dy, nb) {
        int64_t gx =
            dx > 0 ? int64_t(dx * side - int(hi.x)) : (dx < 0 ? int64_t(int(lo.x) - (dx + 1) * side + 1) : int64_t(0));
        int64_t gy =
            dy > 0 ? int64_t(dy * side - int(hi.y)) : (dy < 0 ? int64_t(int(lo.y) - (dy + 1) * side + 1) : int64_t(0));
        if (reaches(dom.radii, uint64_t(gx * gx + gy * gy)) && !grid_is_sample(grid.word[nb])) set_flag(flags, nb);
    }
}

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
