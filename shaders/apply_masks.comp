#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
#include "masked.glsl"
layout(local_size_x_id = 0) in;
// Mask mode, per base cell without a sample: its word takes its new mask of active sub-cells. A
// pass of its own: refine_masked reads the neighbours' words. Where the refinement is scattered
// (refine_masked), the masks' sub-cells are counted here, once scatter_covers has cleared the
// covered ones. At the last mask-mode level, a base cell with surviving children parks their
// 64-bit mask in its word until scatter_masked, and masks[i] becomes their count, for the scan
// that ranks them in the explicit list.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    bool counting = scattered_refinement(a);  // the same in every invocation
    group_active_begin(counting);
    if (i < a.cell_count) {
        uint b = masked_base(a, i);
        if (masked_leaves(a.domain, a.side, a.param)) {
            uvec2 kept = uvec2(a.masks.value[i], a.work.value[i]);
            uint n = subcell_count(kept);
            if (n != 0u) a.grid.word[b] = kept;
            a.masks.value[i] = n;
        } else {
            uint mask = a.masks.value[i];
            a.grid.word[b] = masked_word(a.grid.word[b], mask);
            if (counting) group_active_add(mask);
        }
    }
    group_active_end(a, counting);
}
