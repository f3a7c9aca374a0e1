#version 460
#extension GL_GOOGLE_include_directive : require
// Mask mode, per base cell with darts: writes them (those covered by earlier samples already
// rejected) and appends the undecided to work list 0, as throw_darts. Variant throw_masked_empty
// (CMakeLists.txt, VRPD_NO_SAMPLES): for a grid that holds no sample yet (throw_cell).
#include "common.glsl"
#include "shared/sampler.h"
#include "masked.glsl"
layout(local_size_x_id = 0) in;
#ifdef VRPD_NO_SAMPLES
const bool kNoSamples = true;
#else
const bool kNoSamples = false;
#endif
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    if (i >= a.cell_count) return;
    uint b = masked_base(a, i);
    uvec2 w = a.grid.word[b];
    if (!grid_is_darts(w)) return;
    uvec2 range = grid_darts(w);
    if (range.x == range.y) return;
    uint undecided = throw_masked_base(a, a.darts, a.grid, b, range.x, kNoSamples);
    if (undecided == 0u) return;
    uint slot = atomicAdd(a.counters.value[COUNTER_WORK0 + 3u], undecided);
    for (uint j = range.x; j < range.y; j++)
        if (dart_at(a.darts, j).w == DART_UNDECIDED) a.work.value[slot++] = j;
}
