#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
#include "masked.glsl"
layout(local_size_x_id = 0) in;
// Mask mode, per base cell without a sample: its word takes its new mask of active sub-cells. A
// pass of its own: refine_masked reads the neighbours' words. Where the refinement is scattered
// (refine_masked), a boxed cell's mask is every child of its active sub-cells (all_children)
// less those scatter_covers cleared (a border cell's, refine_masked's, holds no other child),
// and the masks' sub-cells are counted here. At the last mask-mode level, a base cell with
// surviving children parks their 64-bit mask in its word until scatter_masked, and masks[i]
// becomes their count, for the scan that ranks them in the explicit list.
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
            uvec2 w = a.grid.word[b];
            uint mask = a.masks.value[i];
            if (counting) mask &= all_children(w);
            a.grid.word[b] = masked_word(w, mask);
            if (counting) group_active_add(mask);
        }
    }
    group_active_end(a, counting);
}
