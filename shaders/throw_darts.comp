#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per base cell (run by its first active cell): writes the darts of its active cells (those
// covered by earlier samples already rejected) and appends its undecided darts to work list 0.
// The list's order depends on scheduling, which is harmless: resolution's result does not depend
// on the visiting order.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = work_item();
    if (e >= a.cell_count || !first_in_base_cell(a.domain, a.cells, e)) return;
    uint undecided = throw_base_cell(a, a.cells, a.scan, a.darts, a.grid, e);
    if (undecided == 0u) return;
    uint slot = atomicAdd(a.counters.value[COUNTER_WORK0 + 3u], undecided);
    uvec2 range = grid_darts(a.grid.word[base_of_point(a.domain, a.cells.cell[e])]);
    for (uint j = range.x; j < range.y; j++)
        if (dart_at(a.darts, j).w == DART_UNDECIDED) a.work.value[slot++] = j;
}
