#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per (active cell, child): survivors go to the next active list, in order (ranks from the scan).
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= a.cell_count * a.param) return;
    uint rank = a.scan.value[i];
    if (a.scan.value[i + 1u] == rank) return;
    a.cells_out.cell[rank] = child_corner(a.cells.cell[i / a.param], a.side, i % a.param);
}
