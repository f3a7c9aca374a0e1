#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per dart: rejects darts off the domain or covered by earlier rounds' samples; the rest go to
// the work list. The list's order depends on scheduling, which is harmless: resolution's result
// does not depend on the order darts are visited in.
layout(push_constant) uniform Push { DartArgs a; };

void main() {
    uint d = gl_GlobalInvocationID.x;
    if (d >= a.dart_count) return;
    uint state = filter_dart(a.domain, a.grid, a.darts.dart[d]);
    a.darts.dart[d].w = state;
    if (state == DART_UNDECIDED) a.work_out.value[atomicAdd(a.counters.value[a.work_out_slot + 3u], 1u)] = d;
}
