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
// their number to counters[COUNTER_ACTIVE]. At the last mask-mode level (masked_leaves) the 64-bit
// mask goes to masks[i] and work[i] (low and high halves), for apply_masks. Invocation
// cell_count writes the trailing 0 that the scan of the counts needs.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    if (i < a.cell_count) {
        uvec2 kept = refine_masked_base(a, a.grid, masked_base(a, i));
        a.masks.value[i] = kept.x;
        if (masked_leaves(a.domain, a.side, a.param)) {
            a.work.value[i] = kept.y;
        } else {
            uint n = uint(bitCount(kept.x));
            if (n != 0u) atomicAdd(a.counters.value[COUNTER_ACTIVE], n);
        }
    } else if (i == a.cell_count) {
        a.masks.value[i] = 0u;
    }
}
