#version 460
#extension GL_GOOGLE_include_directive : require
// Per undecided dart: one step of the arrival-order resolution (see resolve_dart). A decision sets
// the dart's state at once (atomically: other invocations of the pass read it); an undecided dart
// goes to the next work list. Variant resolve_darts_one (CMakeLists.txt): one radius only.
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
layout(push_constant) uniform Push { DartArgs a; };

// Dart d takes its decision; an undecided dart goes to the next work list.
void decide(uint d, uint state) {
    if (state == DART_UNDECIDED) a.work_out.value[atomicAdd(a.counters.value[a.work_out_slot + 3u], 1u)] = d;
    else set_dart_state(a.darts, d, state);
}

#ifdef VRPD_ONE_RADIUS
void main() {
    uint i = work_item();
    if (i >= a.counters.value[a.work_in_slot + 3u]) return;
    uint d = a.work_in.value[i];
    decide(d, resolve_dart(a.domain, a.grid, a.darts, d, a.param != 0u));
}
#else
// Two radii: the census settles most darts in a few reads, and the rest take gathers and T tests,
// a workgroup's together (workgroup_list.glsl).
#include "workgroup_list.glsl"

void main() {
    uint i = work_item();
    list_begin();
    if (i < a.counters.value[a.work_in_slot + 3u]) {
        uint d = a.work_in.value[i];
        uint state = census_state(dart_site(a.domain, a.darts, d), a.grid, a.darts, d, a.param != 0u);
        if (state == DART_TESTED) {
            list_add(d);
        } else {
            decide(d, state);
        }
    }
    uint d;
    if (list_take(d)) decide(d, tested_state(dart_site(a.domain, a.darts, d), a.grid, a.darts, d));
}
#endif
