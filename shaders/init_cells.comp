#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// The first active list: every base cell, row by row (ordered by base cell, as throw_cell needs).
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    if (i < a.cell_count)
        a.cells.cell[i] = base_corner(a.domain, i);
}
