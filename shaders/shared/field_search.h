// The device's leaf search over a sizing field's leaf tree (shared/field_tree.h): the leaves that
// meet the square `reach` around a block [a, b] (on a torus, around any image), as an iterator a
// kernel steps through with field_search_next. It meets the leaves the host's search
// (FieldQuadtree::near, near_samples, near_fresh) meets, tile by tile in the same ranges; inside a
// tile it holds only the current node and finds a parent's word again by descent from the root,
// where the host keeps a stack of siblings to visit (field/quadtree.h) that a device cannot hold.
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

VRPD_BEGIN

// What field_search_next gives when no leaf is left, and when the budget ran out first.
const uint FIELD_SEARCH_DONE = 0xFFFFFFFFu;
const uint FIELD_SEARCH_OVERFLOW = 0xFFFFFFFEu;
// The search's state of `depth`: no node (between tiles), or a node not yet visited.
const uint FIELD_SEARCH_BETWEEN = 0xFFFFFFFFu;

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
    uint visited;
    uint word;
    uint root;
    // The steps taken, and the most allowed.
    uint steps;
    uint budget;
};

// A search around [a, b] (inside the lattice) of reach `reach`, entering only subtrees with
// `need` (0: every one inside the lattice), of at most `budget` steps.
VRPD_FN FieldSearch field_search_begin(VRPD_IN(FieldTreeView) t, Lattice l, uvec2 a, uvec2 b, uint64_t reach, uint need,
                                       uint budget) {
    FieldSearch s;
    s.need = need;
    s.steps = 0u;
    s.budget = budget;
    s.depth = FIELD_SEARCH_BETWEEN;
    s.x = 0u;
    s.y = 0u;
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
        if (!field_search_enters(s, word) || !field_search_meets(s, cx, cy, t.tile_bits - s.depth - 1u)) continue;
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
