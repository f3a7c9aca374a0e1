#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per active cell that is the first of its base cell: the grid word becomes the accepted sample
// or empty; scan[j] flags accepted darts. Invocation 0 writes the trailing 0 at scan[darts].
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = work_item();
    if (e == 0u) a.scan.value[a.param] = 0u;
    if (e < a.cell_count && first_in_base_cell(a.domain, a.cells, e))
        commit_base_cell(a.grid, a.darts, a.scan, a.counters, base_of_point(a.domain, a.cells.cell[e]));
}
