// The sampling domain on an integer lattice, and the exact predicates on it (paper Eqs. 1-3).
// Positions are 31-bit lattice coordinates; squared distances are exact 64-bit integers, so the
// conflict and cover tests give the same answer on every device and on the CPU.
#ifndef VRPD_DOMAIN_H
#define VRPD_DOMAIN_H
#include "bridge.h"

VRPD_BEGIN

// Everything a kernel needs to know about the domain. Crosses the bus inside push constants.
// Base cells are squares of 2^cell_bits lattice units whose diagonal is shorter than the radius,
// so a base cell holds at most one sample and a sample covers its whole base cell.
struct Domain {
    uint64_t radius2;      // inhibition Rf: conflict iff squared lattice distance < radius2 (Eqs. 1, 5)
    uint64_t cover2;       // coverage Rc: a point is covered iff its squared distance < cover2 (Eqs. 2, 7);
                           // equal to radius2 for one radius, else at most MAX_COVER2 (see coverage.h)
    uint lattice_x;        // lattice points per row: x in [0, lattice_x); < 2^31
    uint lattice_y;
    uint cells_x;          // base cells per row
    uint cells_y;
    uint cell_bits;        // base cell side = 1 << cell_bits lattice units
    uint periodic;         // 1: torus of lattice_x * lattice_y, 0: free boundary
    uint reach;            // base cells within this many rows/columns may hold: a conflicting sample (bits
                           // 0-7, <= MAX_REACH), a covering one (bits 8-15), one within 2 Rc (bits 16-23);
                           // bits 24 + 2 |dy|: the conflict scans' row_reach of row dy (conflict_row)
    uint seed;
};

const uint MAX_REACH = 3u;

VRPD_FN bool two_radii(Domain dom) { return dom.cover2 != dom.radius2; }
// A kernel built for one radius only defines VRPD_ONE_RADIUS before its includes: the code that
// serves two radii (the T tests of coverage.h, the corner bookkeeping, the grid-scan fallback of
// a cell test) is then left out of its SPIR-V, under #ifndef where kernels reach it. llvmpipe
// runs every branch of a SIMD batch whether a lane takes it or not, and every loop body at least
// once (measured: a block of 400 hashes that no dart entered added 1.1 s to throw_masked at
// r = 0.001), so code merely never taken costs there. Left out, it saved at r = 0.001:
// refine_masked 2.5-2.7 s -> 1.3 s (then 1.34-1.47 s -> 1.16-1.29 s for the corner bookkeeping
// and the fallback), resolve_darts 1.4-1.5 s -> 1.1-1.3 s, and 0.45 s of the 0.85 s it took to
// build the kernels. (A specialization constant that folds the code away kept most of the
// run-time gain but only 0.1 s of the build's.) The Vulkan engine builds each such kernel's
// one-radius variant or its two-radii one (*_two.comp) for the run.
VRPD_FN int conflict_reach(Domain dom) { return int(dom.reach & 0xFFu); }
VRPD_FN int cover_reach(Domain dom) { return int((dom.reach >> 8u) & 0xFFu); }
// The widest neighbourhood any kernel scans: 2 Rc with two radii (a dart's membership in T
// depends on the samples within 2 Rc), else Rf.
VRPD_FN uint influence_reach(Domain dom) { return (dom.reach >> 16u) & 0xFFu; }
// Squared radius of the influence neighbourhood: samples at distance^2 <= 4 Rc^2 can matter.
VRPD_FN uint64_t influence2(Domain dom) { return uint64_t(4) * dom.cover2 + uint64_t(1); }

// Grid words (one uvec2 per base cell): a sample's lattice position, or one of these tags.
// Lattice coordinates are < 2^31, so bit 31 of .x marks a tag.
const uint GRID_TAG = 0x80000000u;
const uint GRID_EMPTY = 0xFFFFFFFFu;  // .x of an empty cell
// A cell whose .x is GRID_TAG | first holds this round's darts [first, .y) (first < 2^30). In
// mask mode (sampler.h) .x is GRID_TAG | GRID_PACKED | first and .y packs the dart count (high
// 16 bits) with the base cell's mask of active sub-cells (low 16 bits); an empty cell's .y is
// that mask between rounds.
const uint GRID_PACKED = 0x40000000u;
const uint GRID_MASK_BITS = 0xFFFFu;

VRPD_FN bool grid_is_sample(uvec2 word) { return (word.x & GRID_TAG) == 0u; }
VRPD_FN bool grid_is_darts(uvec2 word) { return word.x != GRID_EMPTY && (word.x & GRID_TAG) != 0u; }
// The darts [first, end) of a darts word.
VRPD_FN uvec2 grid_darts(uvec2 word) {
    uint first = word.x & ~(GRID_TAG | GRID_PACKED);
    return uvec2(first, (word.x & GRID_PACKED) != 0u ? first + (word.y >> 16u) : word.y);
}

// Absolute difference of two coordinates along one axis, the shorter way round on a torus.
VRPD_FN uint axis_gap(uint a, uint b, uint extent, uint periodic) {
    uint d = a > b ? a - b : b - a;
    if (periodic != 0u && d > extent - d) d = extent - d;
    return d;
}

VRPD_FN uint64_t distance2(Domain dom, uvec2 p, uvec2 q) {
    uint64_t dx = uint64_t(axis_gap(p.x, q.x, dom.lattice_x, dom.periodic));
    uint64_t dy = uint64_t(axis_gap(p.y, q.y, dom.lattice_y, dom.periodic));
    return dx * dx + dy * dy;
}

// Eq. 1: two samples conflict iff they are closer than Rf (Eq. 5). A point at distance exactly Rc is
// uncovered (Eqs. 2, 7), so conflict and cover are the same strict test, with one radius or another.
VRPD_FN bool in_disk(Domain dom, uvec2 centre, uvec2 p) { return distance2(dom, centre, p) < dom.radius2; }

// Signed offset from coordinate a to b along one axis, the shorter way round on a torus. Exact
// when |offset| < extent / 2 (callers use it only within 2 Rc, less than a quarter of the torus).
// Coordinates are below 2^31, so 32-bit arithmetic holds every step.
VRPD_FN int axis_offset(uint a, uint b, uint extent, uint periodic) {
    int d = int(b) - int(a);
    int half_extent = int(extent / 2u);
    if (periodic != 0u) d += d > half_extent ? -int(extent) : (d < -half_extent ? int(extent) : 0);
    return d;
}

VRPD_FN ivec2 offset_to(Domain dom, uvec2 from, uvec2 to) {
    return ivec2(axis_offset(from.x, to.x, dom.lattice_x, dom.periodic), axis_offset(from.y, to.y, dom.lattice_y, dom.periodic));
}

VRPD_FN bool in_domain(Domain dom, uvec2 p) { return p.x < dom.lattice_x && p.y < dom.lattice_y; }

// Squared gap between a base cell and the one (dx, dy) cells away: no point of the two is nearer.
VRPD_FN uint64_t cell_gap2(Domain dom, int dx, int dy) {
    uint side = 1u << dom.cell_bits;
    uint ax = uint(dx < 0 ? -dx : dx);
    uint ay = uint(dy < 0 ? -dy : dy);
    uint64_t gx = ax == 0u ? uint64_t(0) : uint64_t(ax - 1u) * uint64_t(side) + uint64_t(1);
    uint64_t gy = ay == 0u ? uint64_t(0) : uint64_t(ay - 1u) * uint64_t(side) + uint64_t(1);
    return gx * gx + gy * gy;
}

VRPD_FN uvec2 base_cell_of(Domain dom, uvec2 p) { return uvec2(p.x >> dom.cell_bits, p.y >> dom.cell_bits); }
VRPD_FN uint base_index(Domain dom, uvec2 cell) { return cell.y * dom.cells_x + cell.x; }

// Is base cell `cell` at least influence_reach cells from every side of the grid? Then its
// neighbours' indices are plain offsets from its own: no wrap, no side to fall off.
VRPD_FN bool inner_cell(Domain dom, uvec2 cell) {
    uint r = influence_reach(dom);
    return cell.x >= r && cell.x + r < dom.cells_x && cell.y >= r && cell.y + r < dom.cells_y;
}

// neighbour_index for a cell near a side of the grid. make_plan guarantees influence_reach <=
// cells per side, so one wrap step suffices on a torus.
VRPD_COLD_FN uint wrapped_neighbour_index(Domain dom, uvec2 cell, int dx, int dy) {
    int x = int(cell.x) + dx;
    int y = int(cell.y) + dy;
    int w = int(dom.cells_x);
    int h = int(dom.cells_y);
    if (dom.periodic != 0u) {
        x += x < 0 ? w : (x >= w ? -w : 0);
        y += y < 0 ? h : (y >= h ? -h : 0);
    } else if (x < 0 || y < 0 || x >= w || y >= h) {
        return GRID_EMPTY;
    }
    return uint(y) * dom.cells_x + uint(x);
}

// Index of the base cell (cx + dx, cy + dy), or GRID_EMPTY when it falls off a free boundary.
// `inner` is inner_cell(dom, cell), computed once per scan.
VRPD_FN uint neighbour_index(Domain dom, uvec2 cell, bool inner, int dx, int dy) {
    if (inner) return uint(int(base_index(dom, cell)) + dy * int(dom.cells_x) + dx);
    return wrapped_neighbour_index(dom, cell, dx, dy);
}

// The columns a scan of row dy (|dy| <= reach) must visit: |dx| <= row_reach, the cells some of
// whose points are closer than sqrt(limit2) to some point of the centre cell; -1 if none is.
// Scans over these use neighbour_index, which leaves out only cells off a free boundary.
VRPD_FN int computed_row_reach(Domain dom, int dy, int reach, uint64_t limit2) {
    int w = reach;
    while (w >= 0 && cell_gap2(dom, w, dy) >= limit2) w--;
    return w;
}

// computed_row_reach for the conflict scans (radius2, conflict_reach), which the plan stores in
// bits 24-31 of Domain::reach: 0 to MAX_REACH, since the centre column of a row within the reach
// is always within it. Those scans run for every dart (and with one radius for every cell test
// too); computing their rows took 3.8 % of the cpu's instructions at r = 0.002.
VRPD_FN int conflict_row(Domain dom, int dy) { return int((dom.reach >> (24u + 2u * uint(dy < 0 ? -dy : dy))) & 3u); }

VRPD_FN int row_reach(Domain dom, int dy, int reach, uint64_t limit2) {
    if (limit2 == dom.radius2 && reach == conflict_reach(dom)) return conflict_row(dom, dy);
    return computed_row_reach(dom, dy, reach, limit2);
}

// The domain as seen from base cell `cell`: on a torus, a cell whose neighbourhood does not
// wrap, on a torus at least 2 (reach + 1) cells wide, sees every relevant offset shorter than half
// the torus, so straight distances equal torus distances there and the wrap can be skipped.
// Every predicate gives the same answer with either domain; this one is cheaper.
VRPD_FN Domain local_domain(Domain dom, uvec2 cell) {
    uint r = influence_reach(dom);
    if (dom.periodic != 0u && inner_cell(dom, cell) && dom.cells_x >= 2u * r + 2u && dom.cells_y >= 2u * r + 2u)
        dom.periodic = 0u;
    return dom;
}

VRPD_END
#endif
