#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per active cell: its Poisson number of darts this round. Invocation cell_count writes the
// trailing 0 that makes the exclusive scan end in the total.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = gl_GlobalInvocationID.x;
    if (e < a.cell_count) a.scan.value[e] = dart_count(cell_stream(a.round_key, a.cells.cell[e]), a.param);
    else if (e == a.cell_count) a.scan.value[e] = 0u;
}
