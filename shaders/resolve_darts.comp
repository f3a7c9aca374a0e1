#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per undecided dart: one step of the arrival-order resolution (see resolve_dart). States only
// move from undecided to final, so reading a neighbour's stale state merely delays a decision.
layout(push_constant) uniform Push { DartArgs a; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= a.counters.value[a.work_in_slot + 3u]) return;
    uint d = a.work_in.value[i];
    uint state = resolve_dart(a.domain, a.grid, a.darts, d);
    if (state == DART_UNDECIDED) a.work_out.value[atomicAdd(a.counters.value[a.work_out_slot + 3u], 1u)] = d;
    else a.darts.dart[d].w = state;
}
