#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per active cell: its surviving children go to the next active list, in order (ranks from the scan).
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    if (i < a.cell_count) scatter_children(a, a.cells, a.scan, a.masks, a.cells_out, i);
}
