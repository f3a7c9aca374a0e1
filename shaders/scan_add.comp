#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/kernels.h"
// Exclusive prefix sum, pass 3: adds each block's offset to its elements, a workgroup a block,
// each invocation every 64th element (adjacent invocations, adjacent elements).
layout(local_size_x = 64) in;
layout(push_constant) uniform Push { ScanArgs a; };

void main() {
    uint block = workgroup_index();
    if (block >= a.block_count) return;  // a row's workgroups past the blocks, all of them at once
    uint offset = a.block_sums.value[block];
    uint end = min(a.count, (block + 1u) * SCAN_BLOCK);
    for (uint i = block * SCAN_BLOCK + gl_LocalInvocationID.x; i < end; i += 64u) a.data.value[i] += offset;
}
