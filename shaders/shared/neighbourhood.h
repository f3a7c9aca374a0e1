// The one neighbourhood scan: every kernel that looks at the base cells around a point or a cell
// (conflicts, cover tests, T tests, the dart cells of two radii) visits them through
// VRPD_FOR_EACH_NEIGHBOUR, which leaves out the cells no point of which can lie within the
// scan's radius and the cells off a free boundary.
#ifndef VRPD_NEIGHBOURHOOD_H
#define VRPD_NEIGHBOURHOOD_H
#include "bridge.h"
#include "domain.h"
#include "grid.h"

VRPD_BEGIN

// Is base cell `cell` at least `reach` cells from every side of the grid? Then a scan within that
// reach meets no side: its neighbours' indices are plain offsets, whatever the domain's wrap.
VRPD_FN bool inside_by(VRPD_IN(Domain) dom, uvec2 cell, int reach) {
    uint r = uint(reach);
    return cell.x >= r && cell.x + r < dom.cells_x && cell.y >= r && cell.y + r < dom.cells_y;
}

// An inner cell is inside by influence_reach, the widest scan's: every scan of it is plain.
VRPD_FN bool inner_cell(VRPD_IN(Domain) dom, uvec2 cell) {
    return inside_by(dom, cell, int(influence_reach(dom.radii)));
}

// The first and last offsets a scan within `reach` of base cell coordinate c visits along an axis
// (of n cells): all of [-reach, reach] on a torus, those that stay on the grid on a free boundary.
VRPD_FN int first_offset(VRPD_IN(Domain) dom, uint c, int reach) {
    return dom.lattice.periodic != 0u ? -reach : max(-reach, -int(c));
}
VRPD_FN int last_offset(VRPD_IN(Domain) dom, uint c, uint n, int reach) {
    return dom.lattice.periodic != 0u ? reach : min(reach, int(n) - 1 - int(c));
}

// Base cell coordinate c (a cell's plus an offset) on an axis of n cells, wrapped on a torus;
// make_plan guarantees influence_reach <= cells per side, so one wrap step suffices.
VRPD_FN int wrapped_cell(int c, int n) { return c < 0 ? c + n : (c >= n ? c - n : c); }

// The columns a scan of row dy (|dy| <= reach) must visit: |dx| <= row_reach, the cells some of
// whose points are closer than sqrt(limit2) to some point of the centre cell; -1 if none is.
VRPD_FN int computed_row_reach(Domain dom, int dy, int reach, uint64_t limit2) {
    int w = reach;
    while (w >= 0 && cell_gap2(dom, w, dy) >= limit2) w--;
    return w;
}

// computed_row_reach for the conflict scans (inhibition2, conflict_reach), which the plan
// stores in bits 24-31 of Radii::reach: 0 to MAX_REACH, since the centre column of a row within
// the reach is always within it. Those scans run for every dart (and with one radius for every
// cell test too), so each reads its rows' reach from the plan instead of a loop of gap tests.
VRPD_FN int conflict_row(Radii r, int dy) { return int((r.reach >> (24u + 2u * uint(dy < 0 ? -dy : dy))) & 3u); }

VRPD_FN int row_reach(Domain dom, int dy, int reach, uint64_t limit2) {
    if (limit2 == dom.radii.inhibition2 && reach == conflict_reach(dom.radii)) return conflict_row(dom.radii, dy);
    return computed_row_reach(dom, dy, reach, limit2);
}

// Do inner cells see a straight domain (local_domain)? On a free boundary, or on a torus at least
// 2 (reach + 1) cells wide.
VRPD_FN bool straight_inner_cells(VRPD_IN(Domain) dom) {
    uint r = influence_reach(dom.radii);
    return dom.lattice.periodic == 0u || (dom.cells_x >= 2u * r + 2u && dom.cells_y >= 2u * r + 2u);
}

// The domain as seen from base cell `cell`: on a torus at least 2 (reach + 1) cells wide, a cell
// whose neighbourhood does not wrap sees every relevant offset shorter than half the torus, so
// straight distances equal torus distances there and the wrap can be skipped. Every predicate
// gives the same answer with either domain; this one is cheaper.
VRPD_FN Domain local_domain(VRPD_IN(Domain) dom, uvec2 cell) {
    Domain local = dom;
    if (dom.lattice.periodic != 0u && inner_cell(dom, cell) && straight_inner_cells(dom)) local.lattice.periodic = 0u;
    return local;
}

// Visits the base cells (dx, dy) around base cell `cell` within `reach` rows and columns whose
// points may lie closer than sqrt(limit2) to a point of `cell`, row by row, as `nb`, their index
// (an int: base cells number fewer than 2^31). The body follows as a block; `continue` goes to the
// next cell, `return` ends the scan. GLSL has neither closures nor function pointers: a loop
// macro keeps the scan written once while every compiler sees two plain nested loops. The
// loops' bounds leave out the rows and columns off a free boundary, and a row's column steps
// along, wrapping at the torus's side, so that a cell costs a few adds and no branch (a SIMD
// batch of llvmpipe runs both sides of a branch).
#define VRPD_FOR_EACH_NEIGHBOUR(dom, cell, reach, limit2, dx, dy, nb)                                                  \
    for (int dy = first_offset(dom, (cell).y, reach), vrpd_last_dy = last_offset(dom, (cell).y, (dom).cells_y, reach), \
             nb = 0;                                                                                                   \
         dy <= vrpd_last_dy; dy++)                                                                                     \
        for (int vrpd_width = row_reach(dom, dy, reach, limit2), dx = first_offset(dom, (cell).x, vrpd_width),         \
                 vrpd_last_dx = last_offset(dom, (cell).x, (dom).cells_x, vrpd_width),                                 \
                 vrpd_x = wrapped_cell(int((cell).x) + dx, int((dom).cells_x)),                                        \
                 vrpd_row = wrapped_cell(int((cell).y) + dy, int((dom).cells_y)) * int((dom).cells_x);                 \
             dx <= vrpd_last_dx; dx++, vrpd_x = vrpd_x + 1 == int((dom).cells_x) ? 0 : vrpd_x + 1)                     \
            if (((nb = vrpd_row + vrpd_x), true))

// This round's darts [first, end) in a grid word, or an empty range if it holds none.
VRPD_FN uvec2 darts_in(uvec2 word) { return grid_is_darts(word) ? grid_darts(word) : uvec2(0u, 0u); }

// Visits this round's darts, as index j, in the base cells VRPD_FOR_EACH_NEIGHBOUR visits.
#define VRPD_FOR_EACH_NEARBY_DART(dom, grid, cell, reach, limit2, j)                              \
    VRPD_FOR_EACH_NEIGHBOUR(dom, cell, reach, limit2, vrpd_dx, vrpd_dy, vrpd_nb)                  \
        for (uint j = darts_in(grid.word[vrpd_nb]).x, vrpd_end = darts_in(grid.word[vrpd_nb]).y; j < vrpd_end; j++)

VRPD_END
#endif
