#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per entry of the work list a resolution pass just read: its decision becomes the dart's state.
layout(push_constant) uniform Push { DartArgs a; };

void main() {
    uint i = work_item();
    if (i >= a.counters.value[a.work_in_slot + 3u]) return;
    uint v = a.work_in.value[i];
    uint state = v >> DECISION_SHIFT;
    set_dart_state(a.darts, v & (MAX_ROUND_DARTS - 1u), state);
}
