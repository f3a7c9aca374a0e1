#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Mask mode's end, per base cell with surviving children: they go to the explicit active list
// from their rank on, from the mask apply_masks parked in the word, which becomes empty again.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint b = gl_GlobalInvocationID.x;
    if (b >= a.cell_count) return;
    uint rank = a.scan.value[b];
    if (a.scan.value[b + 1u] == rank) return;
    scatter_subcells(a.domain, a.cells_out, rank, a.grid.word[b], b, a.side);
    a.grid.word[b] = uvec2(GRID_EMPTY, GRID_EMPTY);
}
