// A sizing field's table as every device reads it (the host builds it: field/table.h): the nodes
// in lattice units, the patches of the table cells where the field bends, and the min/max
// pyramids. r at a lattice point, and bounds of r over a block of lattice points: exact inside one
// table cell, where the bilinear interpolant's extremes lie at the block's corners, and from the
// pyramids beyond it.
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

// A patch's four words in `patches`: its first node in patch_nodes, its depth (a grid of
// (2^depth + 1)^2 nodes over its table cell), and its least and greatest node.
const uint FIELD_PATCH_WORDS = 4u;

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
    FieldWords patches;      // FIELD_PATCH_WORDS a patch, in cell order
    FieldWords patch_nodes;  // the patches' nodes
    // Level k >= 1 from pyramid_start[k]: the least (pyramid_lo) and greatest (pyramid_hi) node
    // over blocks of 2^k x 2^k table cells (their boundary nodes included), cells_x >> k
    // (rounded up) per row. Level 0 is the cells' own nodes (or their patches' bounds).
    FieldWords pyramid_lo;
    FieldWords pyramid_hi;
    FieldWords pyramid_start;
};

// The four nodes of table cell (i, j), in field_interpolate's order.
VRPD_FN uvec4 field_cell_nodes(VRPD_IN(FieldTableView) t, uint i, uint j) {
    uint at = j * (t.cells_x + 1u) + i;
    uint row = t.cells_x + 1u;
    return uvec4(t.nodes.value[at], t.nodes.value[at + 1u], t.nodes.value[at + row], t.nodes.value[at + row + 1u]);
}

// Table cell (i, j)'s patch, or -1.
VRPD_FN int field_patch(VRPD_IN(FieldTableView) t, uint i, uint j) {
    if (t.patch_count == 0u) return -1;
    uint c = j * t.cells_x + i;
    uint64_t word = t.patched.value[c >> 6u];
    uint bit = c & 63u;
    if (((word >> bit) & uint64_t(1)) == uint64_t(0)) return -1;
    uint64_t below = word & ((uint64_t(1) << bit) - uint64_t(1));
    return int(t.patch_rank.value[c >> 6u] + uint(bitCount(uint(below)) + bitCount(uint(below >> 32u))));
}
VRPD_FN uint field_patch_word(VRPD_IN(FieldTableView) t, int q, uint k) {
    return t.patches.value[uint(q) * FIELD_PATCH_WORDS + k];
}

// The side's bits of a patch's cells, and the nodes of the one holding offset f (inside its
// table cell), whose corner is (f >> bits) << bits.
VRPD_FN uint field_patch_bits(VRPD_IN(FieldTableView) t, int q) { return t.cell_bits - field_patch_word(t, q, 1u); }
VRPD_FN uvec4 field_patch_nodes(VRPD_IN(FieldTableView) t, int q, uvec2 f) {
    uint depth = field_patch_word(t, q, 1u);
    uint bits = t.cell_bits - depth;
    uint n = (1u << depth) + 1u;
    uint at = field_patch_word(t, q, 0u) + (f.y >> bits) * n + (f.x >> bits);
    return uvec4(t.patch_nodes.value[at], t.patch_nodes.value[at + 1u], t.patch_nodes.value[at + n],
                 t.patch_nodes.value[at + n + 1u]);
}

// r at lattice point p (inside the lattice).
VRPD_FN uint field_radius(VRPD_IN(FieldTableView) t, uvec2 p) {
    uint mask = (1u << t.cell_bits) - 1u;
    uvec2 f = uvec2(p.x & mask, p.y & mask);
    uint i = p.x >> t.cell_bits;
    uint j = p.y >> t.cell_bits;
    int q = field_patch(t, i, j);
    if (q >= 0) {
        uint bits = field_patch_bits(t, q);
        uint low = (1u << bits) - 1u;
        return field_interpolate(field_patch_nodes(t, q, f), uvec2(f.x & low, f.y & low), bits);
    }
    return field_interpolate(field_cell_nodes(t, i, j), f, t.cell_bits);
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

// The same for the block [fa, fb] (offsets) of table cell (i, j), which holds patch q: exact,
// but for a block across many cells of the patch. The interpolant is bilinear on each piece of
// the block that the patch's cell lines cut: its extremes are at the pieces' corners, where
// those lines meet the block's edges and each other. Past 8 lines each way, the least and
// largest node of the patch cells met bound it.
VRPD_COLD_FN uvec2 field_patch_extremes(VRPD_IN(FieldTableView) t, int q, uint i, uint j, uvec2 fa, uvec2 fb) {
    uint bits = field_patch_bits(t, q);
    uvec2 ka = uvec2(fa.x >> bits, fa.y >> bits);
    uvec2 kb = uvec2(fb.x >> bits, fb.y >> bits);
    if (ka == kb) {
        uvec2 corner = uvec2(ka.x << bits, ka.y << bits);
        return field_corner_extremes(field_patch_nodes(t, q, fa), bits, fa - corner, fb - corner);
    }
    uvec2 lines = kb - ka;
    uint lo = 0xFFFFFFFFu;
    uint hi = 0u;
    if (lines.x <= 8u && lines.y <= 8u) {
        uvec2 cell = uvec2(i << t.cell_bits, j << t.cell_bits);
        for (uint y = 0u; y <= lines.y + 1u; y++)
            for (uint x = 0u; x <= lines.x + 1u; x++) {
                // The block's edges (0 and lines + 1) and the cell lines inside it.
                uvec2 f = uvec2(x == 0u ? fa.x : (x > lines.x ? fb.x : (ka.x + x) << bits),
                                y == 0u ? fa.y : (y > lines.y ? fb.y : (ka.y + y) << bits));
                uint v = field_radius(t, cell + f);
                lo = min(lo, v);
                hi = max(hi, v);
            }
        return uvec2(lo, hi);
    }
    uint n = (1u << field_patch_word(t, q, 1u)) + 1u;
    uint first = field_patch_word(t, q, 0u);
    for (uint y = ka.y; y <= kb.y + 1u; y++)
        for (uint x = ka.x; x <= kb.x + 1u; x++) {
            uint v = t.patch_nodes.value[first + y * n + x];
            lo = min(lo, v);
            hi = max(hi, v);
        }
    return uvec2(lo, hi);
}

// The least (x) and greatest (y) node of table cell (i, j): its patch's, or of its four nodes.
VRPD_FN uvec2 field_cell_range(VRPD_IN(FieldTableView) t, uint i, uint j) {
    int q = field_patch(t, i, j);
    if (q >= 0) return uvec2(field_patch_word(t, q, 2u), field_patch_word(t, q, 3u));
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

VRPD_END
#endif
