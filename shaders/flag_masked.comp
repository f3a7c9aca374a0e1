#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Mask mode, per base cell: flags it if it has active sub-cells, for the scan that lists the
// active base cells (masked.glsl). Invocation cell_count clears the flag after the last base
// cell, for the scan's total.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint b = work_item();
    if (b < a.cell_count) a.scan.value[b] = masked_active(a.grid.word[b]) ? 1u : 0u;
    else if (b == a.cell_count) a.scan.value[b] = 0u;
}
