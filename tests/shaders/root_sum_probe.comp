#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/t_membership.h"
layout(local_size_x = 64) in;
// Test kernel: sign_of_root_sum on the device (128-bit squares from 32-bit halves) for a batch of
// (a, l, b, m), so a test can compare it with the host's exact sign.
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Cases { i64vec4 value[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Signs { int value[]; };
layout(push_constant) uniform Push { Cases cases; Signs signs; uint count; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    i64vec4 c = cases.value[i];
    signs.value[i] = sign_of_root_sum(c.x, uint64_t(c.y), c.z, uint64_t(c.w));
}
