#version 460
#extension GL_GOOGLE_include_directive : require
#define VRPD_ONE_RADIUS  // mask mode serves one radius only (shared/domain.h)
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Mask mode's scattered refinement, per sample: the children its disk covers wholly leave the
// masks of the boxed base cells around it (scatter_cover). Runs after refine_masked has written
// the boxed cells' masks, and before apply_masks, over the samples (`cells`): the cell_count of
// earlier rounds and this round's, counters[COUNTER_ACCEPTED]. A pass over the samples, not the
// base cells (about three a sample), leaves no SIMD lane without one.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    if (i >= a.cell_count + a.counters.value[COUNTER_ACCEPTED]) return;
    scatter_cover(a.domain, scatter_box(a.domain, a.side, a.param), a.side, a.cells.cell[i], a.masks);
}
