// The device's leaf search over a sizing field's leaf tree (shared/field_tree.h): the leaves that
// meet the square `reach` around a block [a, b] (on a torus, around any image), as an iterator a
// kernel steps through with field_search_next. It meets the leaves the host's search
// (FieldQuadtree::near, near_samples, near_fresh) meets, tile by tile in the same ranges; inside a
// tile it holds only the current node and finds a parent's word again by descent from the root,
// where the host keeps a stack of siblings to visit (field/quadtree.h) that a device cannot hold.
// A gate (FieldGate) makes it skip the subtrees that cannot matter to the caller.
//
// A search counts its steps (each pass of its loops, and its caller's pass over each leaf) and
// stops at a budget, giving FIELD_SEARCH_OVERFLOW: lavapipe ends every loop of an invocation
// after 65 535 passes in all (llvmpipe's LP_MAX_TGSI_LOOP_ITERATIONS, shared by the loops of a
// SIMD vector of invocations), so a longer search would end early there without a sign. The
// budget makes the stop deterministic and seen, the same on every device and on the host.
#ifndef VRPD_FIELD_SEARCH_H
#define VRPD_FIELD_SEARCH_H
#include "bridge.h"
#include "field_tree.h"
#include "lattice.h"

// A kernel whose searches pass through a gate (FieldGate) defines FIELD_SEARCH_GATED before its
// includes; the others compile without the gate's code, which a device's compiler would otherwise
// take again in every kernel at every run. The host has it always.
#if defined(__cplusplus) && !defined(FIELD_SEARCH_GATED)
#define FIELD_SEARCH_GATED
#endif

VRPD_BEGIN

// What field_search_next gives when no leaf is left, and when the budget ran out first.
const uint FIELD_SEARCH_DONE = 0xFFFFFFFFu;
const uint FIELD_SEARCH_OVERFLOW = 0xFFFFFFFEu;
// The search's state of `depth`: no node (between tiles), or a node not yet visited.
const uint FIELD_SEARCH_BETWEEN = 0xFFFFFFFFu;

#ifdef FIELD_SEARCH_GATED
// What a search may skip besides the subtrees without its flag, so that one whose square holds
// thousands of leaves (a reach set by a large r, among leaves set by small ones) enters only the
// subtrees that can matter:
// - `keyed`: the subtrees none of whose darts arrives before `key` (keys: per inner node, at its
//   children's index / 4, the least key of the round's darts below it; a key equal to `key` is
//   entered, its order settled by index).
// - `reached`: the blocks no point of which is within f of `point`, whose r is `r`: f is at most
//   the rule's f of r and the block's greatest r (from the table's max pyramid), the block's
//   points the earlier (later == 0) or the later ones (later == 1).
// Each test is a step.
struct FieldGate {
    uint keyed;
    uint key;
    FieldWords keys;
    uint reached;
    uint rule;
    uint r;
    uint later;
    uvec2 point;
    uint r_hi;       // the field's greatest r
    uint levels;     // the table's pyramid levels
    uint cell_bits;  // its cells' side
    uint cells_x;
    FieldWords pyramid_hi;
    FieldWords pyramid_start;
    Lattice lattice;
};
#endif

struct FieldSearch {
    // The query's square per axis in unwrapped lattice coordinates, and whether it spans the
    // torus (then every tile once, each whole).
    int64_t lo_x;
    int64_t hi_x;
    int64_t lo_y;
    int64_t hi_y;
    uint all_x;
    uint all_y;
    // The flag a subtree must carry to be entered (FIELD_OCCUPIED, FIELD_FRESH), or 0 for all.
    uint need;
    // The tiles the square meets (unwrapped: on a torus one period off either side) and the
    // current one.
    int tile_x0;
    int tile_x1;
    int tile_y1;
    int tile_x;
    int tile_y;
    // The square clipped to the current tile, in offsets from its corner.
    uint clip_lo_x;
    uint clip_hi_x;
    uint clip_lo_y;
    uint clip_hi_y;
    // The current node: its depth below the tile's root (FIELD_SEARCH_BETWEEN: none), its corner
    // in offsets from the tile's, whether it is visited (a leaf given, or an inner node's children
    // entered), its word, and the tile's root word (a parent's word is found again from it).
    uint depth;
    uint x;
    uint y;
    // The current tile's corner in lattice coordinates (the image inside the lattice).
    uint origin_x;
    uint origin_y;
    uint visited;
    uint word;
    uint root;
    // The steps taken, and the most allowed.
    uint steps;
    uint budget;
#ifdef FIELD_SEARCH_GATED
    FieldGate gate;
#endif
};
#ifdef FIELD_SEARCH_GATED

// The gate's tests (FieldGate), both off.
VRPD_FN void field_search_ungated(VRPD_INOUT(FieldSearch) s) {
    s.gate.keyed = 0u;
    s.gate.reached = 0u;
}

// Lets search s enter only the blocks with a point within f of point p of radius r, the blocks'
// points the earlier (later == 0) or the later (later == 1).
VRPD_FN void field_search_gate_reach(VRPD_INOUT(FieldSearch) s, VRPD_IN(FieldTableView) table, Lattice l, uint rule,
                                     uint r_hi, uvec2 p, uint r, uint later) {
    s.gate.reached = 1u;
    s.gate.rule = rule;
    s.gate.r = r;
    s.gate.later = later;
    s.gate.point = p;
    s.gate.r_hi = r_hi;
    uint cells = max(table.cells_x, table.cells_y);
    s.gate.levels = cells > 1u ? uint(findMSB(cells - 1u)) + 1u : 0u;
    s.gate.cell_bits = table.cell_bits;
    s.gate.cells_x = table.cells_x;
    s.gate.pyramid_hi = table.pyramid_hi;
    s.gate.pyramid_start = table.pyramid_start;
    s.gate.lattice = l;
}

// Lets search s enter only the subtrees with a dart whose key is at most `key`.
VRPD_FN void field_search_gate_key(VRPD_INOUT(FieldSearch) s, FieldWords keys, uint key) {
    s.gate.keyed = 1u;
    s.gate.keys = keys;
    s.gate.key = key;
}

// The greatest r over the block of side 2^bits at `corner` (aligned to its side, inside the
// tiles): the pyramid's block of cells that holds it, at level 1 at least.
VRPD_FN uint field_gate_max(VRPD_IN(FieldGate) g, uvec2 corner, uint bits) {
    uint k = max(bits, g.cell_bits + 1u) - g.cell_bits;
    if (k > g.levels) return g.r_hi;
    uint w = (g.cells_x + (1u << k) - 1u) >> k;
    return g.pyramid_hi
        .value[g.pyramid_start.value[k] + (corner.y >> (g.cell_bits + k)) * w + (corner.x >> (g.cell_bits + k))];
}

// The bound of f between the gate's point and a point of radius `other` of a block.
VRPD_FN uint field_gate_f(VRPD_IN(FieldGate) g, uint other) {
    return g.later != 0u ? rule_f(g.rule, g.r, other) : rule_f(g.rule, other, g.r);
}

// Does the gate let search s enter node `word`, of side 2^bits at offsets (x, y) in the tile?
VRPD_FN bool field_gate_admits(VRPD_INOUT(FieldSearch) s, uint word, uint x, uint y, uint bits) {
    if (s.gate.keyed != 0u && (word & FIELD_LEAF) == 0u) {
        s.steps++;
        if (s.gate.keys.value[(word & FIELD_INDEX) >> 2u] > s.gate.key) return false;
    }
    if (s.gate.reached == 0u) return true;
    s.steps++;
    uvec2 a = uvec2(s.origin_x + x, s.origin_y + y);
    uint last = (1u << bits) - 1u;
    uvec2 b = uvec2(min(a.x + last, s.gate.lattice.extent_x - 1u), min(a.y + last, s.gate.lattice.extent_y - 1u));
    uint64_t d2 = near_distance2(s.gate.lattice, s.gate.point, a, b);
    // f is at least the rule's f of r and 0: within that, no bound is needed.
    if (field_conflict(field_gate_f(s.gate, 0u), d2)) return true;
    return field_conflict(field_gate_f(s.gate, field_gate_max(s.gate, a, bits)), d2);
}
#endif

// A search around [a, b] (inside the lattice) of reach `reach`, entering only subtrees with
// `need` (0: every one inside the lattice), of at most `budget` steps.
VRPD_FN FieldSearch field_search_begin(VRPD_IN(FieldTreeView) t, Lattice l, uvec2 a, uvec2 b, uint64_t reach, uint need,
                                       uint budget) {
    FieldSearch s;
    s.need = need;
    s.steps = 0u;
    s.budget = budget;
#ifdef FIELD_SEARCH_GATED
    field_search_ungated(s);
#endif
    s.depth = FIELD_SEARCH_BETWEEN;
    s.x = 0u;
    s.y = 0u;
    s.origin_x = 0u;
    s.origin_y = 0u;
    s.visited = 0u;
    s.word = 0u;
    s.root = 0u;
    s.clip_lo_x = 0u;
    s.clip_hi_x = 0u;
    s.clip_lo_y = 0u;
    s.clip_hi_y = 0u;
    int64_t tiles_y = int64_t(t.tiles_y);
    int64_t tiles_x = int64_t(t.tiles_x);
    s.lo_x = int64_t(a.x) - int64_t(reach);
    s.hi_x = int64_t(b.x) + int64_t(reach);
    s.lo_y = int64_t(a.y) - int64_t(reach);
    s.hi_y = int64_t(b.y) + int64_t(reach);
    s.all_x = (l.periodic != 0u && s.hi_x - s.lo_x + 1 >= int64_t(l.extent_x)) ? 1u : 0u;
    s.all_y = (l.periodic != 0u && s.hi_y - s.lo_y + 1 >= int64_t(l.extent_y)) ? 1u : 0u;
    // The tile range per axis: every tile where the square spans the torus; on a torus the
    // floor of each end (negative ends too); on a free box clipped to the lattice.
    int64_t x0 = 0;
    int64_t x1 = tiles_x - 1;
    int64_t y0 = 0;
    int64_t y1 = tiles_y - 1;
    if (s.all_x == 0u) {
        x0 = l.periodic != 0u ? s.lo_x >> t.tile_bits : max(s.lo_x, int64_t(0)) >> t.tile_bits;
        x1 = l.periodic != 0u ? s.hi_x >> t.tile_bits : min(tiles_x - 1, max(s.hi_x, int64_t(0)) >> t.tile_bits);
        if (l.periodic == 0u && s.hi_x < 0) x1 = x0 - 1;
    }
    if (s.all_y == 0u) {
        y0 = l.periodic != 0u ? s.lo_y >> t.tile_bits : max(s.lo_y, int64_t(0)) >> t.tile_bits;
        y1 = l.periodic != 0u ? s.hi_y >> t.tile_bits : min(tiles_y - 1, max(s.hi_y, int64_t(0)) >> t.tile_bits);
        if (l.periodic == 0u && s.hi_y < 0) y1 = y0 - 1;
    }
    s.tile_x0 = int(x0);
    s.tile_x1 = int(x1);
    s.tile_y1 = int(y1);
    // Before the first tile: field_search_next steps to (x0, y0).
    s.tile_x = int(x0) - 1;
    s.tile_y = int(y0);
    if (x1 < x0) s.tile_y = int(y1) + 1;  // no column: no tile
    return s;
}

// Is a node word one the search enters?
VRPD_FN bool field_search_enters(VRPD_IN(FieldSearch) s, uint word) {
    return s.need != 0u ? (word & s.need) != 0u : word != FIELD_OUTSIDE;
}

// Does the block of side 2^bits at offsets (x, y) from the tile's corner meet the clipped square?
VRPD_FN bool field_search_meets(VRPD_IN(FieldSearch) s, uint x, uint y, uint bits) {
    uint last = (1u << bits) - 1u;
    return x <= s.clip_hi_x && x + last >= s.clip_lo_x && y <= s.clip_hi_y && y + last >= s.clip_lo_y;
}

// The first child, from child `from` on, of inner node `node` at the current depth that meets
// the square and is entered: made the current node (unvisited). False if none is.
VRPD_FN bool field_search_child(VRPD_IN(FieldTreeView) t, VRPD_INOUT(FieldSearch) s, uint node, uint from) {
    uint side = 1u << (t.tile_bits - s.depth - 1u);
    for (uint c = from; c < 4u; c++) {
        s.steps++;
        uint word = t.nodes.value[(node & FIELD_INDEX) + c];
        uint cx = s.x + (c & 1u) * side;
        uint cy = s.y + (c >> 1u) * side;
        uint bits = t.tile_bits - s.depth - 1u;
        if (!field_search_enters(s, word) || !field_search_meets(s, cx, cy, bits)) continue;
#ifdef FIELD_SEARCH_GATED
        if (!field_gate_admits(s, word, cx, cy, bits)) continue;
#endif
        s.depth++;
        s.word = word;
        s.x = cx;
        s.y = cy;
        s.visited = 0u;
        return true;
    }
    return false;
}

// The word of the current node, found again by descent from the tile's root.
VRPD_FN uint field_search_word(VRPD_IN(FieldTreeView) t, VRPD_INOUT(FieldSearch) s) {
    uint word = s.root;
    uint bits = t.tile_bits;
    for (uint d = 0u; d < s.depth; d++) {
        s.steps++;
        word = t.nodes.value[(word & FIELD_INDEX) + field_child_of(uvec2(s.x, s.y), bits)];
        bits--;
    }
    return word;
}

// Steps to the next tile in range whose root is entered, made the current node; false when none
// is left or the budget ran out.
VRPD_FN bool field_search_next_tile(VRPD_IN(FieldTreeView) t, VRPD_INOUT(FieldSearch) s) {
    int tiles_x = int(t.tiles_x);
    int tiles_y = int(t.tiles_y);
    int64_t last = (int64_t(1) << t.tile_bits) - 1;
    for (;;) {
        s.steps++;
        if (s.steps > s.budget) return false;
        s.tile_x++;
        if (s.tile_x > s.tile_x1) {
            s.tile_x = s.tile_x0;
            s.tile_y++;
        }
        if (s.tile_y > s.tile_y1) return false;
        // A square narrower than the torus meets its tiles' images one period either side at most.
        int wx = s.tile_x < 0 ? s.tile_x + tiles_x : (s.tile_x >= tiles_x ? s.tile_x - tiles_x : s.tile_x);
        int wy = s.tile_y < 0 ? s.tile_y + tiles_y : (s.tile_y >= tiles_y ? s.tile_y - tiles_y : s.tile_y);
        uint root = t.roots.value[uint(wy) * t.tiles_x + uint(wx)];
        if (!field_search_enters(s, root)) continue;
        s.origin_x = uint(wx) << t.tile_bits;
        s.origin_y = uint(wy) << t.tile_bits;
#ifdef FIELD_SEARCH_GATED
        if (!field_gate_admits(s, root, 0u, 0u, t.tile_bits)) continue;
#endif
        int64_t ox = int64_t(s.tile_x) << t.tile_bits;
        int64_t oy = int64_t(s.tile_y) << t.tile_bits;
        s.clip_lo_x = s.all_x != 0u ? 0u : uint(clamp(s.lo_x - ox, int64_t(0), last));
        s.clip_hi_x = s.all_x != 0u ? uint(last) : uint(clamp(s.hi_x - ox, int64_t(0), last));
        s.clip_lo_y = s.all_y != 0u ? 0u : uint(clamp(s.lo_y - oy, int64_t(0), last));
        s.clip_hi_y = s.all_y != 0u ? uint(last) : uint(clamp(s.hi_y - oy, int64_t(0), last));
        s.depth = 0u;
        s.root = root;
        s.word = root;
        s.x = 0u;
        s.y = 0u;
        s.visited = 0u;
        return true;
    }
}

// The next leaf the search meets (its index), or FIELD_SEARCH_DONE, or FIELD_SEARCH_OVERFLOW
// (then again on every call). A leaf met at two images of a torus is given twice, as the host's
// search visits it twice.
VRPD_FN uint field_search_next(VRPD_IN(FieldTreeView) t, VRPD_INOUT(FieldSearch) s) {
    for (;;) {
        s.steps++;
        if (s.steps > s.budget) {
            s.steps = s.budget + 1u;
            return FIELD_SEARCH_OVERFLOW;
        }
        if (s.depth == FIELD_SEARCH_BETWEEN) {
            if (!field_search_next_tile(t, s)) return s.steps > s.budget ? FIELD_SEARCH_OVERFLOW : FIELD_SEARCH_DONE;
            continue;
        }
        if (s.visited == 0u) {
            s.visited = 1u;
            if ((s.word & FIELD_LEAF) != 0u) {
                s.steps++;  // the caller's pass over the leaf
                return s.word & FIELD_INDEX;
            }
            if (field_search_child(t, s, s.word, 0u)) continue;
        }
        // The current node is done: on to its next sibling, else up to its parent (done too).
        if (s.depth == 0u) {
            s.depth = FIELD_SEARCH_BETWEEN;
            continue;
        }
        uint bits = t.tile_bits - s.depth;
        uint c = ((s.x >> bits) & 1u) | (((s.y >> bits) & 1u) << 1u);
        s.x &= ~((2u << bits) - 1u);
        s.y &= ~((2u << bits) - 1u);
        s.depth--;
        uint parent = field_search_word(t, s);
        s.word = parent;
        if (field_search_child(t, s, parent, c + 1u)) continue;
        s.visited = 1u;
    }
}

VRPD_END
#endif
