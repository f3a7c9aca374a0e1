// The host's T test (t_membership.h) four circles at a time, on processors with AVX2.
//
// Its answer is the kernel's. The kernel's test counts its steps against T_TEST_BUDGET, but over n
// disks it takes at most n^3 + 9 n^2 + n (n - 1) / 2 + 22 n of them (the pairs' crossings against
// every disk, the box's sides and corners), 8 024 for n = T_LANES_DISKS = 17: up to there the
// budget never runs out, the answer is the geometry's alone, and any order of the same exact
// judgements gives it. Each crossing's doubled point P comes from the same double operations as
// the host's estimates (circle_pair, twice_crossing: the same values in every lane), and each sign
// from the same estimate, exact beyond 1 and taken from the kernel's exact test within it.
//
// The pairs of circles go four at a time: the dart's own circle with four disks' circles, then
// disk i's with disks j..j+3 for j > i. Their crossings in the region (the dart's closed disk,
// and the box's near sides) are judged against four disks at a time, nearest first: covered
// where an estimate is below -1, uncovered if none is below -1 and none within 1 of 0 is covered
// exactly. The disks' circles' crossings with the box's near sides go four circles at a time too
// (lanes_boundary_uncovered); the dart's own circle's and the corners are the kernel's.
#ifndef VRPD_T_MEMBERSHIP_LANES_H
#define VRPD_T_MEMBERSHIP_LANES_H

namespace vrpd::shared {

const uint T_LANES_DISKS = 17u;

#ifdef VRPD_HOST_AVX2
// disk_at[0, n) in doubles, four lanes at a time: the centres and twice the centres, padded to a
// whole vector with points so far that no circle around them meets another or covers anything.
struct alignas(32) DiskLanes {
    static constexpr uint kLanes = 20u;  // T_LANES_DISKS rounded up to whole vectors
    double x[kLanes], y[kLanes], x2[kLanes], y2[kLanes];
};

// disk_at[0, n) as lanes, padded up to the last vector a scan reads: a pair's load may start at
// any disk before n, so it reads up to lane n + 2. The lanes past that are never read.
inline DiskLanes disk_lanes(uint n) {
    DiskLanes d;
    const uint filled = std::min(DiskLanes::kLanes, (n + 6u) & ~3u);
    for (uint k = 0u; k < filled; k++) {
        const bool real = k < n;
        d.x[k] = real ? double(disk_at[k].x) : 1e20;
        d.y[k] = real ? double(disk_at[k].y) : 1e20;
        d.x2[k] = 2.0 * d.x[k];
        d.y2[k] = 2.0 * d.y[k];
    }
    return d;
}

// The disks [0, n) as bits (n <= T_LANES_DISKS), and the lanes of those among k..k+3, bit 0 for
// disk k.
inline uint disk_bits(uint n) { return (1u << n) - 1u; }
inline uint lanes_from(uint bits, uint k) { return (bits >> k) & 15u; }

// The cover searches' step, four disks a step: estimate(k, lanes) gives the estimated signs of the
// disks k..k+3 (of |p - c|^2 - R2, or four times it), and may clear bits of `lanes` (disk k at bit
// k: those that may cover p). False once a lane's estimate is below -1: a disk covers p. Else
// `unsure` holds the lanes within 1 of 0, for the exact test.
template <class Estimate>
[[gnu::always_inline, gnu::target("avx2")]] inline bool lanes_none_below(uint n, uint judged, Estimate estimate,
                                                                         uint& unsure) {
    const __m256d one = _mm256_set1_pd(1.0), minus_one = _mm256_set1_pd(-1.0);
    unsure = 0u;
    judged &= disk_bits(n);
    for (uint k = 0u; k < n; k += 4u) {
        uint lanes = (15u << k) & judged;
        const __m256d e = estimate(k, lanes);
        if (((uint(_mm256_movemask_pd(_mm256_cmp_pd(e, minus_one, _CMP_LT_OQ))) << k) & lanes) != 0u) return false;
        unsure |= (uint(_mm256_movemask_pd(_mm256_cmp_pd(e, one, _CMP_LE_OQ))) << k) & lanes;
    }
    return true;
}

// Is the crossing P (doubled) of the circles around a and b (sigma) outside every open disk of
// disk_at[0, n) but skip_a and skip_b? estimated_crossing_uncovered's judgement, four disks a step.
[[gnu::target("avx2")]] inline bool lanes_crossing_uncovered(const DiskLanes& d, uint n, double px, double py, ivec2 a,
                                                             ivec2 b, int sigma, uint skip_a, uint skip_b,
                                                             uint64_t r2) {
    const __m256d x = _mm256_set1_pd(px), y = _mm256_set1_pd(py), r4 = _mm256_set1_pd(4.0 * double(r2));
    auto estimate = [&](uint k, uint&) __attribute__((always_inline, target("avx2"))) {
        const __m256d ex = _mm256_sub_pd(x, _mm256_load_pd(d.x2 + k));
        const __m256d ey = _mm256_sub_pd(y, _mm256_load_pd(d.y2 + k));
        return _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(ex, ex), _mm256_mul_pd(ey, ey)), r4);
    };
    uint unsure;
    if (!lanes_none_below(n, ~((1u << skip_a) | (1u << skip_b)), estimate, unsure)) return false;
    for (; unsure != 0u; unsure &= unsure - 1u)
        if (exact_crossing_covered(a, b, disk_at[std::countr_zero(unsure)], sigma, r2)) return false;
    return true;
}

// Is a crossing of the circle around a (at ax, ay; the dart's own circle if a is the origin and
// skip_a is n) with a circle around disk_at[j, n) in the region and uncovered? Those circles at
// most 2 Rc from a and not on it; the crossings in the dart's disk if in_disk, and in the box if
// `sides` (near_sides) holds sides of it.
[[gnu::target("avx2")]] inline bool lanes_pairs_uncovered(const DiskLanes& d, uint n, ivec2 a, uint skip_a, uint j,
                                                          uint64_t r2, ivec2 lo, ivec2 hi, bool in_disk, uint sides) {
    const uint real = disk_bits(n);
    const __m256d ax = _mm256_set1_pd(double(a.x)), ay = _mm256_set1_pd(double(a.y));
    const __m256d r4 = _mm256_set1_pd(4.0 * double(r2)), zero = _mm256_setzero_pd();
    const __m256d one = _mm256_set1_pd(1.0), minus_one = _mm256_set1_pd(-1.0);
    // The box's near sides, twice over (P is the doubled point): P.x - 2 lo.x and so on >= 0.
    const __m256d side2[4] = {_mm256_set1_pd(2.0 * double(lo.x)), _mm256_set1_pd(2.0 * double(hi.x)),
                              _mm256_set1_pd(2.0 * double(lo.y)), _mm256_set1_pd(2.0 * double(hi.y))};
    for (; j < n; j += 4u) {
        const __m256d bx = _mm256_loadu_pd(d.x + j), by = _mm256_loadu_pd(d.y + j);
        const __m256d dx = _mm256_sub_pd(bx, ax), dy = _mm256_sub_pd(by, ay);
        const __m256d l = _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy));
        const uint valid = uint(_mm256_movemask_pd(
                               _mm256_and_pd(_mm256_cmp_pd(l, zero, _CMP_GT_OQ), _mm256_cmp_pd(l, r4, _CMP_LE_OQ)))) &
                           lanes_from(real, j);
        if (valid == 0u) continue;
        // circle_pair's sqrt(M / L), and twice_crossing's P = a + b + sigma sqrt(M / L) perp(b - a).
        const __m256d scale = _mm256_sqrt_pd(_mm256_div_pd(_mm256_sub_pd(r4, l), l));
        const __m256d sx = _mm256_add_pd(ax, bx), sy = _mm256_add_pd(ay, by);
        const __m256d t_dy = _mm256_mul_pd(scale, dy), t_dx = _mm256_mul_pd(scale, dx);
        for (int sigma = -1; sigma <= 1; sigma += 2) {
            const __m256d px = sigma < 0 ? _mm256_add_pd(sx, t_dy) : _mm256_sub_pd(sx, t_dy);
            const __m256d py = sigma < 0 ? _mm256_sub_pd(sy, t_dx) : _mm256_add_pd(sy, t_dx);
            uint in = valid, disk_unsure = 0u, box_unsure = 0u;
            if (in_disk) {
                const __m256d e = _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(px, px), _mm256_mul_pd(py, py)), r4);
                in &= uint(_mm256_movemask_pd(_mm256_cmp_pd(e, one, _CMP_LE_OQ)));
                disk_unsure = uint(_mm256_movemask_pd(_mm256_cmp_pd(e, minus_one, _CMP_GE_OQ)));
            }
            for (uint k = 0u; k < 4u; k++) {
                if ((sides & (1u << k)) == 0u) continue;
                const __m256d p = k < 2u ? px : py;
                const __m256d off = (k & 1u) == 0u ? _mm256_sub_pd(p, side2[k]) : _mm256_sub_pd(side2[k], p);
                in &= uint(_mm256_movemask_pd(_mm256_cmp_pd(off, minus_one, _CMP_GE_OQ)));
                box_unsure |= uint(_mm256_movemask_pd(_mm256_cmp_pd(off, one, _CMP_LE_OQ)));
            }
            if (in == 0u) continue;
            alignas(32) double p_x[4], p_y[4];
            _mm256_store_pd(p_x, px);
            _mm256_store_pd(p_y, py);
            for (; in != 0u; in &= in - 1u) {
                const uint t = uint(std::countr_zero(in));
                const ivec2 b = disk_at[j + t];
                if ((disk_unsure & (1u << t)) != 0u && exact_crossing_side(a, b, ivec2(0, 0), sigma, r2) > 0) continue;
                if ((box_unsure & (1u << t)) != 0u && !exact_crossing_in_box(a, b, sigma, lo, hi, r2, sides)) continue;
                if (lanes_crossing_uncovered(d, n, p_x[t], p_y[t], a, b, sigma, skip_a == n ? j + t : skip_a, j + t,
                                             r2))
                    return true;
            }
        }
    }
    return false;
}

// Is the crossing (s, v) of the circle around (cu, cv) with the line u = s (v = cv + root, root =
// tau sqrt(nn)) outside every open disk of disk_at[0, n) but `skip`? side_crossing_uncovered's
// cover search (u, v: the disks' coordinates across and along the side, the lanes of `du`,
// `dv`), four disks a step.
[[gnu::target("avx2")]] inline bool lanes_side_crossing_uncovered(const double* du, const double* dv, uint n, int s,
                                                                  int64_t cv, double root, int tau, uint64_t nn,
                                                                  uint skip, uint64_t r2, bool swap) {
    const __m256d side = _mm256_set1_pd(double(s)), along = _mm256_set1_pd(double(cv));
    const __m256d offset = _mm256_set1_pd(root), r2d = _mm256_set1_pd(double(r2));
    auto estimate = [&](uint k, uint & lanes) __attribute__((always_inline, target("avx2"))) {
        const __m256d ku = _mm256_sub_pd(side, _mm256_load_pd(du + k));
        const __m256d w = _mm256_add_pd(_mm256_sub_pd(along, _mm256_load_pd(dv + k)), offset);
        const __m256d ku2 = _mm256_mul_pd(ku, ku);
        // A disk no nearer the side than Rc covers no point of it (ku^2 >= R2).
        lanes &= uint(_mm256_movemask_pd(_mm256_cmp_pd(ku2, r2d, _CMP_LT_OQ))) << k;
        return _mm256_sub_pd(_mm256_add_pd(ku2, _mm256_mul_pd(w, w)), r2d);
    };
    uint unsure;
    if (!lanes_none_below(n, ~(skip < 32u ? 1u << skip : 0u), estimate, unsure)) return false;
    for (; unsure != 0u; unsure &= unsure - 1u) {
        const ivec2 o = swizzle(disk_at[std::countr_zero(unsure)], swap);
        if (side_crossing_sign(int64_t(s) - int64_t(o.x), cv - int64_t(o.y), nn, r2, int64_t(tau)) < 0) return false;
    }
    return true;
}

// boundary_vertex_uncovered's answer, the disks' circles' crossings with each side four circles a
// step: each crossing on the side (and in the dart's disk if in_disk) by the estimates of
// side_crossing_uncovered (the same doubles), exact within 1 of 0, then judged by
// lanes_side_crossing_uncovered. The dart's own circle's crossings and the corners are the
// kernel's.
[[gnu::target("avx2")]] inline bool lanes_boundary_uncovered(const DiskLanes& d, uint n, uint64_t r2, ivec2 lo,
                                                             ivec2 hi, bool in_disk) {
    const uint real = disk_bits(n);
    const __m256d r2d = _mm256_set1_pd(double(r2)), zero = _mm256_setzero_pd();
    const __m256d one = _mm256_set1_pd(1.0), minus_one = _mm256_set1_pd(-1.0);
    for (uint side = 0u; side < 4u; side++) {
        const bool swap = side >= 2u;
        const int s = (side & 1u) == 0u ? (swap ? lo.y : lo.x) : (swap ? hi.y : hi.x);
        if (!side_near(s, r2)) continue;
        const int v0 = swap ? lo.x : lo.y, v1 = swap ? hi.x : hi.y;
        const double* du = swap ? d.y : d.x;  // across the side
        const double* dv = swap ? d.x : d.y;  // along it
        const __m256d su = _mm256_set1_pd(double(s)), s2 = _mm256_set1_pd(double(int64_t(s) * int64_t(s)));
        const __m256d first = _mm256_set1_pd(double(v0)), last = _mm256_set1_pd(double(v1));
        for (int tau = -1; tau <= 1; tau += 2) {
            if (in_disk && side_crossing_uncovered(ivec2(0, 0), 0xFFFFFFFFu, s, v0, v1, swap, tau, n, r2, true))
                return true;
            const __m256d sign = _mm256_set1_pd(double(tau));
            for (uint i = 0u; i < n; i += 4u) {
                const __m256d cu = _mm256_load_pd(du + i), cv = _mm256_load_pd(dv + i);
                const __m256d gap = _mm256_sub_pd(su, cu);
                const __m256d gap2 = _mm256_mul_pd(gap, gap);
                uint in = uint(_mm256_movemask_pd(_mm256_cmp_pd(gap2, r2d, _CMP_LE_OQ))) & lanes_from(real, i);
                if (in == 0u) continue;
                // N = R2 - (s - c.u)^2 >= 0 in the lanes kept; root = tau sqrt(N).
                const __m256d nn = _mm256_max_pd(_mm256_sub_pd(r2d, gap2), zero);
                const __m256d root = _mm256_mul_pd(sign, _mm256_sqrt_pd(nn));
                const __m256d from_first = _mm256_add_pd(_mm256_sub_pd(cv, first), root);
                const __m256d to_last = _mm256_sub_pd(_mm256_sub_pd(last, cv), root);
                in &= uint(_mm256_movemask_pd(_mm256_cmp_pd(from_first, minus_one, _CMP_GE_OQ))) &
                      uint(_mm256_movemask_pd(_mm256_cmp_pd(to_last, minus_one, _CMP_GE_OQ)));
                uint unsure = uint(_mm256_movemask_pd(_mm256_cmp_pd(from_first, one, _CMP_LE_OQ))) |
                              uint(_mm256_movemask_pd(_mm256_cmp_pd(to_last, one, _CMP_LE_OQ)));
                if (in_disk) {
                    const __m256d v = _mm256_add_pd(cv, root);
                    const __m256d e = _mm256_sub_pd(_mm256_add_pd(s2, _mm256_mul_pd(v, v)), r2d);
                    in &= uint(_mm256_movemask_pd(_mm256_cmp_pd(e, one, _CMP_LE_OQ)));
                    unsure |= uint(_mm256_movemask_pd(_mm256_cmp_pd(e, minus_one, _CMP_GE_OQ)));
                }
                if (in == 0u) continue;
                alignas(32) double roots[4];
                _mm256_store_pd(roots, root);
                for (; in != 0u; in &= in - 1u) {
                    const uint t = uint(std::countr_zero(in)), k = i + t;
                    const ivec2 c = swizzle(disk_at[k], swap);
                    const int64_t gap_k = int64_t(s) - int64_t(c.x);
                    const uint64_t n_k = r2 - uint64_t(gap_k * gap_k);
                    // An estimate within 1 of 0: the kernel's whole test of the crossing.
                    if ((unsure & (1u << t)) != 0u) {
                        if (side_crossing_uncovered(disk_at[k], k, s, v0, v1, swap, tau, n, r2, in_disk)) return true;
                        continue;
                    }
                    if (lanes_side_crossing_uncovered(du, dv, n, s, int64_t(c.y), roots[t], tau, n_k, k, r2, swap))
                        return true;
                }
            }
        }
    }
    return corner_uncovered(lo.x, lo.y, n, r2, in_disk) || corner_uncovered(hi.x, lo.y, n, r2, in_disk) ||
           corner_uncovered(lo.x, hi.y, n, r2, in_disk) || corner_uncovered(hi.x, hi.y, n, r2, in_disk);
}

// sort_disks for n <= T_LANES_DISKS disks whose squared distances from the origin are key[0, n):
// the same stable order, each distance computed once. Sorts key with them.
inline bool sort_keyed_disks(uint n, uint64_t* key, uint64_t r2) {
    for (uint i = 1u; i < n; i++) {
        const ivec2 v = disk_at[i];
        const uint64_t k = key[i];
        uint j = i;
        for (; j > 0u && key[j - 1u] > k; j--) {
            disk_at[j] = disk_at[j - 1u];
            key[j] = key[j - 1u];
        }
        disk_at[j] = v;
        key[j] = k;
    }
    return n > 0u && key[0] < r2;
}

// reaches_uncovered_counted's answer for n <= T_LANES_DISKS disks, each within 2 Rc of the origin,
// key[k] disk k's squared distance from it.
[[gnu::target("avx2")]] inline uint reaches_uncovered_lanes(uint n, uint64_t* key, uint64_t r2, ivec2 lo, ivec2 hi,
                                                            bool in_disk) {
    t_steps = 0u;  // boundary_vertex_uncovered counts, within the budget here
    const bool centre_covered = sort_keyed_disks(n, key, r2);
    if (in_disk && !centre_covered) return T_INSIDE;
    const DiskLanes d = disk_lanes(n);
    const uint sides = near_sides(lo, hi, r2);
    // The dart's circle's crossings with each other circle (all lie on the dart's circle).
    if (in_disk && lanes_pairs_uncovered(d, n, ivec2(0, 0), n, 0u, r2, lo, hi, false, sides)) return T_INSIDE;
    for (uint i = 0u; i + 1u < n; i++)
        if (lanes_pairs_uncovered(d, n, disk_at[i], i, i + 1u, r2, lo, hi, in_disk, sides)) return T_INSIDE;
    return lanes_boundary_uncovered(d, n, r2, lo, hi, in_disk) ? T_INSIDE : T_OUTSIDE;
}
#endif

// The T test (reaches_uncovered_counted's answer): four circles at a time where the processor and
// the test allow, else the kernel's body.
inline uint reaches_uncovered(uint n, uint64_t r2, ivec2 lo, ivec2 hi, bool in_disk) {
#ifdef VRPD_HOST_AVX2
    if (n <= T_LANES_DISKS && host_has_avx2()) {
        uint64_t key[T_LANES_DISKS];
        bool near = true;
        for (uint k = 0u; k < n; k++) {
            key[k] = norm2(disk_at[k]);
            near = near && key[k] <= uint64_t(4) * r2;
        }
        if (near) return reaches_uncovered_lanes(n, key, r2, lo, hi, in_disk);
    }
#endif
    return reaches_uncovered_counted(n, r2, lo, hi, in_disk);
}

}  // namespace vrpd::shared
#endif
