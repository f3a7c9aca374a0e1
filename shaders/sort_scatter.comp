#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/kernels.h"
// Radix sort pass, step 2: one invocation per tile walks its keys in order and sends each to the
// next free index of its digit, so equal digits keep their order: the sort is stable, and after
// four passes the round is in (key, spatial index) order, the arrival order. A workgroup takes
// WORKGROUP_SIZE tiles: with one a workgroup, a SIMD batch of llvmpipe ran one lane in eight.
layout(local_size_x_id = 0) in;
layout(push_constant) uniform Push { SortArgs a; };

void main() {
    uint tile = work_item();
    if (tile >= a.tile_count) return;
    uint next[SORT_BUCKETS];
    for (uint b = 0u; b < SORT_BUCKETS; b++) next[b] = a.histogram.value[b * a.tile_count + tile];
    uint end = min(a.count, (tile + 1u) * SCAN_BLOCK);
    for (uint i = tile * SCAN_BLOCK; i < end; i++) {
        uint key = a.src_keys.value[i];
        uint to = next[(key >> a.shift) & 0xFFu]++;
        a.dst_keys.value[to] = key;
        a.dst_points.point[to] = a.src_points.point[i];
    }
}
