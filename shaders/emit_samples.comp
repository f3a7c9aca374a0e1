#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per dart: an accepted dart becomes sample param + (its rank among accepted darts), in
// spatial order; its key goes to the round's key list, for sort_* to put the round in arrival
// order. Every dart has a key slot: those not accepted fill the slots after the accepted darts'
// with 2^32 - 1, which a sort of all the slots keeps last (VulkanEngine::round).
layout(push_constant) uniform Push { DartArgs a; };

void main() {
    uint d = work_item();
    if (d >= a.dart_count) return;
    uint rank = a.scan.value[d];
    if (a.scan.value[d + 1u] == rank) {
        a.sample_keys.value[a.scan.value[a.dart_count] + d - rank] = ~0u;
        return;
    }
    uvec4 dart = dart_at(a.darts, d);
    a.samples.point[a.param + rank] = uvec2(dart.x, dart.y);
    a.sample_keys.value[rank] = dart.z;
}
