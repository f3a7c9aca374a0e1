#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
#include "masked.glsl"
layout(local_size_x_id = 0) in;
// Mask mode's end, per base cell with surviving children: they go to the explicit active list
// from their rank on, from the mask apply_masks parked in the word, which becomes empty again.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    if (i >= a.cell_count) return;
    uint rank = a.scan.value[i];
    if (a.scan.value[i + 1u] == rank) return;
    uint b = masked_base(a, i);
    scatter_subcells(a.domain, a.cells_out, rank, a.grid.word[b], b, a.side);
    a.grid.word[b] = uvec2(GRID_EMPTY, GRID_EMPTY);
}
