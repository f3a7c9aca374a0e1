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

// What dart j (`other`), met by dart d's scan, says of d: DART_REJECTED if it is accepted and
// inhibits d, DART_UNDECIDED if it is undecided, arrives before d and inhibits it, else
// DART_ACCEPTED (nothing against d; d itself says nothing).
VRPD_FN uint nearby_verdict(DartSite s, uint d, uvec4 other, uint j) {
    if (!live_before(other, j, s.dart.z, d) ||
        !inhibits(s.dom.radii, distance2(s.dom.lattice, uvec2(other.x, other.y), s.p)))
        return DART_ACCEPTED;
    return other.w == DART_ACCEPTED ? DART_REJECTED : DART_UNDECIDED;
}

// Folds a nearby dart's verdict into d's step: true if it decides the step (rejected, or on a
// first pass undecided), which then returns the verdict; an undecided one leaves d `waiting`.
VRPD_FN bool settles(uint verdict, bool first_pass, VRPD_INOUT(bool) waiting) {
    waiting = waiting || verdict == DART_UNDECIDED;
    return verdict == DART_REJECTED || (verdict == DART_UNDECIDED && first_pass);
}

// The darts of base cells [b0, b1] of a grid row: this round's darts are numbered in base cell
// order, so they are one range, from the first darts word's first dart to the last one's end;
// an empty range if no base cell there holds darts. (Mask mode numbers every base cell without
// a sample, so that the first and the last base cell of a row mostly hold one.)
VRPD_FN uvec2 row_darts(Grid grid, uint b0, uint b1) {
    uvec2 range = uvec2(0u, 0u);
    for (uint b = b0; b <= b1; b++) {
        uvec2 w = grid.word[b];
        if (grid_is_darts(w)) {
            range.x = grid_darts(w).x;
            break;
        }
    }
    for (uint b = b1 + 1u; b > b0; b--) {
        uvec2 w = grid.word[b - 1u];
        if (grid_is_darts(w)) {
            range.y = grid_darts(w).y;
            break;
        }
    }
    return range;
}

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
// A dart whose scan meets no side of the grid reads the darts of each of its five rows as one
// range (row_darts), not 21 base cells' words, each with a loop of its own.
VRPD_FN uint resolve_dart(Domain global, Grid grid, Darts darts, uint d, bool first_pass) {
#ifndef VRPD_ONE_RADIUS  // glslang does not fold two_radii(): only the guard keeps T's code out of SPIR-V
    if (two_radii(global.radii)) return resolve_dart_two_radii(global, grid, darts, d, first_pass);
#endif
    DartSite s = dart_site(global, darts, d);
    bool waiting = false;
    int reach = conflict_reach(s.dom.radii);
    if (inside_by(global, s.cell, reach)) {
        uint centre = base_index(global, s.cell);
        for (int dy = -reach; dy <= reach; dy++) {
            uint row = uint(int(centre) + dy * int(global.cells_x)), width = uint(conflict_row(s.dom.radii, dy));
            uvec2 range = row_darts(grid, row - width, row + width);
            for (uint j = range.x; j < range.y; j++) {
                uint verdict = nearby_verdict(s, d, dart_at(darts, j), j);
                if (settles(verdict, first_pass, waiting)) return verdict;
            }
        }
        return waiting ? DART_UNDECIDED : DART_ACCEPTED;
    }
    VRPD_FOR_EACH_NEARBY_DART(s.dom, grid, s.cell, reach, s.dom.radii.inhibition2, j) {
        uint verdict = nearby_verdict(s, d, dart_at(darts, j), j);
        if (settles(verdict, first_pass, waiting)) return verdict;
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
