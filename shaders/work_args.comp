#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// One invocation: the indirect dispatch for a work list (workgroups of WORKGROUP_SIZE in rows of
// at most a.max_groups), and an empty list to append to (none where other_slot is slot).
layout(push_constant) uniform Push { WorkArgs a; };

void main() {
    uint count = a.counters.value[a.slot + 3u];
    uint groups = count / WORKGROUP_SIZE + (count % WORKGROUP_SIZE != 0u ? 1u : 0u);
    uint row = min(groups, a.max_groups);
    a.counters.value[a.slot] = row;
    a.counters.value[a.slot + 1u] = row == 0u ? 1u : groups / row + (groups % row != 0u ? 1u : 0u);
    a.counters.value[a.slot + 2u] = 1u;
    if (a.other_slot != a.slot) a.counters.value[a.other_slot + 3u] = 0u;
}
