#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// One invocation per gated dispatch command: while darts are left undecided, the round's end
// recorded after this kernel in the same submit must not run (VulkanEngine::round).
layout(push_constant) uniform Push { GateArgs a; };

void main() {
    uint i = work_item();
    if (i < a.count && a.counters.value[a.slot] != 0u) a.table.value[3u * i] = 0u;
}
