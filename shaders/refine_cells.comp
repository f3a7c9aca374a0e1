#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per base cell (run by its first active cell): which of the param (4 children, or 1: the cell
// itself) slots of each of its active cells stay active, and how many. Invocation cell_count
// writes the trailing 0 that makes the scan end in the total.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = gl_GlobalInvocationID.x;
    if (e < a.cell_count) {
        if (first_in_base_cell(a.domain, a.cells, e)) refine_base_cell(a, a.cells, a.scan, a.masks, a.grid, e);
    } else if (e == a.cell_count) {
        a.scan.value[e] = 0u;
    }
}
