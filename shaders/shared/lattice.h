// The integer lattice the samples live on (paper section 1, made exact): extent, periodicity and
// the exact squared distance. Coordinates are below 2^31 and squared distances are exact 64-bit
// integers, so every predicate gives the same answer on every device and on the host. The
// lattice's spacing in user units (Plan::quantum) is chosen from the box and the smallest radius
// a run can meet; the kernels never need it.
#ifndef VRPD_LATTICE_H
#define VRPD_LATTICE_H
#include "bridge.h"

VRPD_BEGIN

struct Lattice {
    uint extent_x;         // lattice points per row: x in [0, extent_x); < 2^31
    uint extent_y;
    uint periodic;         // 1: a torus of extent_x * extent_y, 0: a free boundary
};
#ifdef __cplusplus
static_assert(sizeof(Lattice) == 12 && offsetof(Lattice, periodic) == 8);  // std430, as glslang lays it out
#endif

// Absolute difference of two coordinates along one axis, the shorter way round on a torus.
VRPD_FN uint axis_gap(uint a, uint b, uint extent, uint periodic) {
    uint d = a > b ? a - b : b - a;
    if (periodic != 0u && d > extent - d) d = extent - d;
    return d;
}

// The greatest gap along one axis from v to a coordinate of [from, to] (from <= to): at an end, or
// on a torus half of it where [from, to] holds the coordinates that far round either way. Sums
// stay below 2^32: v < extent <= 2^31.
VRPD_FN uint axis_far_gap(uint v, uint from, uint to, uint extent, uint periodic) {
    if (periodic != 0u) {
        uint half_extent = extent / 2u;
        uint ahead = (v + half_extent) % extent, behind = (v + (extent - half_extent)) % extent;
        if ((ahead >= from && ahead <= to) || (behind >= from && behind <= to)) return half_extent;
    }
    return max(axis_gap(v, from, extent, periodic), axis_gap(v, to, extent, periodic));
}

// The least gap along one axis from v to a coordinate of [from, to] (from <= to): 0 inside it,
// else the nearer end, on a torus the shorter way round.
VRPD_FN uint axis_near_gap(uint v, uint from, uint to, uint extent, uint periodic) {
    if (v >= from && v <= to) return 0u;
    return min(axis_gap(v, from, extent, periodic), axis_gap(v, to, extent, periodic));
}

// The squared distance from x to the nearest point of [a, b].
VRPD_FN uint64_t near_distance2(Lattice l, uvec2 x, uvec2 a, uvec2 b) {
    uint64_t gx = uint64_t(axis_near_gap(x.x, a.x, b.x, l.extent_x, l.periodic));
    uint64_t gy = uint64_t(axis_near_gap(x.y, a.y, b.y, l.extent_y, l.periodic));
    return gx * gx + gy * gy;
}

// The squared distance from x to the farthest point of [a, b]: the greatest gap along each axis.
VRPD_FN uint64_t far_distance2(Lattice l, uvec2 x, uvec2 a, uvec2 b) {
    uint64_t gx = uint64_t(axis_far_gap(x.x, a.x, b.x, l.extent_x, l.periodic));
    uint64_t gy = uint64_t(axis_far_gap(x.y, a.y, b.y, l.extent_y, l.periodic));
    return gx * gx + gy * gy;
}

VRPD_FN uint64_t distance2(Lattice l, uvec2 p, uvec2 q) {
    uint64_t dx = uint64_t(axis_gap(p.x, q.x, l.extent_x, l.periodic));
    uint64_t dy = uint64_t(axis_gap(p.y, q.y, l.extent_y, l.periodic));
    return dx * dx + dy * dy;
}

// Signed offset from coordinate a to b along one axis, the shorter way round on a torus. Exact
// when |offset| < extent / 2 (callers use it only within 2 Rc, less than a quarter of the torus).
// Coordinates are below 2^31, so 32-bit arithmetic holds every step.
VRPD_FN int axis_offset(uint a, uint b, uint extent, uint periodic) {
    int d = int(b) - int(a);
    int half_extent = int(extent / 2u);
    if (periodic != 0u) d += d > half_extent ? -int(extent) : (d < -half_extent ? int(extent) : 0);
    return d;
}

VRPD_FN ivec2 offset_to(Lattice l, uvec2 from, uvec2 to) {
    return ivec2(axis_offset(from.x, to.x, l.extent_x, l.periodic), axis_offset(from.y, to.y, l.extent_y, l.periodic));
}

VRPD_FN bool in_lattice(Lattice l, uvec2 p) { return p.x < l.extent_x && p.y < l.extent_y; }

VRPD_END
#endif
