// Arrival-order resolution with two radii (paper section 3, Eq. 9): a dart is kept iff it is
// free (no accepted dart or sample closer than Rf) and in T given the samples and the darts
// accepted before it, decided exactly by t_membership.h over the samples within 2 Rc.
#ifndef VRPD_RESOLVE_TWO_RADII_H
#define VRPD_RESOLVE_TWO_RADII_H
#include "bridge.h"
#include "darts.h"
#include "kernels.h"
#include "neighbourhood.h"
#include "t_membership.h"

VRPD_BEGIN

// Two radii: does the closed Rc-disk around p reach a point of the domain outside the open Rc-disks
// around disk_at[0, n) (offsets from p)? A free boundary's box is passed as offsets from p.
// T_INSIDE, T_OUTSIDE or T_UNKNOWN (see t_membership.h).
VRPD_FN uint reaches_uncovered_at(Domain dom, uvec2 p, uint n) {
    ivec2 lo = ivec2(-FAR_SIDE, -FAR_SIDE);
    ivec2 hi = ivec2(FAR_SIDE, FAR_SIDE);
    if (dom.lattice.periodic == 0u) {
        lo = max(lo, -ivec2(p));
        hi = min(hi, ivec2(dom.lattice.extent_x - 1u - p.x, dom.lattice.extent_y - 1u - p.y));
    }
    return reaches_uncovered(n, dom.radii.coverage2, lo, hi, true);
}

// Early acceptance is tried with at most this many undecided darts before d within 2 Rc: its T
// test, with them counted as accepted, grows as n^3, while each dart left to wait is scanned
// again (docs/performance.md measures the bound).
const uint EARLY_UNDECIDED = 8u;
VRPD_PRIVATE ivec2 undecided_at[EARLY_UNDECIDED];

// Two radii, in one scan of the 2 Rc neighbourhood of dart d: fills disk_at with the samples of
// earlier rounds and this round's accepted darts before d (offsets from d). Returns their count,
// MAX_DISKS + 1 if they do not fit (the scan then stops). `conflict`: an accepted dart is closer
// than Rf. `undecided` counts the undecided darts before d there, the first EARLY_UNDECIDED of
// which go to undecided_at; `undecided_conflict`: one of those is closer than Rf.
VRPD_FN uint gather_accepted(Domain dom, Grid grid, Darts darts, uint d, VRPD_OUT(bool) conflict,
                             VRPD_OUT(uint) undecided, VRPD_OUT(bool) undecided_conflict) {
    uvec4 me = dart_at(darts, d);
    uvec2 p = uvec2(me.x, me.y);
    uvec2 cell = base_cell_of(dom, p);
    int reach = int(influence_reach(dom.radii));
    uint64_t limit2 = influence2(dom.radii);
    uint n = 0u;
    conflict = false;
    undecided = 0u;
    undecided_conflict = false;
    VRPD_FOR_EACH_NEIGHBOUR(dom, cell, reach, limit2, dx, dy, nb) {
        uvec2 w = grid.word[nb];
        if (grid_is_sample(w) && distance2(dom.lattice, p, w) < limit2) {
            if (n == MAX_DISKS) return MAX_DISKS + 1u;
            disk_at[n++] = offset_to(dom.lattice, p, w);
        }
        if (!grid_is_darts(w)) continue;
        uvec2 range = listed_darts(w);
        for (uint j = range.x; j < range.y; j++) {
            uvec4 other = dart_at(darts, j);
            if (!live_before(other, j, me.z, d)) continue;
            uint64_t gap2 = distance2(dom.lattice, p, uvec2(other.x, other.y));
            if (gap2 >= limit2) continue;
            if (other.w == DART_UNDECIDED) {
                if (undecided < EARLY_UNDECIDED)
                    undecided_at[undecided] = offset_to(dom.lattice, p, uvec2(other.x, other.y));
                undecided_conflict = undecided_conflict || inhibits(dom.radii, gap2);
                undecided++;
                continue;
            }
            conflict = conflict || inhibits(dom.radii, gap2);
            if (n == MAX_DISKS) return MAX_DISKS + 1u;
            disk_at[n++] = offset_to(dom.lattice, p, uvec2(other.x, other.y));
        }
    }
    return n;
}

// Two radii: what lies within Rc of dart d (at p, in base cell `cell`), as bits: NEAR_* below.
// Samples of earlier rounds count as accepted; darts count only if they arrive before d.
const uint NEAR_ACCEPTED_RF = 1u;   // a sample or accepted dart closer than Rf
const uint NEAR_ACCEPTED_RC = 2u;   // ... closer than Rc
const uint NEAR_UNDECIDED_RF = 4u;  // an undecided dart closer than Rf
const uint NEAR_UNDECIDED_RC = 8u;  // ... closer than Rc
VRPD_FN uint near_bits(Radii radii, uint64_t d2) {
    return (covers(radii, d2) ? NEAR_ACCEPTED_RC : 0u) | (inhibits(radii, d2) ? NEAR_ACCEPTED_RF : 0u);
}
VRPD_FN uint census(Domain dom, Grid grid, Darts darts, uint d, uvec2 p, uvec2 cell) {
    uint key = dart_at(darts, d).z;
    uint found = 0u;
    int reach = cover_reach(dom.radii);
    VRPD_FOR_EACH_NEIGHBOUR(dom, cell, reach, dom.radii.coverage2, dx, dy, nb) {
        uvec2 w = grid.word[nb];
        if (grid_is_sample(w)) {
            found |= near_bits(dom.radii, distance2(dom.lattice, w, p));
            continue;
        }
        if (!grid_is_darts(w)) continue;
        uvec2 range = listed_darts(w);
        for (uint j = range.x; j < range.y; j++) {
            uvec4 other = dart_at(darts, j);
            if (!live_before(other, j, key, d)) continue;
            uint shift = other.w == DART_ACCEPTED ? 0u : 2u;
            found |= near_bits(dom.radii, distance2(dom.lattice, uvec2(other.x, other.y), p)) << shift;
        }
    }
    return found;
}

// A dart's state from its T test (the run fails on DART_TOO_COMPLEX).
VRPD_FN uint state_of_t(uint t) {
    return t == T_INSIDE ? DART_ACCEPTED : (t == T_OUTSIDE ? DART_REJECTED : DART_TOO_COMPLEX);
}

// Two radii, the textbook decision for the serial backend: the state of dart d (at p, in base
// cell `cell`) given the samples and this round's darts accepted before it: rejected (one is
// closer than Rf, or d is outside T), accepted, or DART_TOO_COMPLEX (t_membership.h's bounds).
// Cheap tests first: a conflict within Rf, and a dart that nothing covers is in U, so in T.
VRPD_FN uint state_given_accepted(Domain dom, Grid grid, Darts darts, uint d, uvec2 p, uvec2 cell) {
    uint near = census(dom, grid, darts, d, p, cell);
    if ((near & NEAR_ACCEPTED_RF) != 0u) return DART_REJECTED;
    if ((near & NEAR_ACCEPTED_RC) == 0u) return DART_ACCEPTED;
    bool conflict;
    uint undecided;
    bool undecided_conflict;
    uint n = gather_accepted(dom, grid, darts, d, conflict, undecided, undecided_conflict);
    if (conflict) return DART_REJECTED;
    return state_of_t(n <= MAX_DISKS ? reaches_uncovered_at(dom, p, n) : T_UNKNOWN);
}

// One step of the exact parallel resolution (resolve_dart) with two radii. A dart is accepted iff it is free and in T
// given the samples and the darts accepted before it. Both only shrink as earlier darts are accepted, so: rejected as
// soon as the accepted ones exclude it; accepted once it is free of, and in T despite, all the undecided too.
// `first_pass`: resolve_dart's. Its two parts: census_state, whose reads of the Rc neighbourhood settle most
// darts, then tested_state for the rest (the Vulkan kernel runs a workgroup's rest together).

// Not a state: census_state leaves the dart to tested_state.
const uint DART_TESTED = 4u;

VRPD_FN uint census_state(DartSite s, Grid grid, Darts darts, uint d, bool first_pass) {
    // Cheap cases first. A conflict rejects d. If nothing covers d, even counting the undecided
    // darts before it, d is in U, so in T, whatever they become: accepted. An undecided dart closer
    // than Rf blocks d until it is decided (d may yet be rejected by T; that can wait).
    uint near = census(s.dom, grid, darts, d, s.p, s.cell);
    if ((near & NEAR_ACCEPTED_RF) != 0u) return DART_REJECTED;
    if ((near & (NEAR_ACCEPTED_RC | NEAR_UNDECIDED_RC)) == 0u) return DART_ACCEPTED;
    if ((near & NEAR_UNDECIDED_RF) != 0u) return DART_UNDECIDED;
    // A round's first pass (few darts of it accepted yet): a dart with an undecided dart before it
    // within Rc waits, its gather and T tests left to a pass that knows the accepted darts. The
    // earliest undecided dart has none, so each pass still decides one.
    if (first_pass && (near & NEAR_UNDECIDED_RC) != 0u) return DART_UNDECIDED;
    return DART_TESTED;
}

// The state of a dart census_state leaves: from the samples and darts within 2 Rc, by T tests.
VRPD_FN uint tested_state(DartSite s, Grid grid, Darts darts, uint d) {
    Domain dom = s.dom;
    uvec2 p = s.p;
    bool conflict;
    uint undecided;
    bool undecided_conflict;
    uint n = gather_accepted(dom, grid, darts, d, conflict, undecided, undecided_conflict);
    if (conflict) return DART_REJECTED;
    // Many undecided darts around: d waits (the earliest undecided dart of any neighbourhood always
    // decides, so the passes end), and its T test with them, growing as n^3, is not tried.
    if (undecided > EARLY_UNDECIDED) return DART_UNDECIDED;
    uint t = n <= MAX_DISKS ? reaches_uncovered_at(dom, p, n) : T_UNKNOWN;
    if (t != T_INSIDE) return state_of_t(t);
    if (undecided == 0u) return DART_ACCEPTED;
    if (undecided_conflict || n + undecided > MAX_DISKS) return DART_UNDECIDED;
    for (uint i = 0u; i < undecided; i++) disk_at[n + i] = undecided_at[i];
    return reaches_uncovered_at(dom, p, n + undecided) == T_INSIDE ? DART_ACCEPTED : DART_UNDECIDED;
}

VRPD_FN uint resolve_dart_two_radii(Domain global, Grid grid, Darts darts, uint d, bool first_pass) {
    DartSite s = dart_site(global, darts, d);
    uint state = census_state(s, grid, darts, d, first_pass);
    return state == DART_TESTED ? tested_state(s, grid, darts, d) : state;
}

VRPD_END
#endif
