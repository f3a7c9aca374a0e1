#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Two radii, per base cell: flags it for darts if it holds no sample (see flag_free_cell).
// Invocation cell_count clears the flag after the last base cell, for the scan's total.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint b = work_item();
    if (b < a.cell_count) flag_free_cell(a.grid, a.scan, b);
    else if (b == a.cell_count) a.scan.value[b] = 0u;
}
