#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/kernels.h"
// Radix sort pass, step 1: the digit counts of one tile of SCAN_BLOCK keys, stored digit-major
// (histogram[digit * tile_count + tile]) so that one exclusive scan gives every (digit, tile)
// its first output index. Shared-memory atomics: counts do not depend on their order.
layout(local_size_x = 64) in;
layout(push_constant) uniform Push { SortArgs a; };
shared uint bins[SORT_BUCKETS];

void main() {
    uint tile = workgroup_index();
    if (tile >= a.tile_count) return;  // a row's workgroups past the tiles, all of them at once
    uint id = gl_LocalInvocationID.x;
    for (uint b = id; b < SORT_BUCKETS; b += 64u) bins[b] = 0u;
    barrier();
    uint base = tile * SCAN_BLOCK + id * 8u;
    for (uint k = 0u; k < 8u; k++)
        if (base + k < a.count) atomicAdd(bins[(a.src_keys.value[base + k] >> a.shift) & 0xFFu], 1u);
    barrier();
    for (uint b = id; b < SORT_BUCKETS; b += 64u) a.histogram.value[b * a.tile_count + tile] = bins[b];
}
