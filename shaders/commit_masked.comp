#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
#include "masked.glsl"
layout(local_size_x_id = 0) in;
// Mask mode, per base cell with darts: commit_base_cell. Invocation 0 writes the trailing 0 at
// scan[darts] (param).
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    if (i == 0u) a.scan.value[a.param] = 0u;
    if (i >= a.cell_count) return;
    uint b = masked_base(a, i);
    if (grid_is_darts(a.grid.word[b])) commit_base_cell(a.grid, a.darts, a.scan, a.counters, b);
}
