#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per (active cell, child): 1 if the child (or the cell itself, with param = 1) stays active.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint slots = a.cell_count * a.param;
    if (i < slots) {
        uvec2 corner = child_corner(a.cells.cell[i / a.param], a.side, i % a.param);
        a.scan.value[i] = cell_survives(a.domain, a.grid, corner, a.side) ? 1u : 0u;
    } else if (i == slots) {
        a.scan.value[i] = 0u;
    }
}
