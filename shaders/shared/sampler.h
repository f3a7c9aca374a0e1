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

// The samples whose disks can reach base cell `cell`: gathered once per active cell, then tested
// against each of its darts or children.
VRPD_FN uint gather_samples(Domain dom, Grid grid, uvec2 cell, VRPD_OUT_ARRAY(uvec2, near, MAX_NEAR)) {
    uint count = 0u;
    int reach = int(dom.reach);
    for (int dy = -reach; dy <= reach; dy++) {
        for (int dx = -reach; dx <= reach; dx++) {
            uint nb = neighbour_cell(dom, cell, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (grid_is_sample(w)) near[count++] = w;
        }
    }
    return count;
}

// The active cells after e that share its base cell: [e, group_end).
VRPD_FN uint group_end(Domain dom, Cells cells, uint e, uint count) {
    uint b = base_of_point(dom, cells.cell[e]);
    uint end = e + 1u;
    while (end < count && base_of_point(dom, cells.cell[end]) == b) end++;
    return end;
}

// For the first active cell e of a base cell: writes the darts of all active cells of that base
// cell (cell i's at scan[i] .. scan[i+1], the exclusive prefix sums of the counts), each already
// rejected if it lies off the domain or in the disk of a sample of an earlier round, and records
// the base cell's dart range in the grid. The nearby samples are gathered once per base cell.
// Returns how many darts are still undecided.
VRPD_FN uint throw_base_cell(CellArgs a, Cells cells, Uints scan, Darts darts, Grid grid, uint e) {
    uint end_cell = group_end(a.domain, cells, e, a.cell_count);
    uint first = scan.value[e];
    uint end = scan.value[end_cell];
    uvec2 base = base_cell_of(a.domain, cells.cell[e]);
    grid.word[base_index(a.domain, base)] = uvec2(GRID_TAG | first, end);
    if (first == end) return 0u;
    uvec2 near[MAX_NEAR];
    uint near_count = gather_samples(a.domain, grid, base, near);
    uint undecided = 0u;
    for (uint i = e; i < end_cell; i++) {
        uvec2 corner = cells.cell[i];
        uint stream = cell_stream(a.domain.seed, a.round, corner);
        uint cell_first = scan.value[i];
        uint cell_end = scan.value[i + 1u];
        for (uint j = cell_first; j < cell_end; j++) {
            uvec4 dart = make_dart(stream, j - cell_first, corner, a.side);
            uvec2 p = uvec2(dart.x, dart.y);
            bool rejected = !in_domain(a.domain, p);
            for (uint k = 0u; k < near_count && !rejected; k++) rejected = in_disk(a.domain, near[k], p);
            dart.w = rejected ? DART_REJECTED : DART_UNDECIDED;
            undecided += rejected ? 0u : 1u;
            darts.dart[j] = dart;
        }
    }
    return undecided;
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

// Which of the `fanout` children (4, or 1: the cell itself) of an active cell stay active, as a
// bit mask, given the samples near its base cell. A child is dropped if it lies off the domain or
// one sample's disk covers it wholly (exact corner test, see cell_in_disk). Children covered only
// by a union of disks stay, and are split until they are single lattice points, where the test
// is exact. The children's x and y intervals are shared in pairs: 2 + 2 far offsets per sample.
VRPD_FN uint surviving_children(Domain dom, uvec2 corner, uint side, uint fanout,
                                uvec2 near[MAX_NEAR], uint near_count) {
    uint halves = fanout == 4u ? 2u : 1u;
    uint alive = 0u;
    uint lo_x[2], hi_x[2], lo_y[2], hi_y[2];
    for (uint h = 0u; h < 2u; h++) {
        lo_x[h] = corner.x + h * side;
        lo_y[h] = corner.y + h * side;
        hi_x[h] = lo_x[h] + (side - 1u);
        hi_y[h] = lo_y[h] + (side - 1u);
        if (dom.periodic == 0u) {
            hi_x[h] = hi_x[h] < dom.lattice_x ? hi_x[h] : dom.lattice_x - 1u;
            hi_y[h] = hi_y[h] < dom.lattice_y ? hi_y[h] : dom.lattice_y - 1u;
        }
    }
    for (uint c = 0u; c < fanout; c++)
        if (in_domain(dom, uvec2(lo_x[c & 1u], lo_y[c >> 1u]))) alive |= 1u << c;
    for (uint k = 0u; k < near_count && alive != 0u; k++) {
        uvec2 p = near[k];
        uint64_t fx[2], fy[2];
        for (uint h = 0u; h < halves; h++) {
            fx[h] = far_offset2(p.x, lo_x[h], hi_x[h], dom.lattice_x, dom.periodic);
            fy[h] = far_offset2(p.y, lo_y[h], hi_y[h], dom.lattice_y, dom.periodic);
        }
        for (uint c = 0u; c < fanout; c++)
            if (fx[c & 1u] + fy[c >> 1u] < dom.radius2) alive &= ~(1u << c);
    }
    return alive;
}

// For the first active cell e of a base cell: flags[i * fanout + c] = 1 for the children c of
// every active cell i of that base cell that stay active (none if the base cell holds a sample).
VRPD_FN void refine_base_cell(CellArgs a, Cells cells, Uints flags, Grid grid, uint e) {
    uint end_cell = group_end(a.domain, cells, e, a.cell_count);
    uvec2 base = base_cell_of(a.domain, cells.cell[e]);
    bool occupied = grid_is_sample(grid.word[base_index(a.domain, base)]);
    uvec2 near[MAX_NEAR];
    uint near_count = occupied ? 0u : gather_samples(a.domain, grid, base, near);
    for (uint i = e; i < end_cell; i++) {
        uint mask = occupied ? 0u : surviving_children(a.domain, cells.cell[i], a.side, a.param, near, near_count);
        for (uint c = 0u; c < a.param; c++) flags.value[i * a.param + c] = (mask >> c) & 1u;
    }
}

VRPD_END
#endif
