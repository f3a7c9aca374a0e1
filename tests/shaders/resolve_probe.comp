#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x = 64) in;
// Test kernel: one arrival-order resolution pass (resolve_dart) over darts [0, count), decisions
// to `decisions`, so a test can compare the device's pass with the host's on the same state.
layout(push_constant) uniform Push { Domain domain; Darts darts; Grid grid; Uints decisions; uint count; };

void main() {
    uint d = gl_GlobalInvocationID.x;
    if (d >= count) return;
    uint state = dart_at(darts, d).w;
    decisions.value[d] = state == DART_UNDECIDED ? resolve_dart(domain, grid, darts, d, false) : state;
}
