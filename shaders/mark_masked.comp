#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
#include "masked.glsl"
layout(local_size_x_id = 0) in;
// Mask mode, per base cell without a sample: its word becomes a packed darts word from its first
// dart on (none where no sub-cell is active), so that a row of base cells mostly begins and ends
// with a darts word (row_darts), and an active cell's darts' records get their sites for
// throw_sited (shared/throw.h).
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    if (i >= a.cell_count) return;
    uint b = masked_base(a, i);
    uvec2 w = a.grid.word[b];
    if (grid_is_sample(w)) return;
    a.grid.word[b] = numbered_word(w, a.scan.value[i]);
    site_masked_darts(a, a.darts, w, b, a.scan.value[i]);
}
