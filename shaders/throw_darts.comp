#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per active cell: writes its darts and its base cell's dart range.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = gl_GlobalInvocationID.x;
    if (e < a.cell_count) throw_cell(a, a.cells, a.scan, a.darts, a.grid, e);
}
