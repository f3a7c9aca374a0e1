// Grid words: one uvec2 per base cell, holding its sample's lattice position, this round's darts,
// or (mask mode, mask_mode.h) the mask of its active sub-cells. Lattice coordinates are < 2^31,
// so bit 31 of .x tells a sample from a tag.
#ifndef VRPD_GRID_H
#define VRPD_GRID_H
#include "bridge.h"

VRPD_BEGIN

const uint GRID_TAG = 0x80000000u;
const uint GRID_EMPTY = 0xFFFFFFFFu;  // .x of an empty cell
// A cell whose .x is GRID_TAG | first holds this round's darts [first, .y) (first < 2^30). In
// mask mode .x is GRID_TAG | GRID_PACKED | first and .y packs the dart count (high 16 bits) with
// the base cell's mask of active sub-cells (low 16 bits); an empty cell's .y is that mask
// between rounds.
const uint GRID_PACKED = 0x40000000u;
const uint GRID_MASK_BITS = 0xFFFFu;

VRPD_FN bool grid_is_sample(uvec2 word) { return (word.x & GRID_TAG) == 0u; }
VRPD_FN bool grid_is_darts(uvec2 word) { return word.x != GRID_EMPTY && (word.x & GRID_TAG) != 0u; }
// A mask-mode word's dart count (the high 16 bits of .y).
VRPD_FN uint packed_dart_count(uvec2 word) { return word.y >> 16u; }
// The darts [first, end) of a darts word.
VRPD_FN uvec2 grid_darts(uvec2 word) {
    uint first = word.x & ~(GRID_TAG | GRID_PACKED);
    return uvec2(first, (word.x & GRID_PACKED) != 0u ? first + packed_dart_count(word) : word.y);
}
// grid_darts for a word outside mask mode, which two radii never use: [first, .y).
VRPD_FN uvec2 listed_darts(uvec2 word) { return uvec2(word.x & ~GRID_TAG, word.y); }

VRPD_END
#endif
