#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/t_membership.h"
layout(local_size_x = 64) in;
// Test kernel: evaluates the T-membership test of shared/t_membership.h on the device for a batch of
// configurations, so a test can compare it with the host's answers. A configuration is
// PROBE_WORDS ivec2: (n, in_disk), r2 as (low, high) 32 bits, the box's lo and hi, then n disk centres.
const uint PROBE_WORDS = 68u;
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Probes { ivec2 word[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Results { uint value[]; };
layout(push_constant) uniform Push { Probes probes; Results results; uint count; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    uint base = i * PROBE_WORDS;
    uint n = uint(probes.word[base].x);
    uint64_t r2 = uint64_t(uint(probes.word[base + 1u].x)) | (uint64_t(uint(probes.word[base + 1u].y)) << 32);
    for (uint k = 0u; k < n; k++) disk_at[k] = probes.word[base + 4u + k];
    bool in_disk = probes.word[base].y != 0;
    results.value[i] = reaches_uncovered(n, r2, probes.word[base + 2u], probes.word[base + 3u], in_disk);
}
