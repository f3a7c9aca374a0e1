#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/kernels.h"
// Exclusive prefix sum, pass 3: adds each block's offset to its elements.
layout(local_size_x_id = 0) in;
layout(push_constant) uniform Push { ScanArgs a; };

void main() {
    uint i = work_item();
    if (i < a.count) a.data.value[i] += a.block_sums.value[i / SCAN_BLOCK];
}
