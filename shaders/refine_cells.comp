#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per active cell: flags its param (4 children, or 1: itself) slots 1 if they stay active.
// Invocation cell_count writes the trailing 0 that makes the scan end in the total.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = gl_GlobalInvocationID.x;
    if (e < a.cell_count) {
        uint mask = surviving_children(a.domain, a.grid, a.cells.cell[e], a.side, a.param);
        for (uint c = 0u; c < a.param; c++) a.scan.value[e * a.param + c] = (mask >> c) & 1u;
    } else if (e == a.cell_count) {
        a.scan.value[e * a.param] = 0u;
    }
}
