#version 460
#extension GL_GOOGLE_include_directive : require
#define VRPD_ONE_RADIUS  // mask mode serves one radius only (shared/domain.h)
// A base cell's samples are always gathered here: surviving_children's scan of the grid is left
// out, as llvmpipe runs a branch's code whether a lane takes it or not (shared/radii.h).
#define VRPD_GATHERED
#include "common.glsl"
#include "shared/sampler.h"
#include "masked.glsl"
layout(local_size_x_id = 0) in;
// Mask mode, per base cell: the mask of its surviving children (or cells) goes to masks[i], and
// their number to counters[COUNTER_ACTIVE]. Where the refinement is scattered (over every base
// cell, into 4 or 16 sub-cells: scatter_box), invocation i serves the i-th base cell of the box's
// border (border_base) and writes its mask to masks[b]; the boxed cells' masks start full (the
// engine fills them), scatter_covers clears the covered children, and apply_masks counts them
// all. At the last mask-mode level (masked_leaves) the 64-bit mask goes to masks[i] and work[i]
// (low and high halves), for apply_masks. Invocation cell_count writes the trailing 0 that the
// scan of the counts needs.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    // The same in every invocation. Counted here unless scattered (apply_masks counts) or at the
    // last level (the scan counts).
    bool scattered = scattered_refinement(a);
    bool leaves = masked_leaves(a.domain, a.side, a.param);
    bool counting = !scattered && !leaves;
    group_active_begin(counting);
    if (i < a.cell_count) {
        uint b = scattered ? border_base(a.domain, scatter_box(a.domain, a.side, a.param), i) : masked_base(a, i);
        uvec2 kept = refine_masked_base(a, a.grid, b);
        a.masks.value[scattered ? b : i] = kept.x;
        if (leaves)
            a.work.value[i] = kept.y;
        else if (counting)
            group_active_add(kept.x);
    } else if (i == a.cell_count && !scattered) {
        a.masks.value[i] = 0u;
    }
    group_active_end(a, counting);
}
