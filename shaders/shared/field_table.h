// A sizing field's table as every device reads it (the host builds it: field/table.h): the nodes
// in lattice units, the kinked cells where the source's one kink crosses (each the least or the
// greatest of two interpolants, one a branch), the patches of the table cells where the field
// bends otherwise, and the min/max pyramids. r at a lattice point, and bounds of r over a block
// of lattice points: exact inside one table cell or leaf of its patch, where the bilinear
// interpolant's extremes lie at the block's corners (in a kinked cell, on one side: the least of
// a min of branches, the greatest of a max), and from the splits' and the pyramids' bounds beyond
// it.
#ifndef VRPD_FIELD_TABLE_H
#define VRPD_FIELD_TABLE_H
#include "bridge.h"
#include "field.h"
#include "lattice.h"

#ifndef __cplusplus
layout(buffer_reference, std430, buffer_reference_align = 4) buffer FieldWords { uint value[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer FieldBits { uint64_t value[]; };
#endif

VRPD_BEGIN

#ifdef __cplusplus
struct FieldWords {
    const uint* value;
};
struct FieldBits {
    const uint64_t* value;
};
#endif

// A patch is a quadtree over its table cell: each split halves a square both ways and gives the
// five nodes its children add. Its FIELD_SPLIT_WORDS words in `splits`: its children (the first
// child split's index << 4, and a bit per child quadrant, x first, that is split itself), its five
// nodes (the bottom, left, centre, right and top midpoints) and the least and greatest node over
// its square, its corners included. Patch q's root is split q; the others follow the roots.
const uint FIELD_SPLIT_WORDS = 8u;

// A kinked cell is the least (FIELD_KINK_MIN) or greatest (FIELD_KINK_MAX) of two bilinear
// interpolants, each of one branch of the source's kink at the cell's corners. Its
// FIELD_KINK_WORDS words in `kinks`: the first branch's four corners (field_interpolate's order),
// the second's, and which join. Kinked cells have no patch.
const uint FIELD_KINK_WORDS = 9u;
const uint FIELD_KINK_MIN = 0u;
const uint FIELD_KINK_MAX = 1u;

// The table as the functions below read it. On the host its arrays are pointers into the
// table's vectors; on a device, buffer references (the same members, from FieldTableArgs).
struct FieldTableView {
    uint cell_bits;  // table cells span 2^cell_bits lattice units
    uint cells_x;    // table cells over the tiles
    uint cells_y;
    uint patch_count;
    FieldWords nodes;        // (cells_x + 1) x (cells_y + 1), row by row
    FieldBits patched;       // a bit per table cell, row by row (with patches)
    FieldWords patch_rank;   // per word of `patched`: the patches of the cells before it
    FieldWords splits;       // FIELD_SPLIT_WORDS a split: the patches' roots in cell order, then the others
    // Level k >= 1 from pyramid_start[k]: the least (pyramid_lo) and greatest (pyramid_hi) node
    // over blocks of 2^k x 2^k table cells (their boundary nodes included), cells_x >> k
    // (rounded up) per row. Level 0 is the cells' own nodes (or their patches' roots' bounds).
    FieldWords pyramid_lo;
    FieldWords pyramid_hi;
    FieldWords pyramid_start;
    uint kink_count;
    uint kink_pad;
    FieldBits kinked;      // a bit per table cell, row by row (with kinked cells)
    FieldWords kink_rank;  // per word of `kinked`: the kinked cells before it
    FieldWords kinks;      // FIELD_KINK_WORDS a kinked cell, in cell order
};

// The four nodes of table cell (i, j), in field_interpolate's order.
VRPD_FN uvec4 field_cell_nodes(VRPD_IN(FieldTableView) t, uint i, uint j) {
    uint at = j * (t.cells_x + 1u) + i;
    uint row = t.cells_x + 1u;
    return uvec4(t.nodes.value[at], t.nodes.value[at + 1u], t.nodes.value[at + row], t.nodes.value[at + row + 1u]);
}

// Cell c's rank among the cells whose bit is set in `bits` (a bit per cell; `rank`: per word, the
// set bits before it), or -1 where its bit is clear.
VRPD_FN int field_ranked(FieldBits bits, FieldWords rank, uint c) {
    uint64_t word = bits.value[c >> 6u];
    uint bit = c & 63u;
    if (((word >> bit) & uint64_t(1)) == uint64_t(0)) return -1;
    uint64_t below = word & ((uint64_t(1) << bit) - uint64_t(1));
    return int(rank.value[c >> 6u] + uint(bitCount(uint(below)) + bitCount(uint(below >> 32u))));
}

// Table cell (i, j)'s patch, or -1.
VRPD_FN int field_patch(VRPD_IN(FieldTableView) t, uint i, uint j) {
    if (t.patch_count == 0u) return -1;
    return field_ranked(t.patched, t.patch_rank, j * t.cells_x + i);
}
// Whether the lookups read kinked cells (1) or not (0): the host and the test kernels do wherever
// a table has them; a field kernel only in its build for tables that may (field.glsl), so that
// the others carry no code for them, which llvmpipe would translate on every run.
#ifndef FIELD_KINKS
#define FIELD_KINKS 1
#endif

// Table cell (i, j)'s kinked cell, or -1.
VRPD_FN int field_kink(VRPD_IN(FieldTableView) t, uint i, uint j) {
    if (t.kink_count == 0u) return -1;
    return field_ranked(t.kinked, t.kink_rank, j * t.cells_x + i);
}
// Branch b's corners of kinked cell k, in field_interpolate's order.
VRPD_FN uvec4 field_kink_branch(VRPD_IN(FieldTableView) t, uint k, uint b) {
    uint at = k * FIELD_KINK_WORDS + 4u * b;
    return uvec4(t.kinks.value[at], t.kinks.value[at + 1u], t.kinks.value[at + 2u], t.kinks.value[at + 3u]);
}
// Kinked cell k's join of x (from its first branch) and y (from its second).
VRPD_FN uint field_kink_join(VRPD_IN(FieldTableView) t, uint k, uint x, uint y) {
    return t.kinks.value[k * FIELD_KINK_WORDS + 8u] == FIELD_KINK_MIN ? min(x, y) : max(x, y);
}

VRPD_FN uint field_split_word(VRPD_IN(FieldTableView) t, uint s, uint k) {
    return t.splits.value[s * FIELD_SPLIT_WORDS + k];
}

// The corners of child c (bit 0: the right half; bit 1: the upper) of split s, whose square has
// corners v (field_interpolate's order).
VRPD_FN uvec4 field_child_nodes(VRPD_IN(FieldTableView) t, uint s, uvec4 v, uint c) {
    uint at = s * FIELD_SPLIT_WORDS;
    uint centre = t.splits.value[at + 3u];
    if (c == 0u) return uvec4(v.x, t.splits.value[at + 1u], t.splits.value[at + 2u], centre);
    if (c == 1u) return uvec4(t.splits.value[at + 1u], v.y, centre, t.splits.value[at + 4u]);
    if (c == 2u) return uvec4(t.splits.value[at + 2u], centre, v.z, t.splits.value[at + 5u]);
    return uvec4(centre, t.splits.value[at + 4u], t.splits.value[at + 5u], v.w);
}

// Child c's split of split s, or -1 where the child is a leaf.
VRPD_FN int field_child_split(VRPD_IN(FieldTableView) t, uint s, uint c) {
    uint w = field_split_word(t, s, 0u);
    if (((w >> c) & 1u) == 0u) return -1;
    return int((w >> 4u) + uint(bitCount(w & ((1u << c) - 1u))));
}

// From split s, over a square of side 2^bits with corners v, down while the block [fa, fb]
// (offsets inside the square) lies in one child: v, fa, fb and bits become that child's. Returns
// the split whose children the block spans, or -1 where the block lies in one leaf.
VRPD_FN int field_descend_block(VRPD_IN(FieldTableView) t, int s, VRPD_INOUT(uvec4) v, VRPD_INOUT(uvec2) fa,
                                VRPD_INOUT(uvec2) fb, VRPD_INOUT(uint) bits) {
    while (s >= 0) {
        uint child_bits = bits - 1u;
        uvec2 ca = uvec2(fa.x >> child_bits, fa.y >> child_bits);
        if (ca != uvec2(fb.x >> child_bits, fb.y >> child_bits)) return s;
        uint c = ca.x | (ca.y << 1u);
        v = field_child_nodes(t, uint(s), v, c);
        uvec2 corner = uvec2(ca.x << child_bits, ca.y << child_bits);
        fa -= corner;
        fb -= corner;
        bits = child_bits;
        s = field_child_split(t, uint(s), c);
    }
    return -1;
}

// The same down to the leaf that holds offset f: the block's loop for one point, without its
// test (r at a point is the hot path).
VRPD_FN void field_descend(VRPD_IN(FieldTableView) t, int s, VRPD_INOUT(uvec4) v, VRPD_INOUT(uvec2) f,
                           VRPD_INOUT(uint) bits) {
    while (s >= 0) {
        bits--;
        uint c = (f.x >> bits) | ((f.y >> bits) << 1u);
        v = field_child_nodes(t, uint(s), v, c);
        f = uvec2(f.x & ((1u << bits) - 1u), f.y & ((1u << bits) - 1u));
        s = field_child_split(t, uint(s), c);
    }
}

// r at lattice point p (inside the lattice).
VRPD_FN uint field_radius(VRPD_IN(FieldTableView) t, uvec2 p) {
    uint mask = (1u << t.cell_bits) - 1u;
    uvec2 f = uvec2(p.x & mask, p.y & mask);
    uint i = p.x >> t.cell_bits;
    uint j = p.y >> t.cell_bits;
#if FIELD_KINKS
    int k = field_kink(t, i, j);
    if (k >= 0)
        return field_kink_join(t, uint(k), field_interpolate(field_kink_branch(t, uint(k), 0u), f, t.cell_bits),
                               field_interpolate(field_kink_branch(t, uint(k), 1u), f, t.cell_bits));
#endif
    uvec4 v = field_cell_nodes(t, i, j);
    uint bits = t.cell_bits;
    int q = field_patch(t, i, j);
    if (q >= 0) field_descend(t, q, v, f, bits);
    return field_interpolate(v, f, bits);
}

// The least (x) and largest (y) of the interpolant of nodes v over a cell of side 2^bits at the
// four corners of the block [fa, fb] (offsets in the cell), where its extremes lie: it is linear
// along each axis. Each row's interpolant along x is taken once per x.
VRPD_FN uvec2 field_corner_extremes(uvec4 v, uint bits, uvec2 fa, uvec2 fb) {
    uint64_t a0 = field_row(v.x, v.y, fa.x, bits);
    uint64_t a1 = field_row(v.z, v.w, fa.x, bits);
    uint64_t b0 = field_row(v.x, v.y, fb.x, bits);
    uint64_t b1 = field_row(v.z, v.w, fb.x, bits);
    uint r0 = field_blend(a0, a1, fa.y, bits);
    uint r1 = field_blend(a0, a1, fb.y, bits);
    uint r2 = field_blend(b0, b1, fa.y, bits);
    uint r3 = field_blend(b0, b1, fb.y, bits);
    return uvec2(min(min(r0, r1), min(r2, r3)), max(max(r0, r1), max(r2, r3)));
}

// The same for the block [fa, fb] (offsets) of kinked cell k: its join's own extreme exactly (the
// least of a min, the greatest of a max), the other bounded by the branches' (the least of a max
// is at least each branch's least; the greatest of a min at most each branch's greatest).
VRPD_FN uvec2 field_kink_extremes(VRPD_IN(FieldTableView) t, uint k, uint bits, uvec2 fa, uvec2 fb) {
    uvec2 a = field_corner_extremes(field_kink_branch(t, k, 0u), bits, fa, fb);
    uvec2 b = field_corner_extremes(field_kink_branch(t, k, 1u), bits, fa, fb);
    if (t.kinks.value[k * FIELD_KINK_WORDS + 8u] == FIELD_KINK_MIN) return uvec2(min(a.x, b.x), min(a.y, b.y));
    return uvec2(max(a.x, b.x), max(a.y, b.y));
}

// The same for the block [fa, fb] (offsets) of a square of side 2^bits with corners v, split by
// s (or one leaf, s = -1). Inside one leaf, exact. Else the block meets two or four quadrants of
// the least split that holds it: in a quadrant that is a leaf, exact over its part of the block;
// in one that is split, that split's least and greatest node.
VRPD_FN uvec2 field_split_extremes(VRPD_IN(FieldTableView) t, int s0, uvec4 v, uvec2 fa, uvec2 fb, uint bits) {
    int split = field_descend_block(t, s0, v, fa, fb, bits);
    if (split < 0) return field_corner_extremes(v, bits, fa, fb);
    uint s = uint(split);
    uint child_bits = bits - 1u;
    uint m = 1u << child_bits;
    uint lo = 0xFFFFFFFFu;
    uint hi = 0u;
    for (uint c = 0u; c < 4u; c++) {
        uint cx = c & 1u;
        uint cy = c >> 1u;
        if ((cx == 0u ? fa.x >= m : fb.x < m) || (cy == 0u ? fa.y >= m : fb.y < m)) continue;
        // The quadrant's part of the block, in its own offsets.
        uvec2 a = uvec2(cx == 0u ? fa.x : max(fa.x, m) - m, cy == 0u ? fa.y : max(fa.y, m) - m);
        uvec2 b = uvec2(cx == 0u ? min(fb.x, m - 1u) : fb.x - m, cy == 0u ? min(fb.y, m - 1u) : fb.y - m);
        int k = field_child_split(t, s, c);
        uvec2 e = k < 0 ? field_corner_extremes(field_child_nodes(t, s, v, c), child_bits, a, b)
                        : uvec2(field_split_word(t, uint(k), 6u), field_split_word(t, uint(k), 7u));
        lo = min(lo, e.x);
        hi = max(hi, e.y);
    }
    return uvec2(lo, hi);
}

// The same for the block [fa, fb] (offsets) of table cell (i, j), which holds patch q.
VRPD_OUTLINED_FN uvec2 field_patch_extremes(VRPD_IN(FieldTableView) t, int q, uint i, uint j, uvec2 fa, uvec2 fb) {
    return field_split_extremes(t, q, field_cell_nodes(t, i, j), fa, fb, t.cell_bits);
}

// The least (x) and greatest (y) node of table cell (i, j): its patch's, or of its four nodes; of
// a kinked cell, field_kink_extremes over the cell and its far edges.
VRPD_FN uvec2 field_cell_range(VRPD_IN(FieldTableView) t, uint i, uint j) {
#if FIELD_KINKS
    int k = field_kink(t, i, j);
    if (k >= 0) return field_kink_extremes(t, uint(k), t.cell_bits, uvec2(0u), uvec2(1u << t.cell_bits));
#endif
    int q = field_patch(t, i, j);
    if (q >= 0) return uvec2(field_split_word(t, uint(q), 6u), field_split_word(t, uint(q), 7u));
    uvec4 n = field_cell_nodes(t, i, j);
    return uvec2(min(min(n.x, n.y), min(n.z, n.w)), max(max(n.x, n.y), max(n.z, n.w)));
}

// Does [a, b] lie in one table cell?
VRPD_FN bool field_in_one_cell(VRPD_IN(FieldTableView) t, uvec2 a, uvec2 b) {
    return (a.x >> t.cell_bits) == (b.x >> t.cell_bits) && (a.y >> t.cell_bits) == (b.y >> t.cell_bits);
}

// The least (x) and largest (y) r over [a, b], which lies in one table cell.
VRPD_FN uvec2 field_cell_extremes(VRPD_IN(FieldTableView) t, uvec2 a, uvec2 b) {
    uint mask = (1u << t.cell_bits) - 1u;
    uvec2 fa = uvec2(a.x & mask, a.y & mask);
    uvec2 fb = uvec2(b.x & mask, b.y & mask);
    uint i = a.x >> t.cell_bits;
    uint j = a.y >> t.cell_bits;
#if FIELD_KINKS
    int k = field_kink(t, i, j);
    if (k >= 0) return field_kink_extremes(t, uint(k), t.cell_bits, fa, fb);
#endif
    int q = field_patch(t, i, j);
    if (q >= 0) return field_patch_extremes(t, q, i, j, fa, fb);
    return field_corner_extremes(field_cell_nodes(t, i, j), t.cell_bits, fa, fb);
}

// A bound of r over [a, b] from the table cells it meets, in at most 2 x 2 blocks of the
// pyramid's level: the least node (upper == false) or the greatest; at level 0, the cells' ranges.
VRPD_FN uint field_bound_over_blocks(VRPD_IN(FieldTableView) t, uvec2 a, uvec2 b, bool upper) {
    uint i0 = a.x >> t.cell_bits;
    uint i1 = b.x >> t.cell_bits;
    uint j0 = a.y >> t.cell_bits;
    uint j1 = b.y >> t.cell_bits;
    uint k = 0u;
    while ((i1 >> k) - (i0 >> k) > 1u || (j1 >> k) - (j0 >> k) > 1u) k++;
    uint v = upper ? 0u : 0xFFFFFFFFu;
    if (k > 0u) {
        uint w = (t.cells_x + (1u << k) - 1u) >> k;
        uint start = t.pyramid_start.value[k];
        for (uint j = j0 >> k; j <= j1 >> k; j++)
            for (uint i = i0 >> k; i <= i1 >> k; i++) {
                uint at = start + j * w + i;
                v = upper ? max(v, t.pyramid_hi.value[at]) : min(v, t.pyramid_lo.value[at]);
            }
        return v;
    }
    for (uint j = j0; j <= j1; j++)
        for (uint i = i0; i <= i1; i++) {
            uvec2 range = field_cell_range(t, i, j);
            v = upper ? max(v, range.y) : min(v, range.x);
        }
    return v;
}

// The least and greatest r over the lattice points of [a, b] (inclusive, inside the lattice):
// exact inside one table cell, else a bound from the pyramid.
VRPD_FN uint field_min_over(VRPD_IN(FieldTableView) t, uvec2 a, uvec2 b) {
    if (field_in_one_cell(t, a, b)) return field_cell_extremes(t, a, b).x;
    return field_bound_over_blocks(t, a, b, false);
}
VRPD_FN uint field_max_over(VRPD_IN(FieldTableView) t, uvec2 a, uvec2 b) {
    if (field_in_one_cell(t, a, b)) return field_cell_extremes(t, a, b).y;
    return field_bound_over_blocks(t, a, b, true);
}
// Both, with one read of the table inside one table cell.
VRPD_FN uvec2 field_extremes_over(VRPD_IN(FieldTableView) t, uvec2 a, uvec2 b) {
    if (field_in_one_cell(t, a, b)) return field_cell_extremes(t, a, b);
    return uvec2(field_bound_over_blocks(t, a, b, false), field_bound_over_blocks(t, a, b, true));
}

// The least r over each child k (bit k of `open`; x, then y, low first) of the block [a, b] split
// at m: along each axis the child spans [a, e] or [m, b], e = min(m - 1, b). Each is
// field_min_over's. Inside one table cell the descent of its patch to the least split that holds
// the whole block is taken once (a child's own descent passes through it), and where the block
// lies in one leaf, the two rows' interpolants along x once for each x.
VRPD_FN uvec4 field_children_min(VRPD_IN(FieldTableView) t, uvec2 a, uvec2 e, uvec2 m, uvec2 b, uint open) {
    uvec4 least = uvec4(0u);
    uint i = a.x >> t.cell_bits;
    uint j = a.y >> t.cell_bits;
    bool one = field_in_one_cell(t, a, b);
#if FIELD_KINKS
    one = one && field_kink(t, i, j) < 0;
#endif
    if (!one) {
        for (uint k = 0u; k < 4u; k++)
            if (((open >> k) & 1u) != 0u)
                least[k] = field_min_over(t, uvec2((k & 1u) != 0u ? m.x : a.x, (k >> 1u) != 0u ? m.y : a.y),
                                          uvec2((k & 1u) != 0u ? b.x : e.x, (k >> 1u) != 0u ? b.y : e.y));
        return least;
    }
    uint mask = (1u << t.cell_bits) - 1u;
    uvec4 v = field_cell_nodes(t, i, j);
    uvec2 fa = uvec2(a.x & mask, a.y & mask);
    uvec2 fb = uvec2(b.x & mask, b.y & mask);
    uint bits = t.cell_bits;
    int s = field_descend_block(t, field_patch(t, i, j), v, fa, fb, bits);
    // The children's corners as offsets in the square the descent ended in (m clipped to b where
    // no child starts there).
    uvec2 square = uvec2(a.x & mask, a.y & mask) - fa;
    uvec2 fe = uvec2(e.x & mask, e.y & mask) - square;
    uvec2 fm = uvec2(min(m.x, b.x) & mask, min(m.y, b.y) & mask) - square;
    if (s >= 0) {
        for (uint k = 0u; k < 4u; k++)
            if (((open >> k) & 1u) != 0u)
                least[k] =
                    field_split_extremes(t, s, v, uvec2((k & 1u) != 0u ? fm.x : fa.x, (k >> 1u) != 0u ? fm.y : fa.y),
                                         uvec2((k & 1u) != 0u ? fb.x : fe.x, (k >> 1u) != 0u ? fb.y : fe.y), bits)
                        .x;
        return least;
    }
    uint xs[4] = {fa.x, fe.x, fm.x, fb.x};
    uint ys[4] = {fa.y, fe.y, fm.y, fb.y};
    uint64_t row0[4];
    uint64_t row1[4];
    for (uint c = 0u; c < 4u; c++) {
        row0[c] = field_row(v.x, v.y, xs[c], bits);
        row1[c] = field_row(v.z, v.w, xs[c], bits);
    }
    for (uint k = 0u; k < 4u; k++) {
        uint x = 2u * (k & 1u);
        uint y = 2u * (k >> 1u);
        least[k] =
            min(min(field_blend(row0[x], row1[x], ys[y], bits), field_blend(row0[x + 1u], row1[x + 1u], ys[y], bits)),
                min(field_blend(row0[x], row1[x], ys[y + 1u], bits),
                    field_blend(row0[x + 1u], row1[x + 1u], ys[y + 1u], bits)));
    }
    return least;
}

VRPD_END
#endif
