#version 460
#extension GL_GOOGLE_include_directive : require
#ifdef VRPD_SUBGROUP_SCAN
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif
#include "common.glsl"
#include "shared/kernels.h"
// Exclusive prefix sum, pass 1: each workgroup scans SCAN_BLOCK elements in place (8 per
// invocation, contiguous for coalesced loads) and writes its block's sum. A scan of one block
// is then done: its sum is the total, written to counters[total_slot] as pass 2 would.
// Variant scan_blocks_subgroup (VRPD_SUBGROUP_SCAN, for devices whose compute shaders have
// subgroup arithmetic and subgroups of at most 64 invocations, so that the workgroup holds whole
// ones): the invocation sums are scanned within each subgroup, and each subgroup adds the totals
// of those before it, behind one barrier where the shared-memory scan takes thirteen (llvmpipe
// runs a barrier by switching between its invocations).
layout(local_size_x = 64) in;
layout(push_constant) uniform Push { ScanArgs a; };
shared uint partial[64];

void main() {
    uint block = workgroup_index();
    if (block >= a.block_count) return;  // a row's workgroups past the blocks, all of them at once
    uint base = block * SCAN_BLOCK + gl_LocalInvocationID.x * 8u;
    uint v[8];
    uint sum = 0u;
    for (uint k = 0u; k < 8u; k++) {
        v[k] = base + k < a.count ? a.data.value[base + k] : 0u;
        sum += v[k];
    }
#ifdef VRPD_SUBGROUP_SCAN
    uint inclusive = subgroupInclusiveAdd(sum);
    if (gl_SubgroupInvocationID == gl_SubgroupSize - 1u) partial[gl_SubgroupID] = inclusive;
    barrier();
    for (uint s = 0u; s < gl_SubgroupID; s++) inclusive += partial[s];
#else
    partial[gl_LocalInvocationID.x] = sum;
    barrier();
    // Hillis-Steele inclusive scan of the 64 invocation sums.
    for (uint offset = 1u; offset < 64u; offset <<= 1u) {
        uint add = gl_LocalInvocationID.x >= offset ? partial[gl_LocalInvocationID.x - offset] : 0u;
        barrier();
        partial[gl_LocalInvocationID.x] += add;
        barrier();
    }
    uint inclusive = partial[gl_LocalInvocationID.x];
#endif
    uint running = inclusive - sum;
    for (uint k = 0u; k < 8u; k++) {
        if (base + k < a.count) a.data.value[base + k] = running;
        running += v[k];
    }
    if (gl_LocalInvocationID.x == 63u) {
        a.block_sums.value[block] = inclusive;
        if (a.block_count == 1u) a.counters.value[a.total_slot] = inclusive;
    }
}
