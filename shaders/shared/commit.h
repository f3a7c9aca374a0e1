// The end of a round: each base cell with darts keeps its accepted dart (at most one, as a
// base cell's diagonal is shorter than Rf) as its sample, or is empty again.
#ifndef VRPD_COMMIT_H
#define VRPD_COMMIT_H
#include "bridge.h"
#include "darts.h"
#include "grid.h"
#include "kernels.h"

VRPD_BEGIN

// The word of a base cell whose darts word is w after a round without a sample in it: empty,
// keeping the mask of its active sub-cells in mask mode.
VRPD_FN uvec2 empty_after_round(uvec2 w) {
    return uvec2(GRID_EMPTY, (w.x & GRID_PACKED) != 0u ? (w.y & GRID_MASK_BITS) : GRID_EMPTY);
}

// The word base cell b keeps after its round (its word is a darts word): the accepted dart, if
// any (at most one: the base cell's diagonal is shorter than r), else empty_after_round.
VRPD_FN uvec2 committed_word(Darts darts, uvec2 w) {
    uvec2 range = grid_darts(w);
    for (uint j = range.x; j < range.y; j++) {
        uvec4 dart = dart_at(darts, j);
        if (dart.w == DART_ACCEPTED) return uvec2(dart.x, dart.y);
    }
    return empty_after_round(w);
}

// Ends the round for the base cell of active cell e (called for the first active cell of each
// base cell): the grid word becomes committed_word's; flags[j] = 1 marks accepted darts for
// emission. (One loop with the flags, not a call of committed_word: each buffer read costs.)
// A dart left DART_TOO_COMPLEX sets counters[COUNTER_TOO_COMPLEX]: the engine fails the run.
VRPD_FN void commit_base_cell(Grid grid, Darts darts, Uints flags, Uints counters, uint b) {
    uvec2 w = grid.word[b];
    uvec2 result = empty_after_round(w);
    uvec2 range = grid_darts(w);
    for (uint j = range.x; j < range.y; j++) {
        uvec4 dart = dart_at(darts, j);
        if (dart.w == DART_TOO_COMPLEX) set_flag(counters, COUNTER_TOO_COMPLEX);
        bool accepted = dart.w == DART_ACCEPTED;
        flags.value[j] = accepted ? 1u : 0u;
        if (accepted) result = uvec2(dart.x, dart.y);
    }
    grid.word[b] = result;
}

// A run from given samples (SampleOptions::initial): each given sample p takes its base cell's
// grid word before the first round. The caller has checked that they are conflict-free,
// so each has a base cell of its own.
VRPD_FN void place_sample(Domain dom, Grid grid, uvec2 p) { grid.word[base_of_point(dom, p)] = p; }

VRPD_END
#endif
