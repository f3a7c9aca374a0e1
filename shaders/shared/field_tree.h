// The base cells of a sizing-field run as every device reads them (the host builds them:
// field/quadtree.h): a quadtree under each tile, its leaves following the local radius. A node
// word is FIELD_OUTSIDE (a block outside the lattice), or FIELD_LEAF | its leaf's index, or the
// index of its first child in `nodes` (the four children in order: x, then y, low first); with
// FIELD_OCCUPIED where a leaf of its subtree holds a sample and FIELD_FRESH where one is fresh.
#ifndef VRPD_FIELD_TREE_H
#define VRPD_FIELD_TREE_H
#include "bridge.h"
#include "field_table.h"

VRPD_BEGIN

const uint FIELD_LEAF = 0x80000000u;
const uint FIELD_OCCUPIED = 0x40000000u;
const uint FIELD_FRESH = 0x20000000u;
const uint FIELD_INDEX = 0x1FFFFFFFu;
// A leaf word no leaf has (indices stay below FIELD_INDEX), without the flags, so a search for
// flagged subtrees passes over it by its flag test alone.
const uint FIELD_OUTSIDE = FIELD_LEAF | FIELD_INDEX;

struct FieldTreeView {
    uint tile_bits;  // tiles span 2^tile_bits lattice units
    uint tiles_x;    // tiles per row
    uint tiles_y;    // rows of tiles
    FieldWords roots;  // a node word per tile, row by row
    FieldWords nodes;  // the inner nodes' children, four words each
};

// The child of a node of side 2^bits that holds lattice point p (0 to 3).
VRPD_FN uint field_child_of(uvec2 p, uint bits) {
    return ((p.x >> (bits - 1u)) & 1u) | (((p.y >> (bits - 1u)) & 1u) << 1u);
}

// The tile holding lattice point p (inside the lattice): its index in `roots`.
VRPD_FN uint field_tile_of(VRPD_IN(FieldTreeView) t, uvec2 p) {
    return (p.y >> t.tile_bits) * t.tiles_x + (p.x >> t.tile_bits);
}

// The leaf holding lattice point p (inside the lattice), by descent from its tile's root: its
// index (x) and its side's bits (y); its corner is p with those low bits cleared.
VRPD_FN uvec2 field_leaf_at(VRPD_IN(FieldTreeView) t, uvec2 p) {
    uint node = t.roots.value[field_tile_of(t, p)];
    uint bits = t.tile_bits;
    while ((node & FIELD_LEAF) == 0u) {
        node = t.nodes.value[(node & FIELD_INDEX) + field_child_of(p, bits)];
        bits--;
    }
    return uvec2(node & FIELD_INDEX, bits);
}

VRPD_END
#endif
