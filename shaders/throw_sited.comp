#version 460
#extension GL_GOOGLE_include_directive : require
// Per dart of the round (a.cell_count: the darts): makes it at the site its record holds (the
// marking kernels write them), rejects it if it lies off the domain or an earlier round's sample
// inhibits it, and appends it to work list 0 if it is left undecided. The list's order depends on
// scheduling, which is harmless: resolution's result does not depend on the visiting order.
// Variant throw_sited_empty (CMakeLists.txt, VRPD_NO_SAMPLES): for a grid that holds no sample
// yet, where only the domain is tested.
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
#ifdef VRPD_NO_SAMPLES
const bool kNoSamples = true;
#else
const bool kNoSamples = false;
#endif
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint j = work_item();
    if (j >= a.cell_count) return;
    if (throw_sited(a, a.darts, a.grid, j, kNoSamples) == DART_REJECTED)
        set_dart_state(a.darts, j, DART_REJECTED);
    else
        a.work.value[atomicAdd(a.counters.value[COUNTER_WORK0 + 3u], 1u)] = j;
}
