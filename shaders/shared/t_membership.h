// Exact membership in the paper's T = S ∩ (U ⊕ Rc) (section 3, Eq. 9) for two radii Rf < Rc:
// does the closed Rc-disk around a dart y reach a point that no earlier sample's open Rc-disk
// covers? All disks have one radius Rc (squared radius R2 = Radii::coverage2, an integer in lattice
// units), and every quantity below is an integer: the answer is exact and the same on every device.
//
// The method. Let K = (closed disk of y) minus (the open disks of the samples within 2 Rc of y).
// If K is not empty, either y itself is in K, or K has a vertex: a point where two of the circles
// (y's own or the samples') cross, lying in y's closed disk and in no sample's open disk. (A
// component of K without a vertex is bounded by whole circles; with equal radii that forces y's
// circle to meet no other disk, so y is in K, or a sample at y itself, which the Rf test rejects.)
// So y reaches U iff y is uncovered or one of those O(n^2) intersection points is uncovered.
// With a free boundary U (and so K) is clipped to the box [0, lattice_x - 1] x [0, lattice_y - 1],
// and K's vertices also include the crossings of the circles with the box's sides and its corners.
// The same search, with a square in place of y's disk, tells whether a quadtree cell still holds a
// point of U: its corners, the circles' crossings with its sides, and crossings inside it.
//
// Precision. An intersection point p = m + sigma h n/|n| of the circles around a and b (m the
// midpoint, n = perp(b - a), L = |b - a|^2, h^2 = R2 - L/4) is irrational, but for a third centre c
//     4 sqrt(L) (|p - c|^2 - R2) = A sqrt(L) + sigma B sqrt(M),
//     A = |e|^2 - L,  B = 2 e.n,  e = a + b - 2c,  M = 4 R2 - L,
// so its side of c's circle is the sign of A sqrt(L) + B' sqrt(M), decided by comparing A^2 L with
// B'^2 M. With R2 <= MAX_COVER2 = 2^38 and only centres c with |e|^2 <= 16 R2 compared (others are
// more than Rc from p), both products are below 2^124: 128-bit integers, no floating point.
#ifndef VRPD_COVERAGE_H
#define VRPD_COVERAGE_H
#include "bridge.h"

VRPD_BEGIN

const uint64_t MAX_COVER2 = uint64_t(1) << 38;

// Centres (offsets from the dart, |offset|^2 <= 4 R2) of the disks a test considers. Samples are
// >= Rf apart, so (4 Rc / Rf + 1)^2 = 289 could fit around a dart at Rc = 4 Rf; tests meet far
// fewer (docs/performance.md).
const uint MAX_DISKS = 64u;
VRPD_PRIVATE ivec2 disk_at[MAX_DISKS];

// The test's cost is bounded: it takes at most T_TEST_BUDGET loop steps, counted alike on every
// device, and answers T_UNKNOWN past them; tests take far fewer (docs/performance.md). The bound
// matters on lavapipe: llvmpipe ends every loop of a shader once 65 535 iterations have run in
// one SIMD batch of invocations, without an error.
const uint T_TEST_BUDGET = 8192u;
const uint T_OUTSIDE = 0u;  // the dart is not in T
const uint T_INSIDE = 1u;
const uint T_UNKNOWN = 2u;  // the budget ran out (or more than MAX_DISKS disks)
VRPD_PRIVATE uint t_steps;
// One loop step of the test; false once the budget is spent (every loop then ends).
VRPD_FN bool t_step() {
    t_steps++;
    return t_steps <= T_TEST_BUDGET;
}

VRPD_FN uint64_t norm2(ivec2 v) {
    int64_t x = int64_t(v.x);
    int64_t y = int64_t(v.y);
    return uint64_t(x * x + y * y);
}

// a * b as a 128-bit (hi, lo), from 32-bit halves (GLSL has no 64-bit widening multiply).
VRPD_FN void mul_wide_halves(uint64_t a, uint64_t b, VRPD_OUT(uint64_t) hi, VRPD_OUT(uint64_t) lo) {
    uint64_t low32 = uint64_t(0xFFFFFFFFu);
    uint64_t p00 = (a & low32) * (b & low32);
    uint64_t p01 = (a & low32) * (b >> 32);
    uint64_t p10 = (a >> 32) * (b & low32);
    uint64_t p11 = (a >> 32) * (b >> 32);
    uint64_t mid = (p00 >> 32) + (p01 & low32) + (p10 & low32);
    lo = (p00 & low32) | (mid << 32);
    hi = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
}

// a * b as a 128-bit (hi, lo): the same exact product, by the host's native 128-bit multiply
// (a test checks mul_wide_halves against it).
#ifdef __cplusplus
VRPD_FN void mul_wide(uint64_t a, uint64_t b, VRPD_OUT(uint64_t) hi, VRPD_OUT(uint64_t) lo) {
    const unsigned __int128 p = static_cast<unsigned __int128>(a) * b;
    hi = uint64_t(p >> 64);
    lo = uint64_t(p);
}
#else
void mul_wide(uint64_t a, uint64_t b, out uint64_t hi, out uint64_t lo) { mul_wide_halves(a, b, hi, lo); }
#endif

// s^2 m as a 128-bit (hi, lo); the caller guarantees s^2 m < 2^128.
VRPD_FN void square_times(uint64_t s, uint64_t m, VRPD_OUT(uint64_t) hi, VRPD_OUT(uint64_t) lo) {
    uint64_t h1;
    uint64_t l1;
    mul_wide(s, s, h1, l1);
    uint64_t h2;
    mul_wide(l1, m, h2, lo);
    hi = h2 + h1 * m;
}

// The sign of a 64-bit integer, read from its high word: Mesa 22.3's lavapipe miscompiles some
// comparisons of sign-extended 64-bit integers with 0 (int64_t(x) < int64_t(0) came out false for
// a negative x), which the coverage_probe test caught; 32-bit tests of the high word are right.
VRPD_FN bool is_negative(int64_t v) { return (uint(uint64_t(v) >> 32) & 0x80000000u) != 0u; }
VRPD_FN int sign_of(int64_t v) { return is_negative(v) ? -1 : (v != int64_t(0) ? 1 : 0); }
VRPD_FN uint64_t magnitude(int64_t v) { return is_negative(v) ? uint64_t(0) - uint64_t(v) : uint64_t(v); }

// The sign of a sqrt(l) + b sqrt(m), exactly (a^2 l and b^2 m below 2^128).
VRPD_FN int sign_of_root_sum(int64_t a, uint64_t l, int64_t b, uint64_t m) {
    int sa = l == uint64_t(0) ? 0 : sign_of(a);
    int sb = m == uint64_t(0) ? 0 : sign_of(b);
    if (sa == sb || sb == 0) return sa;
    if (sa == 0) return sb;
    uint64_t ah;
    uint64_t al;
    uint64_t bh;
    uint64_t bl;
    square_times(magnitude(a), l, ah, al);
    square_times(magnitude(b), m, bh, bl);
    if (ah == bh && al == bl) return 0;
    return (ah > bh || (ah == bh && al > bl)) ? sa : sb;
}

// Sign of |p - c|^2 - R2 for the crossing p (side sigma = +-1) of the circles around a and b.
// Needs 0 < |b - a|^2 <= 4 R2 and |a + b - 2c|^2 <= 16 R2.
VRPD_FN int crossing_side(ivec2 a, ivec2 b, ivec2 c, int sigma, uint64_t r2) {
    int64_t dx = int64_t(b.x) - int64_t(a.x);
    int64_t dy = int64_t(b.y) - int64_t(a.y);
    int64_t ex = int64_t(a.x) + int64_t(b.x) - 2 * int64_t(c.x);
    int64_t ey = int64_t(a.y) + int64_t(b.y) - 2 * int64_t(c.y);
    uint64_t l = uint64_t(dx * dx + dy * dy);
    int64_t big_a = ex * ex + ey * ey - int64_t(l);
    int64_t big_b = 2 * (ey * dx - ex * dy) * int64_t(sigma);
    return sign_of_root_sum(big_a, l, big_b, uint64_t(4) * r2 - l);
}

VRPD_FN bool crossing_near(ivec2 a, ivec2 b, ivec2 c, uint64_t r2) {
    return norm2(ivec2(a.x + b.x - 2 * c.x, a.y + b.y - 2 * c.y)) <= uint64_t(16) * r2;
}

// A side of the box, as an offset from the dart: FAR_SIDE (no side within 2 Rc) on a torus, and
// for sides further than that. A side matters only within Rc of the dart (s^2 <= R2).
const int FAR_SIDE = 1 << 21;
VRPD_FN bool side_near(int s, uint64_t r2) { return uint64_t(int64_t(s) * int64_t(s)) <= r2; }

// The sides of the box within Rc of the origin (side_near), as bits: lo.x, hi.x, lo.y, hi.y. A
// test takes them once; on a torus, and for a dart away from a free box's sides, there are none.
const uint SIDE_LO_X = 1u;
const uint SIDE_HI_X = 2u;
const uint SIDE_LO_Y = 4u;
const uint SIDE_HI_Y = 8u;
VRPD_FN uint near_sides(ivec2 lo, ivec2 hi, uint64_t r2) {
    return (side_near(lo.x, r2) ? SIDE_LO_X : 0u) | (side_near(hi.x, r2) ? SIDE_HI_X : 0u) |
           (side_near(lo.y, r2) ? SIDE_LO_Y : 0u) | (side_near(hi.y, r2) ? SIDE_HI_Y : 0u);
}

// Is the crossing (sigma) of the circles around a and b inside the box (lo.x, lo.y) - (hi.x, hi.y)?
// 2 sqrt(L) (p.x - x0) = (a.x + b.x - 2 x0) sqrt(L) - sigma dy sqrt(M), and alike for the others.
// Only the `sides` near the dart (near_sides) are tested: the crossings tested lie within Rc of it.
VRPD_FN bool crossing_in_box(ivec2 a, ivec2 b, int sigma, ivec2 lo, ivec2 hi, uint64_t r2, uint sides) {
    if (sides == 0u) return true;
    int64_t dx = int64_t(b.x) - int64_t(a.x);
    int64_t dy = int64_t(b.y) - int64_t(a.y);
    uint64_t l = uint64_t(dx * dx + dy * dy);
    uint64_t m = uint64_t(4) * r2 - l;
    int64_t sx = int64_t(a.x) + int64_t(b.x);
    int64_t sy = int64_t(a.y) + int64_t(b.y);
    int64_t sg = int64_t(sigma);
    if ((sides & SIDE_LO_X) != 0u && sign_of_root_sum(sx - 2 * int64_t(lo.x), l, -sg * dy, m) < 0) return false;
    if ((sides & SIDE_HI_X) != 0u && sign_of_root_sum(2 * int64_t(hi.x) - sx, l, sg * dy, m) < 0) return false;
    if ((sides & SIDE_LO_Y) != 0u && sign_of_root_sum(sy - 2 * int64_t(lo.y), l, sg * dx, m) < 0) return false;
    if ((sides & SIDE_HI_Y) != 0u && sign_of_root_sum(2 * int64_t(hi.y) - sy, l, -sg * dx, m) < 0) return false;
    return true;
}

VRPD_FN ivec2 swizzle(ivec2 p, bool swap) { return swap ? ivec2(p.y, p.x) : p; }

// The sign of |q|^2 - R2 for q = (ku, kv + t sqrt(N)): a side crossing p = (s, c.v + t sqrt(N))
// (below) against the circle of a centre o, with ku = s - o.u and kv = c.v - o.v.
VRPD_FN int side_crossing_sign(int64_t ku, int64_t kv, uint64_t nn, uint64_t r2, int64_t t) {
    return sign_of_root_sum(ku * ku + kv * kv + int64_t(nn) - int64_t(r2), uint64_t(1), 2 * t * kv, nn);
}

// The crossing (tau = +-1) of the circle around c with the side u = s of the box, in coordinates
// (u, v) where u is across the side (swap: u is y); the side runs over v in [v0, v1]. Is the
// crossing p = (s, c.v + tau sqrt(N)), N = R2 - (s - c.u)^2, on the side, in the dart's closed
// disk (if in_disk), and outside every open disk but c's (skip)? Each test is a sign of a + b sqrt(N).
#ifndef __cplusplus
bool side_crossing_uncovered(ivec2 centre, uint skip, int s, int v0, int v1, bool swap, int tau, uint n, uint64_t r2,
                             bool in_disk) {
    ivec2 c = swizzle(centre, swap);
    int64_t du = int64_t(s) - int64_t(c.x);
    if (uint64_t(du * du) > r2) return false;
    uint64_t nn = r2 - uint64_t(du * du);
    int64_t t = int64_t(tau);
    int64_t cv = int64_t(c.y);
    if (sign_of_root_sum(cv - int64_t(v0), uint64_t(1), t, nn) < 0) return false;
    if (sign_of_root_sum(int64_t(v1) - cv, uint64_t(1), -t, nn) < 0) return false;
    int64_t s64 = int64_t(s);
    if (in_disk && side_crossing_sign(s64, cv, nn, r2, t) > 0) return false;
    for (uint k = 0u; k < n && t_step(); k++) {
        if (k == skip) continue;
        ivec2 o = swizzle(disk_at[k], swap);
        int64_t ku = s64 - int64_t(o.x);
        if (uint64_t(ku * ku) >= r2) continue;
        int64_t kv = cv - int64_t(o.y);
        if (side_crossing_sign(ku, kv, nn, r2, t) < 0) return false;
    }
    return t_steps <= T_TEST_BUDGET;
}
#else
// The host's body estimates the crossing's v = c.v + tau sqrt(N) in doubles and takes the exact
// sign (the kernel's) only where an estimate lies within 1 of 0: the same answers and counted
// steps. N < 2^39 is exact as a double and its correctly rounded root is within 2^-33 of sqrt(N);
// the offsets here stay below 2^22, so v (and v less an offset) is within 2^-30, its square within
// 2^-6, and each squared distance less R2 (sums below 2^46, each rounding within 2^-7) within 0.05.
// Always inlined into the box's boundary loop: as a call it costs two radii 2 % more instructions.
[[gnu::always_inline]] inline bool side_crossing_uncovered(ivec2 centre, uint skip, int s, int v0, int v1, bool swap,
                                                           int tau, uint n, uint64_t r2, bool in_disk) {
    ivec2 c = swizzle(centre, swap);
    int64_t du = int64_t(s) - int64_t(c.x);
    if (uint64_t(du * du) > r2) return false;
    uint64_t nn = r2 - uint64_t(du * du);
    int64_t t = int64_t(tau);
    int64_t cv = int64_t(c.y);
    const double root = double(tau) * std::sqrt(double(nn));
    auto sign = [](double estimate, auto exact) { return estimate > 1.0 ? 1 : (estimate < -1.0 ? -1 : exact()); };
    if (sign(double(cv - v0) + root, [&] { return sign_of_root_sum(cv - int64_t(v0), uint64_t(1), t, nn); }) < 0)
        return false;
    if (sign(double(v1 - cv) - root, [&] { return sign_of_root_sum(int64_t(v1) - cv, uint64_t(1), -t, nn); }) < 0)
        return false;
    int64_t s64 = int64_t(s);
    const double r2d = double(r2);
    if (in_disk) {
        const double v = double(cv) + root;
        if (sign(double(s64 * s64) + v * v - r2d, [&] { return side_crossing_sign(s64, cv, nn, r2, t); }) > 0)
            return false;
    }
    for (uint k = 0u; k < n && t_step(); k++) {
        if (k == skip) continue;
        ivec2 o = swizzle(disk_at[k], swap);
        int64_t ku = s64 - int64_t(o.x);
        if (uint64_t(ku * ku) >= r2) continue;
        int64_t kv = cv - int64_t(o.y);
        const double w = double(kv) + root;
        if (sign(double(ku * ku) + w * w - r2d, [&] { return side_crossing_sign(ku, kv, nn, r2, t); }) < 0)
            return false;
    }
    return t_steps <= T_TEST_BUDGET;
}
#endif

// Is the box corner (x, y) in the dart's closed disk (if in_disk) and outside every open disk?
VRPD_FN bool corner_uncovered(int x, int y, uint n, uint64_t r2, bool in_disk) {
    ivec2 p = ivec2(x, y);
    if (in_disk && (!side_near(x, r2) || !side_near(y, r2) || norm2(p) > r2)) return false;
    for (uint k = 0u; k < n && t_step(); k++)
        if (norm2(ivec2(p.x - disk_at[k].x, p.y - disk_at[k].y)) < r2) return false;
    return t_steps <= T_TEST_BUDGET;
}

// The crossings of the circles (the dart's if in_disk, then disk_at[0, n)'s) with the sides of the
// box, and its corners: is one of them in the dart's closed disk (if in_disk) and uncovered?
VRPD_FN bool boundary_vertex_uncovered(uint n, uint64_t r2, ivec2 lo, ivec2 hi, bool in_disk) {
    for (uint side = 0u; side < 4u; side++) {
        bool swap = side >= 2u;
        int s = (side & 1u) == 0u ? (swap ? lo.y : lo.x) : (swap ? hi.y : hi.x);
        if (!side_near(s, r2)) continue;
        int v0 = swap ? lo.x : lo.y;
        int v1 = swap ? hi.x : hi.y;
        for (int tau = -1; tau <= 1; tau += 2) {
            if (in_disk && side_crossing_uncovered(ivec2(0, 0), 0xFFFFFFFFu, s, v0, v1, swap, tau, n, r2, true))
                return true;
            for (uint i = 0u; i < n && t_step(); i++)
                if (side_crossing_uncovered(disk_at[i], i, s, v0, v1, swap, tau, n, r2, in_disk)) return true;
        }
    }
    return corner_uncovered(lo.x, lo.y, n, r2, in_disk) || corner_uncovered(hi.x, lo.y, n, r2, in_disk) ||
           corner_uncovered(lo.x, hi.y, n, r2, in_disk) || corner_uncovered(hi.x, hi.y, n, r2, in_disk);
}

// Is the crossing (sigma) of the circles around a and b outside every open disk of disk_at[0, n)
// other than skip_a and skip_b?
#ifndef __cplusplus
bool crossing_uncovered(ivec2 a, ivec2 b, int sigma, uint skip_a, uint skip_b, uint n, uint64_t r2) {
    for (uint k = 0u; k < n && t_step(); k++) {
        if (k == skip_a || k == skip_b) continue;
        ivec2 c = disk_at[k];
        if (crossing_near(a, b, c, r2) && crossing_side(a, b, c, sigma, r2) < 0) return false;
    }
    return t_steps <= T_TEST_BUDGET;  // a search cut short proves nothing
}

// Is a crossing of the circles around a and b (disk_at[i] and disk_at[j]) in the region and
// outside every other open disk? sigma = -1 first, then +1.
bool pair_crossing_uncovered(ivec2 a, ivec2 b, uint i, uint j, uint n, uint64_t r2, ivec2 lo, ivec2 hi, bool in_disk,
                             uint sides) {
    for (int sigma = -1; sigma <= 1; sigma += 2)
        if ((!in_disk || crossing_side(a, b, ivec2(0, 0), sigma, r2) <= 0) &&
            crossing_in_box(a, b, sigma, lo, hi, r2, sides) && crossing_uncovered(a, b, sigma, i, j, n, r2))
            return true;
    return false;
}
#else
// The exact tests the estimates fall back on, out of line: inlined, the compiler computes their
// operands for every pair ahead of the rare call, holding them on the stack.
VRPD_COLD_FN int exact_crossing_side(ivec2 a, ivec2 b, ivec2 c, int sigma, uint64_t r2) {
    return crossing_side(a, b, c, sigma, r2);
}
VRPD_COLD_FN bool exact_crossing_covered(ivec2 a, ivec2 b, ivec2 c, int sigma, uint64_t r2) {
    return crossing_near(a, b, c, r2) && crossing_side(a, b, c, sigma, r2) < 0;
}
VRPD_COLD_FN bool exact_crossing_in_box(ivec2 a, ivec2 b, int sigma, ivec2 lo, ivec2 hi, uint64_t r2, uint sides) {
    return crossing_in_box(a, b, sigma, lo, hi, r2, sides);
}
// The host's body reads each sign from a double-precision estimate first, and takes the exact
// test (the kernel's) only where the estimate is within 1 of 0: the answers, and the steps
// counted, are the kernel's. The estimate: with P = a + b + sigma sqrt(M / L) n (twice the
// crossing), D = |P - 2c|^2 - 4 R2 = 4 (|p - c|^2 - R2). R2 <= 2^38 and the centres lie within
// 2 Rc <= 2^20 of the origin, so |P| < 2^22 and |P - 2c| < 2^23; M and L are exact, and
// sqrt(M / L) times an integer carries a relative error below 4 * 2^-53, so each coordinate of
// P - 2c is within 2^-28 of the truth (each rounding of a sum adds at most 2^-30), its square
// within 2 * 2^23 * 2^-28 + 2^-7 < 0.07, and D within 0.2. The dart's own circle (the pair
// loop's in_disk test) is the one around the origin, c = 0: the same bound holds.
struct Doubled {  // a point times two, in doubles: P, or 2c
    double x = 0.0, y = 0.0;
};
// 2 disk_at[k] for the estimates: reaches_uncovered sets them (estimate_disks) before its
// searches, which read them.
VRPD_PRIVATE Doubled disk_twice[MAX_DISKS];
inline void estimate_disks(uint n) {
    for (uint k = 0u; k < n; k++) disk_twice[k] = {2.0 * double(disk_at[k].x), 2.0 * double(disk_at[k].y)};
}
// The circles around a and b: b - a, a + b and sqrt(M / L), as doubles, taken once for both
// crossings.
struct CirclePair {
    double dx, dy, sx, sy, scale;
};
inline CirclePair circle_pair(ivec2 a, ivec2 b, uint64_t r2) {
    const double dx = double(b.x) - double(a.x);
    const double dy = double(b.y) - double(a.y);
    const double l = dx * dx + dy * dy;
    return {dx, dy, double(a.x) + double(b.x), double(a.y) + double(b.y), std::sqrt((4.0 * double(r2) - l) / l)};
}
// P for crossing sigma of the pair.
inline Doubled twice_crossing(const CirclePair& c, int sigma) {
    const double s = double(sigma) * c.scale;
    return {c.sx - s * c.dy, c.sy + s * c.dx};
}
// crossing_uncovered, the crossing's P given.
inline bool estimated_crossing_uncovered(Doubled p, ivec2 a, ivec2 b, int sigma, uint skip_a, uint skip_b, uint n,
                                         uint64_t r2) {
    const double r4 = 4.0 * double(r2);
    for (uint k = 0u; k < n && t_step(); k++) {
        if (k == skip_a || k == skip_b) continue;
        const double ex = p.x - disk_twice[k].x;
        const double ey = p.y - disk_twice[k].y;
        const double d = ex * ex + ey * ey - r4;
        if (d > 1.0) continue;
        if (d < -1.0) return false;
        if (exact_crossing_covered(a, b, disk_at[k], sigma, r2)) return false;
    }
    return t_steps <= T_TEST_BUDGET;  // a search cut short proves nothing
}
inline bool crossing_uncovered(ivec2 a, ivec2 b, int sigma, uint skip_a, uint skip_b, uint n, uint64_t r2) {
    return estimated_crossing_uncovered(twice_crossing(circle_pair(a, b, r2), sigma), a, b, sigma, skip_a, skip_b, n,
                                        r2);
}
// crossing_in_box, the crossing's P given: 2 sqrt(L) (p.x - x0) has the sign of P.x - 2 x0, which
// the estimate holds within 2^-28 (the sides tested lie within Rc of the origin), so the exact
// test runs only where P.x - 2 x0 is within 1 of 0 (and alike for the other sides).
inline bool estimated_crossing_in_box(Doubled p, ivec2 a, ivec2 b, int sigma, ivec2 lo, ivec2 hi, uint64_t r2,
                                      uint sides) {
    if (sides == 0u) return true;
    const double off[4] = {p.x - 2.0 * double(lo.x), 2.0 * double(hi.x) - p.x, p.y - 2.0 * double(lo.y),
                           2.0 * double(hi.y) - p.y};
    bool unsure = false;
    for (uint k = 0u; k < 4u; k++) {
        if ((sides & (1u << k)) == 0u) continue;
        if (off[k] < -1.0) return false;
        unsure = unsure || off[k] <= 1.0;
    }
    return !unsure || exact_crossing_in_box(a, b, sigma, lo, hi, r2, sides);
}
// One square root for the pair's two crossings, and the dart's circle estimated too.
[[gnu::always_inline]] inline bool pair_crossing_uncovered(ivec2 a, ivec2 b, uint i, uint j, uint n, uint64_t r2,
                                                           ivec2 lo, ivec2 hi, bool in_disk, uint sides) {
    const CirclePair pair = circle_pair(a, b, r2);
    for (int sigma = -1; sigma <= 1; sigma += 2) {
        const Doubled p = twice_crossing(pair, sigma);
        if (in_disk) {
            const double d = p.x * p.x + p.y * p.y - 4.0 * double(r2);
            if (d > 1.0 || (d >= -1.0 && exact_crossing_side(a, b, ivec2(0, 0), sigma, r2) > 0)) continue;
        }
        if (estimated_crossing_in_box(p, a, b, sigma, lo, hi, r2, sides) &&
            estimated_crossing_uncovered(p, a, b, sigma, i, j, n, r2))
            return true;
    }
    return false;
}
#endif

// Sorts disk_at[0, n), nearest the origin first: those are the likeliest to cover a vertex near
// it, and a vertex's search stops at the first disk that covers it. Returns whether one of them
// covers the origin (its open disk holds it).
VRPD_FN bool sort_disks(uint n, uint64_t r2) {
    for (uint i = 1u; i < n; i++) {
        ivec2 v = disk_at[i];
        uint64_t key = norm2(v);
        uint j = i;
        for (; j > 0u && norm2(disk_at[j - 1u]) > key; j--) disk_at[j] = disk_at[j - 1u];
        disk_at[j] = v;
    }
    return n > 0u && norm2(disk_at[0]) < r2;
}

// Does the region reach a point outside every open disk around disk_at[0, n)? The region is the
// box lo - hi (offsets from the origin; FAR_SIDE for none), cut, if in_disk, to the closed disk of
// squared radius r2 around the origin: a dart's reach into U (in_disk), or whether a quadtree
// cell still holds a point of U (the cell as the box, its corner the origin; every side of it and
// every disk centre within 2 Rc of that corner). See the method above. T_INSIDE, T_OUTSIDE, or
// T_UNKNOWN past the step budget. A witness found before the budget runs out is a witness: only
// "no witness" needs the whole search. The kernel's test, step by step in a fixed order.
VRPD_FN uint reaches_uncovered_counted(uint n, uint64_t r2, ivec2 lo, ivec2 hi, bool in_disk) {
    t_steps = 0u;
    bool centre_covered = sort_disks(n, r2);
#ifdef __cplusplus
    estimate_disks(n);
#endif
    if (in_disk && !centre_covered) return T_INSIDE;
    uint sides = near_sides(lo, hi, r2);
    // The dart's circle's crossings with each other circle (both lie on the dart's circle).
    for (uint i = 0u; i < n && in_disk && t_step(); i++) {
        if (norm2(disk_at[i]) == uint64_t(0)) continue;
        if (pair_crossing_uncovered(ivec2(0, 0), disk_at[i], i, i, n, r2, lo, hi, false, sides)) return T_INSIDE;
    }
    for (uint i = 0u; i < n && t_step(); i++) {
        for (uint j = i + 1u; j < n && t_step(); j++) {
            ivec2 a = disk_at[i];
            ivec2 b = disk_at[j];
            uint64_t l = norm2(ivec2(b.x - a.x, b.y - a.y));
            if (l == uint64_t(0) || l > uint64_t(4) * r2) continue;
            if (pair_crossing_uncovered(a, b, i, j, n, r2, lo, hi, in_disk, sides)) return T_INSIDE;
        }
    }
    if (boundary_vertex_uncovered(n, r2, lo, hi, in_disk)) return T_INSIDE;
    return t_steps > T_TEST_BUDGET ? T_UNKNOWN : T_OUTSIDE;
}

#ifndef __cplusplus
uint reaches_uncovered(uint n, uint64_t r2, ivec2 lo, ivec2 hi, bool in_disk) {
    return reaches_uncovered_counted(n, r2, lo, hi, in_disk);
}
#endif

VRPD_END
#ifdef __cplusplus
#include "t_membership_lanes.h"
#endif
#endif
