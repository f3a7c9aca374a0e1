// The bodies of the sampler's kernels (one active cell or one dart each), shared by the Vulkan
// shaders and the CPU backends. Flat-quadtree maximal Poisson-disk sampling (Ebeida et al. 2012)
// driven as exact random sequential adsorption: paper section 1, Eqs. 1-4.
#ifndef VRPD_SAMPLER_H
#define VRPD_SAMPLER_H
#include "bridge.h"
#include "darts.h"
#include "domain.h"
#include "kernels.h"

VRPD_BEGIN

VRPD_FN uint base_of_point(Domain dom, uvec2 p) { return base_index(dom, base_cell_of(dom, p)); }

// Active cells are ordered by base cell, so the darts of one base cell are one contiguous range.
VRPD_FN bool first_in_base_cell(Domain dom, Cells cells, uint e) {
    return e == 0u || base_of_point(dom, cells.cell[e - 1u]) != base_of_point(dom, cells.cell[e]);
}
VRPD_FN bool last_in_base_cell(Domain dom, Cells cells, uint e, uint count) {
    return e + 1u == count || base_of_point(dom, cells.cell[e + 1u]) != base_of_point(dom, cells.cell[e]);
}

// Writes the darts of active cell e at scan[e] .. scan[e+1] (the exclusive prefix sums of the
// counts) and records the dart range of its base cell in the grid.
VRPD_FN void throw_cell(CellArgs a, Cells cells, Uints scan, Darts darts, Grid grid, uint e) {
    uvec2 corner = cells.cell[e];
    uint first = scan.value[e];
    uint end = scan.value[e + 1u];
    uint stream = cell_stream(a.domain.seed, a.round, corner);
    for (uint j = first; j < end; j++) darts.dart[j] = make_dart(stream, j - first, corner, a.side);
    uint b = base_of_point(a.domain, corner);
    if (first_in_base_cell(a.domain, cells, e)) grid.word[b].x = GRID_TAG | first;
    if (last_in_base_cell(a.domain, cells, e, a.cell_count)) grid.word[b].y = end;
}

// A dart off the domain, or inside the disk of a sample of an earlier round, is rejected at once.
VRPD_FN uint filter_dart(Domain dom, Grid grid, uvec4 dart) {
    uvec2 p = uvec2(dart.x, dart.y);
    if (!in_domain(dom, p)) return DART_REJECTED;
    uvec2 cell = base_cell_of(dom, p);
    int reach = int(dom.reach);
    for (int dy = -reach; dy <= reach; dy++) {
        for (int dx = -reach; dx <= reach; dx++) {
            uint nb = neighbour_cell(dom, cell, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (grid_is_sample(w) && in_disk(dom, w, p)) return DART_REJECTED;
        }
    }
    return DART_UNDECIDED;
}

// One step of the exact parallel resolution of a round: dart d is accepted once every earlier
// conflicting dart (in arrival order) is rejected, and rejected as soon as one is accepted.
// Decisions are only taken when they are final, so the outcome is the sequential process's
// whatever the order and timing of the steps; only the number of passes varies.
VRPD_FN uint resolve_dart(Domain dom, Grid grid, Darts darts, uint d) {
    uvec4 me = darts.dart[d];
    uvec2 p = uvec2(me.x, me.y);
    uvec2 cell = base_cell_of(dom, p);
    bool waiting = false;
    int reach = int(dom.reach);
    for (int dy = -reach; dy <= reach; dy++) {
        for (int dx = -reach; dx <= reach; dx++) {
            uint nb = neighbour_cell(dom, cell, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (!grid_is_darts(w)) continue;
            for (uint j = w.x & ~GRID_TAG; j < w.y; j++) {
                if (j == d) continue;
                uvec4 other = darts.dart[j];
                if (other.w == DART_REJECTED || !arrives_before(other.z, j, me.z, d)) continue;
                if (!in_disk(dom, uvec2(other.x, other.y), p)) continue;
                if (other.w == DART_ACCEPTED) return DART_REJECTED;
                waiting = true;
            }
        }
    }
    return waiting ? DART_UNDECIDED : DART_ACCEPTED;
}

// The textbook test, for the serial backend: does an already accepted dart of this round cover d?
VRPD_FN bool covered_by_accepted_dart(Domain dom, Grid grid, Darts darts, uint d) {
    uvec4 me = darts.dart[d];
    uvec2 p = uvec2(me.x, me.y);
    uvec2 cell = base_cell_of(dom, p);
    int reach = int(dom.reach);
    for (int dy = -reach; dy <= reach; dy++) {
        for (int dx = -reach; dx <= reach; dx++) {
            uint nb = neighbour_cell(dom, cell, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (!grid_is_darts(w)) continue;
            for (uint j = w.x & ~GRID_TAG; j < w.y; j++) {
                uvec4 other = darts.dart[j];
                if (j != d && other.w == DART_ACCEPTED && in_disk(dom, uvec2(other.x, other.y), p)) return true;
            }
        }
    }
    return false;
}

// Ends the round for the base cell of active cell e (called for the first active cell of each
// base cell): the grid word becomes the accepted sample, if any (at most one: the base cell's
// diagonal is shorter than r), else empty again; flags[j] = 1 marks accepted darts for emission.
VRPD_FN void commit_base_cell(Grid grid, Darts darts, Uints flags, uint b) {
    uvec2 w = grid.word[b];
    uvec2 result = uvec2(GRID_EMPTY, GRID_EMPTY);
    for (uint j = w.x & ~GRID_TAG; j < w.y; j++) {
        uvec4 dart = darts.dart[j];
        bool accepted = dart.w == DART_ACCEPTED;
        flags.value[j] = accepted ? 1u : 0u;
        if (accepted) result = uvec2(dart.x, dart.y);
    }
    grid.word[b] = result;
}

// Child c (0..3, or 0 for a cell kept whole) of an active cell; side is the child's side.
VRPD_FN uvec2 child_corner(uvec2 corner, uint side, uint c) {
    return uvec2(corner.x + (c & 1u) * side, corner.y + (c >> 1u) * side);
}

// A cell stays active unless it lies off the domain, its base cell holds a sample, or one
// sample's disk covers it wholly (exact corner test). Cells covered only by a union of disks
// stay, and are split until they are single lattice points, where the test is exact.
VRPD_FN bool cell_survives(Domain dom, Grid grid, uvec2 corner, uint side) {
    if (!in_domain(dom, corner)) return false;
    uvec2 cell = base_cell_of(dom, corner);
    if (grid_is_sample(grid.word[base_index(dom, cell)])) return false;
    int reach = int(dom.reach);
    for (int dy = -reach; dy <= reach; dy++) {
        for (int dx = -reach; dx <= reach; dx++) {
            uint nb = neighbour_cell(dom, cell, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (grid_is_sample(w) && cell_in_disk(dom, corner, side, w)) return false;
        }
    }
    return true;
}

VRPD_END
#endif
