#version 460
#extension GL_GOOGLE_include_directive : require
// Per undecided dart: one step of the arrival-order resolution (see resolve_dart). It reads the
// darts' states and writes only its own work-list slot (the decision) and the next work list;
// apply_decisions writes the states after the pass. Variant resolve_darts_one (CMakeLists.txt):
// one radius only.
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
layout(push_constant) uniform Push { DartArgs a; };

#ifdef VRPD_ONE_RADIUS
void main() {
    uint i = work_item();
    if (i >= a.counters.value[a.work_in_slot + 3u]) return;
    uint d = a.work_in.value[i];
    uint state = resolve_dart(a.domain, a.grid, a.darts, d, a.param != 0u);
    a.work_in.value[i] = d | (state << DECISION_SHIFT);
    if (state == DART_UNDECIDED) a.work_out.value[atomicAdd(a.counters.value[a.work_out_slot + 3u], 1u)] = d;
}
#else
// Two radii: the census settles most darts in a few reads, and the rest take gathers and T tests.
// A workgroup first lists its darts that the census leaves in shared memory, then its first
// invocations test them, so that a SIMD batch of lanes (llvmpipe's 8, a GPU's warp) runs the tests
// for the darts it holds rather than for any one of its lanes' darts.
shared uint pending[WORKGROUP_SIZE];
shared uint pending_count;

// Work-list slot i (dart d) takes its decision; an undecided dart goes to the next work list.
void decide(uint i, uint d, uint state) {
    a.work_in.value[i] = d | (state << DECISION_SHIFT);
    if (state == DART_UNDECIDED) a.work_out.value[atomicAdd(a.counters.value[a.work_out_slot + 3u], 1u)] = d;
}

void main() {
    uint i = work_item();
    if (gl_LocalInvocationID.x == 0u) pending_count = 0u;
    barrier();
    if (i < a.counters.value[a.work_in_slot + 3u]) {
        uint d = a.work_in.value[i];
        uint state = census_state(dart_site(a.domain, a.darts, d), a.grid, a.darts, d, a.param != 0u);
        if (state == DART_TESTED) {
            pending[atomicAdd(pending_count, 1u)] = i;
        } else {
            decide(i, d, state);
        }
    }
    barrier();
    if (gl_LocalInvocationID.x < pending_count) {
        uint j = pending[gl_LocalInvocationID.x];
        uint d = a.work_in.value[j];
        decide(j, d, tested_state(dart_site(a.domain, a.darts, d), a.grid, a.darts, d));
    }
}
#endif
