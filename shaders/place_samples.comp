#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Before the first round of a run from given samples: each takes its base cell's grid word.
layout(push_constant) uniform Push { DartArgs a; };

void main() {
    uint i = work_item();
    if (i < a.dart_count) place_sample(a.domain, a.grid, a.samples.point[i]);
}
