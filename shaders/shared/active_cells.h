// The active cells of the flat quadtree (Ebeida et al. 2012; paper section 1): squares of the
// lattice that may still hold uncovered points, listed in base cell order so that the cells of one
// base cell, and the darts thrown into them, are contiguous.
#ifndef VRPD_ACTIVE_CELLS_H
#define VRPD_ACTIVE_CELLS_H
#include "bridge.h"
#include "domain.h"
#include "kernels.h"

VRPD_BEGIN

// Active cells are ordered by base cell, so the darts of one base cell are one contiguous range.
VRPD_FN bool first_in_base_cell(Domain dom, Cells cells, uint e) {
    return e == 0u || base_of_point(dom, cells.cell[e - 1u]) != base_of_point(dom, cells.cell[e]);
}

// The active cells after e that share its base cell: [e, group_end).
VRPD_FN uint group_end(Domain dom, Cells cells, uint e, uint count) {
    uint b = base_of_point(dom, cells.cell[e]);
    uint end = e + 1u;
    while (end < count && base_of_point(dom, cells.cell[end]) == b) end++;
    return end;
}

#ifdef __cplusplus
// Calls f(e, end) for each group [e, end) of list entries sharing a base cell (the list is in base
// cell order) whose first entry lies in [b, stop): each entry's base cell is found once or twice,
// where a test of every entry (first_in_base_cell) and its group's search find it three times or
// more. `single`: each entry is a base cell of its own (two radii's dart cells), a group each.
template <class F>
inline void for_each_base_group(const Domain& dom, Cells cells, std::size_t b, std::size_t stop, uint n, bool single,
                                F&& f) {
    if (single) {
        for (std::size_t i = b; i < stop; ++i) f(uint(i), uint(i + 1));
        return;
    }
    std::size_t i = b;
    while (i < stop && !first_in_base_cell(dom, cells, uint(i))) ++i;
    while (i < stop) {
        const uint end = group_end(dom, cells, uint(i), n);
        f(uint(i), end);
        i = end;
    }
}
#endif

// Child c (0..3, or 0 for a cell kept whole) of an active cell; side is the child's side.
VRPD_FN uvec2 child_corner(uvec2 corner, uint side, uint c) {
    return uvec2(corner.x + (c & 1u) * side, corner.y + (c >> 1u) * side);
}

VRPD_END
#endif
