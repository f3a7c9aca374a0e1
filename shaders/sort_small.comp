#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/kernels.h"
// The radix sort of at most SORT_SMALL elements (a round with few samples), in one workgroup and
// one dispatch: each element goes to its rank among all by (key, index), the order the four
// stable radix passes give, in place once every invocation has ranked its own.
layout(local_size_x = 128) in;
layout(push_constant) uniform Push { SortArgs a; };
const uint kPer = SORT_SMALL / 128u;

void main() {
    uint n = a.count;
    uint id = gl_LocalInvocationID.x;
    uint key[kPer], rank[kPer];
    uvec2 point[kPer];
    for (uint e = 0u; e < kPer; e++) {
        uint i = id + 128u * e;
        if (i >= n) break;
        key[e] = a.src_keys.value[i];
        point[e] = a.src_points.point[i];
        rank[e] = 0u;
        for (uint j = 0u; j < n; j++) {
            uint other = a.src_keys.value[j];
            rank[e] += (other < key[e] || (other == key[e] && j < i)) ? 1u : 0u;
        }
    }
    memoryBarrierBuffer();
    barrier();  // every element read before any is written
    for (uint e = 0u; e < kPer; e++) {
        if (id + 128u * e >= n) break;
        a.src_keys.value[rank[e]] = key[e];
        a.src_points.point[rank[e]] = point[e];
    }
}
