// Exact arrival-order resolution of a round's darts (paper section 1, Eq. 4): the accepted
// darts are those the sequential process would accept, read in arrival order. One step for the
// Vulkan engine's passes and the cpu backend, the textbook decision for the serial oracle.
#ifndef VRPD_RESOLVE_H
#define VRPD_RESOLVE_H
#include "bridge.h"
#include "darts.h"
#include "kernels.h"
#include "neighbourhood.h"
#include "resolve_two_radii.h"

VRPD_BEGIN

// One step of the exact parallel resolution of a round: dart d is accepted once every earlier
// conflicting dart (in arrival order) is rejected, and rejected as soon as one is accepted.
// Decisions are only taken when they are final, so the outcome is the sequential process's.
// A step reads the other darts' states once each, as they stand: a state it reads is undecided or
// final, and either way the decision it supports is the sequential one. So a Vulkan pass sets
// each decision as it takes it, and the darts after it in the pass see it (fewer passes).
// `first_pass`: the Vulkan engine's first pass of a round, where few darts are accepted yet: the
// first earlier undecided dart in conflict leaves d undecided, without a scan for an accepted one
// (what stopping there saves: docs/performance.md). With two radii such a pass leaves the T tests
// of a dart with an undecided dart before it within Rc to the passes after it.
VRPD_FN uint resolve_dart(Domain global, Grid grid, Darts darts, uint d, bool first_pass) {
#ifndef VRPD_ONE_RADIUS  // glslang does not fold two_radii(): only the guard keeps T's code out of SPIR-V
    if (two_radii(global.radii)) return resolve_dart_two_radii(global, grid, darts, d, first_pass);
#endif
    DartSite s = dart_site(global, darts, d);
    bool waiting = false;
    int reach = conflict_reach(s.dom.radii);
    VRPD_FOR_EACH_NEARBY_DART(s.dom, grid, s.cell, reach, s.dom.radii.inhibition2, j) {
        if (j == d) continue;
        uvec4 other = dart_at(darts, j);
        if (!live_before(other, j, s.dart.z, d) ||
            !inhibits(s.dom.radii, distance2(s.dom.lattice, uvec2(other.x, other.y), s.p)))
            continue;
        if (other.w == DART_ACCEPTED) return DART_REJECTED;
        if (first_pass) return DART_UNDECIDED;
        waiting = true;
    }
    return waiting ? DART_UNDECIDED : DART_ACCEPTED;
}

// The cpu backend decides each dart once, not in passes (HostEngine::resolve): when resolve_dart
// leaves d undecided, a dart d waits for is decided first, and d is tried again. This finds one:
// an undecided dart before d within its influence radius (Rf, or 2 Rc with two radii), which
// exists whenever resolve_dart leaves d undecided; GRID_EMPTY if there is none.
VRPD_FN uint undecided_before(Domain global, Grid grid, Darts darts, uint d) {
    DartSite s = dart_site(global, darts, d);
    int reach = int(influence_reach(s.dom.radii));
    uint64_t limit2 = two_radii(s.dom.radii) ? influence2(s.dom.radii) : s.dom.radii.inhibition2;
    VRPD_FOR_EACH_NEARBY_DART(s.dom, grid, s.cell, reach, limit2, j) {
        uvec4 other = dart_at(darts, j);
        if (other.w == DART_UNDECIDED && live_before(other, j, s.dart.z, d) &&
            distance2(s.dom.lattice, s.p, uvec2(other.x, other.y)) < limit2)
            return j;
    }
    return GRID_EMPTY;
}

// The textbook test, for the serial backend, given the darts of this round accepted so far: the
// state of d (rejected if one is closer than Rf; with two radii, also if d is outside T).
VRPD_FN uint serial_decision(Domain global, Grid grid, Darts darts, uint d) {
    DartSite s = dart_site(global, darts, d);
    if (two_radii(global.radii)) return state_given_accepted(s.dom, grid, darts, d, s.p, s.cell);
    int reach = conflict_reach(s.dom.radii);
    VRPD_FOR_EACH_NEARBY_DART(s.dom, grid, s.cell, reach, s.dom.radii.inhibition2, j) {
        uvec4 other = dart_at(darts, j);
        if (j != d && other.w == DART_ACCEPTED &&
            inhibits(s.dom.radii, distance2(s.dom.lattice, uvec2(other.x, other.y), s.p)))
            return DART_REJECTED;
    }
    return DART_ACCEPTED;
}

VRPD_END
#endif
