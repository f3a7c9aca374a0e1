// Spatially varying radii (paper section 5, Eqs. 10-12) on the integer lattice. The sizing field
// is a table of radii in lattice units at the nodes of a square grid whose cells span 2^bits
// lattice units (bits <= MAX_FIELD_CELL_BITS); r at a lattice point is the floor of the bilinear
// interpolant of its cell's four nodes, computed in 64-bit integers: one rounding, the same on
// every device. The rules' radius f, conflicts |x - y|^2 < f^2 and the thinning of Eq. 12 are
// integer functions of it too.
#ifndef VRPD_FIELD_H
#define VRPD_FIELD_H
#include "bridge.h"

VRPD_BEGIN

// With node values below 2^32 and 2^bits-unit cells, the interpolant's sums stay below 2^(32 + 2 bits).
const uint MAX_FIELD_CELL_BITS = 15u;

// Table 1's rules (SizingRule's order): f(x, y) for an earlier sample x and a later point y.
const uint RULE_PRIOR = 0u;
const uint RULE_CURRENT = 1u;
const uint RULE_BIGGER = 2u;
const uint RULE_SMALLER = 3u;

// The interpolant's two steps: along x between nodes v0 and v1 at offset f (times 2^bits), then
// along y between two such rows at offset f, floored.
VRPD_FN uint64_t field_row(uint v0, uint v1, uint f, uint bits) {
    return uint64_t(v0) * ((uint64_t(1) << bits) - uint64_t(f)) + uint64_t(v1) * uint64_t(f);
}
VRPD_FN uint field_blend(uint64_t row0, uint64_t row1, uint f, uint bits) {
    return uint((row0 * ((uint64_t(1) << bits) - uint64_t(f)) + row1 * uint64_t(f)) >> (2u * bits));
}

// r at offset f (0 <= f < 2^bits on each axis) inside a table cell with nodes
// v = (v00, v10, v01, v11) (x first): floor of the bilinear interpolant.
VRPD_FN uint field_interpolate(uvec4 v, uvec2 f, uint bits) {
    return field_blend(field_row(v.x, v.y, f.x, bits), field_row(v.z, v.w, f.x, bits), f.y, bits);
}

// f(x, y) from r(x) of the earlier sample and r(y) of the later point. Non-decreasing in both,
// so a lower bound of r over a region gives a lower bound of f over it.
VRPD_FN uint rule_f(uint rule, uint r_earlier, uint r_later) {
    if (rule == RULE_PRIOR) return r_earlier;
    if (rule == RULE_CURRENT) return r_later;
    if (rule == RULE_BIGGER) return max(r_earlier, r_later);
    return min(r_earlier, r_later);
}

// Eq. 10: points at squared lattice distance d2 conflict under radius f (f < 2^32: f^2 < 2^64).
VRPD_FN bool field_conflict(uint f, uint64_t d2) { return d2 < uint64_t(f) * uint64_t(f); }

// Eq. 12 by thinning: a dart thrown at the rate of radius `bound` <= r is kept with probability
// (bound / r)^2, decided by comparing a uniform 32-bit hash with it in 2^-32 units.
VRPD_FN bool keep_weighted(uint hash, uint bound, uint r) {
    if (bound >= r) return true;
    uint64_t t = (uint64_t(bound) << 32) / uint64_t(r);  // < 2^32
    return uint64_t(hash) < ((t * t) >> 32);
}

// Eq. 12's weight of a cell whose least r is `lo`: the most w <= 31 with r_lo 2^w <= lo, so that
// darts thrown at the rate of radius r_lo 2^w (<= r over the cell) are thinned by keep_weighted.
VRPD_FN uint field_cell_weight(uint r_lo, uint lo) {
    uint w = 0u;
    while (w < 31u && (uint64_t(r_lo) << (w + 1u)) <= uint64_t(lo)) w++;
    return w;
}

VRPD_END
#endif
