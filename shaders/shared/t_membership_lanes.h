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
// exactly. The box's side crossings and corners are the kernel's (boundary_vertex_uncovered).
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

// Lanes [0, count) of four, as bits.
inline uint first_lanes(uint count) { return count >= 4u ? 15u : (1u << count) - 1u; }

// Is the crossing P (doubled) of the circles around a and b (sigma) outside every open disk of
// disk_at[0, n) but skip_a and skip_b? estimated_crossing_uncovered's judgement, four disks a step.
[[gnu::target("avx2")]] inline bool lanes_crossing_uncovered(const DiskLanes& d, uint n, double px, double py, ivec2 a,
                                                             ivec2 b, int sigma, uint skip_a, uint skip_b,
                                                             uint64_t r2) {
    const __m256d x = _mm256_set1_pd(px), y = _mm256_set1_pd(py), r4 = _mm256_set1_pd(4.0 * double(r2));
    const __m256d one = _mm256_set1_pd(1.0), minus_one = _mm256_set1_pd(-1.0);
    const uint judged = ~((1u << skip_a) | (1u << skip_b));
    uint unsure = 0u;
    for (uint k = 0u; k < n; k += 4u) {
        const __m256d ex = _mm256_sub_pd(x, _mm256_load_pd(d.x2 + k));
        const __m256d ey = _mm256_sub_pd(y, _mm256_load_pd(d.y2 + k));
        const __m256d e = _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(ex, ex), _mm256_mul_pd(ey, ey)), r4);
        const uint lanes = (first_lanes(n - k) << k) & judged;
        if (((uint(_mm256_movemask_pd(_mm256_cmp_pd(e, minus_one, _CMP_LT_OQ))) << k) & lanes) != 0u) return false;
        unsure |= (uint(_mm256_movemask_pd(_mm256_cmp_pd(e, one, _CMP_LE_OQ))) << k) & lanes;
    }
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
                           first_lanes(n - j);
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

// reaches_uncovered_counted's answer for n <= T_LANES_DISKS disks, each within 2 Rc of the origin.
[[gnu::target("avx2")]] inline uint reaches_uncovered_lanes(uint n, uint64_t r2, ivec2 lo, ivec2 hi, bool in_disk) {
    t_steps = 0u;  // boundary_vertex_uncovered counts, within the budget here
    const bool centre_covered = sort_disks(n, r2);
    if (in_disk && !centre_covered) return T_INSIDE;
    DiskLanes d;
    for (uint k = 0u; k < DiskLanes::kLanes; k++) {
        const bool real = k < n;
        d.x[k] = real ? double(disk_at[k].x) : 1e20;
        d.y[k] = real ? double(disk_at[k].y) : 1e20;
        d.x2[k] = 2.0 * d.x[k];
        d.y2[k] = 2.0 * d.y[k];
    }
    const uint sides = near_sides(lo, hi, r2);
    // The dart's circle's crossings with each other circle (all lie on the dart's circle).
    if (in_disk && lanes_pairs_uncovered(d, n, ivec2(0, 0), n, 0u, r2, lo, hi, false, sides)) return T_INSIDE;
    for (uint i = 0u; i + 1u < n; i++)
        if (lanes_pairs_uncovered(d, n, disk_at[i], i, i + 1u, r2, lo, hi, in_disk, sides)) return T_INSIDE;
    return boundary_vertex_uncovered(n, r2, lo, hi, in_disk) ? T_INSIDE : T_OUTSIDE;
}
#endif

// The T test (reaches_uncovered_counted's answer): four circles at a time where the processor and
// the test allow, else the kernel's body.
inline uint reaches_uncovered(uint n, uint64_t r2, ivec2 lo, ivec2 hi, bool in_disk) {
#ifdef VRPD_HOST_AVX2
    if (n <= T_LANES_DISKS && host_has_avx2()) {
        bool near = true;
        for (uint k = 0u; k < n; k++) near = near && norm2(disk_at[k]) <= uint64_t(4) * r2;
        if (near) return reaches_uncovered_lanes(n, r2, lo, hi, in_disk);
    }
#endif
    return reaches_uncovered_counted(n, r2, lo, hi, in_disk);
}

}  // namespace vrpd::shared
#endif
