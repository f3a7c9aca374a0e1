#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/kernels.h"
// Exclusive prefix sum, pass 2: one workgroup scans the block sums in chunks of 64 and writes
// the grand total to counters[total_slot].
layout(local_size_x = 64) in;
layout(push_constant) uniform Push { ScanArgs a; };
shared uint partial[64];

void main() {
    uint carry = 0u;
    uint id = gl_LocalInvocationID.x;
    for (uint start = 0u; start < a.block_count; start += 64u) {
        uint v = start + id < a.block_count ? a.block_sums.value[start + id] : 0u;
        partial[id] = v;
        barrier();
        for (uint offset = 1u; offset < 64u; offset <<= 1u) {
            uint add = id >= offset ? partial[id - offset] : 0u;
            barrier();
            partial[id] += add;
            barrier();
        }
        if (start + id < a.block_count) a.block_sums.value[start + id] = carry + partial[id] - v;
        carry += partial[63];
        barrier();
    }
    if (id == 0u) a.counters.value[a.total_slot] = carry;
}
