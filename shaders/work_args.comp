#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// One invocation: the indirect dispatch for a work list, and an empty list to append to.
layout(push_constant) uniform Push { WorkArgs a; };

void main() {
    uint count = a.counters.value[a.slot + 3u];
    a.counters.value[a.slot] = (count + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    a.counters.value[a.slot + 1u] = 1u;
    a.counters.value[a.slot + 2u] = 1u;
    a.counters.value[a.other_slot + 3u] = 0u;
}
