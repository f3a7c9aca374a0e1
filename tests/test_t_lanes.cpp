// The host's four-lane T test (shared/t_membership_lanes.h) against the kernel's step-counted one
// (reaches_uncovered_counted): the same answer on the configurations the sampler meets, and on
// ones built so that the answer rests on exact ties, which only the exact fallbacks decide.
#include <catch2/catch.hpp>

#include <random>

#include "shared/sampler.h"
#include "t_membership_support.h"

using namespace vrpd;
using vrpd::test::Config;
using vrpd::test::describe;

namespace {

// Both tests' answers on c (each sorts disk_at, so each gets its own copy).
std::pair<shared::uint, shared::uint> both_answers(const Config& c, std::uint64_t r2) {
    const auto n = shared::uint(c.disks.size());
    std::copy(c.disks.begin(), c.disks.end(), shared::disk_at);
    const shared::uint lanes = shared::reaches_uncovered(n, r2, c.lo, c.hi, c.in_disk);
    std::copy(c.disks.begin(), c.disks.end(), shared::disk_at);
    const shared::uint counted = shared::reaches_uncovered_counted(n, r2, c.lo, c.hi, c.in_disk);
    return {lanes, counted};
}

// The twelve lattice directions of length 5: (3, 4), (4, 3), (5, 0) and their mirror images.
std::vector<glm::ivec2> pythagorean_directions() {
    std::vector<glm::ivec2> v;
    for (const glm::ivec2 d : {glm::ivec2(3, 4), glm::ivec2(4, 3), glm::ivec2(5, 0), glm::ivec2(0, 5)})
        for (const int sx : {1, -1})
            for (const int sy : {1, -1})
                if ((d.x != 0 || sx == 1) && (d.y != 0 || sy == 1)) v.emplace_back(sx * d.x, sy * d.y);
    return v;
}

}  // namespace

TEST_CASE("T membership: the host's four-lane test answers as the kernel's counted test", "[two-radii]") {
#ifndef VRPD_HOST_AVX2
    SUCCEED("not x86-64: reaches_uncovered is the counted test itself");
#else
    if (!shared::host_has_avx2()) SUCCEED("no AVX2 here: reaches_uncovered is the counted test itself");
    if (!shared::host_has_avx2()) return;
    std::mt19937_64 rng(23);
    int inside = 0, outside = 0;
    for (const double rc : {1000.0, double((1 << 19) - 1)}) {
        const std::uint64_t r2 = std::uint64_t(rc * rc);
        for (const double ratio : {1.1, 1.5, 2.0, 4.0})
            for (const bool boxed : {false, true})
                for (const bool in_disk : {true, false})
                    for (int i = 0; i < 300; ++i) {
                        Config c = vrpd::test::random_config(rng, rc, rc / ratio, boxed, in_disk);
                        if (c.disks.size() > shared::T_LANES_DISKS) c.disks.resize(shared::T_LANES_DISKS);
                        const auto [lanes, counted] = both_answers(c, r2);
                        INFO("Rc " << rc << " ratio " << ratio << ": " << describe(c));
                        REQUIRE(counted != shared::T_UNKNOWN);
                        REQUIRE(lanes == counted);
                        (counted == shared::T_INSIDE ? inside : outside)++;
                    }
    }
    CHECK(inside > 2000);
    CHECK(outside > 2000);
#endif
}

// Twelve circles of radius 5 s through a lattice point p (centres p + s d, d of length 5) cover
// every point within 9.4 s of p but p itself, which lies on all of them: every crossing at p
// ties with ten other circles, and only the exact signs find p uncovered.
TEST_CASE("T membership: the four-lane test decides ties at a crossing exactly", "[two-radii]") {
#ifndef VRPD_HOST_AVX2
    SUCCEED("not x86-64: reaches_uncovered is the counted test itself");
#else
    if (!shared::host_has_avx2()) SUCCEED("no AVX2 here: reaches_uncovered is the counted test itself");
    if (!shared::host_has_avx2()) return;
    const glm::ivec2 far(shared::FAR_SIDE, shared::FAR_SIDE);
    std::mt19937_64 rng(7);
    for (const int s : {200, 104855}) {
        const std::uint64_t r2 = std::uint64_t(25) * std::uint64_t(s) * std::uint64_t(s);
        REQUIRE(r2 <= shared::MAX_COVER2);
        auto around = [&](glm::ivec2 p) {
            Config c;
            for (const glm::ivec2 d : pythagorean_directions()) c.disks.push_back(p + s * d);
            c.lo = -far;
            c.hi = far;
            return c;
        };
        auto expect = [&](const Config& c, shared::uint answer, const char* what) {
            const auto [lanes, counted] = both_answers(c, r2);
            INFO("s " << s << ", " << what << ": " << describe(c));
            REQUIRE(counted == answer);
            REQUIRE(lanes == answer);
        };
        // A dart at the origin, p = (s, 0) inside its disk: p is the disk's one uncovered point.
        Config c = around({s, 0});
        expect(c, shared::T_INSIDE, "p in the dart's disk");
        c.disks.push_back({5 * s, 0});  // 4 s from p: covers it
        expect(c, shared::T_OUTSIDE, "p covered by a thirteenth disk");
        // p on the dart's circle (a tie of the dart's own disk too), the far side of the dart's
        // disk covered by a disk at -0.6 p.
        c = around({3 * s, 4 * s});
        c.disks.push_back({-9 * s / 5, -12 * s / 5});
        expect(c, shared::T_INSIDE, "p on the dart's circle");
        // A box side through p (the box's exact test), or one unit past it.
        c = around({s, 0});
        c.lo.x = s;
        expect(c, shared::T_INSIDE, "p on the box's side");
        c.lo.x = s + 1;
        expect(c, shared::T_OUTSIDE, "p one unit outside the box");
        // A quadtree cell [0, h]^2 holding p inside, on its side, or one unit off it.
        const int h = 2 * s;
        for (const auto& [p, answer] :
             {std::pair{glm::ivec2(s, s), shared::T_INSIDE}, std::pair{glm::ivec2(0, s), shared::T_INSIDE},
              std::pair{glm::ivec2(-1, s), shared::T_OUTSIDE}}) {
            c = around(p);
            c.in_disk = false;
            c.lo = {0, 0};
            c.hi = {h, h};
            expect(c, answer, "a cell");
        }
        // Each centre moved by up to one unit: near ties, decided alike.
        for (int i = 0; i < 400; ++i) {
            c = around({s, int(rng() % 3) - 1});
            for (glm::ivec2& d : c.disks) d += glm::ivec2(int(rng() % 3) - 1, int(rng() % 3) - 1);
            c.in_disk = rng() % 2 == 0;
            if (!c.in_disk) {
                c.lo = {0, -s};
                c.hi = {2 * s, s};
            }
            const auto [lanes, counted] = both_answers(c, r2);
            INFO("s " << s << ", moved centres: " << describe(c));
            REQUIRE(lanes == counted);
        }
    }
#endif
}

// Each crossing's judgement alone, where the whole test's answer could hide one (a point where
// circles tie is a vertex of several kinds): the four-lane cover searches against the host's
// estimated ones (themselves tested against the exact signs), on the twelve circles through p,
// every centre moved by up to a unit or not.
TEST_CASE("T membership: the four-lane cover search of each crossing is the kernel's", "[two-radii]") {
#ifndef VRPD_HOST_AVX2
    SUCCEED("not x86-64: reaches_uncovered is the counted test itself");
#else
    if (!shared::host_has_avx2()) SUCCEED("no AVX2 here: reaches_uncovered is the counted test itself");
    if (!shared::host_has_avx2()) return;
    std::mt19937_64 rng(3);
    const int far = shared::FAR_SIDE;
    int covered = 0, uncovered = 0, ties = 0;
    for (const int s : {200, 104855}) {
        const std::uint64_t r2 = std::uint64_t(25) * std::uint64_t(s) * std::uint64_t(s);
        const double r4 = 4.0 * double(r2);
        for (int round = 0; round < 40; ++round) {
            const glm::ivec2 p(s, 0);
            std::vector<glm::ivec2> disks;
            for (const glm::ivec2 d : pythagorean_directions()) disks.push_back(p + s * d);
            if (round % 2 == 1)
                for (glm::ivec2& d : disks) d += glm::ivec2(int(rng() % 3) - 1, int(rng() % 3) - 1);
            const auto n = shared::uint(disks.size());
            std::copy(disks.begin(), disks.end(), shared::disk_at);
            shared::estimate_disks(n);
            const shared::DiskLanes lanes = shared::disk_lanes(n);
            for (shared::uint i = 0; i < n; ++i) {
                // The pairs' crossings.
                for (shared::uint j = i + 1; j < n; ++j) {
                    const glm::ivec2 a = disks[i], b = disks[j];
                    const auto l = shared::norm2(b - a);
                    if (l == 0 || l > 4 * r2) continue;
                    const shared::CirclePair pair = shared::circle_pair(a, b, r2);
                    for (const int sigma : {-1, 1}) {
                        const shared::Doubled at = shared::twice_crossing(pair, sigma);
                        shared::t_steps = 0;
                        const bool kernel = shared::crossing_uncovered(a, b, sigma, i, j, n, r2);
                        const bool four = shared::lanes_crossing_uncovered(lanes, n, at.x, at.y, a, b, sigma, i, j, r2);
                        INFO("s " << s << " pair " << i << "," << j << " sigma " << sigma);
                        REQUIRE(four == kernel);
                        (kernel ? uncovered : covered)++;
                        for (shared::uint k = 0; k < n; ++k) {
                            const double ex = at.x - 2.0 * disks[k].x, ey = at.y - 2.0 * disks[k].y;
                            ties += k != i && k != j && std::abs(ex * ex + ey * ey - r4) <= 1.0;
                        }
                    }
                }
                // The circle's crossings with lines through p, across and along each axis, as a
                // box's side (no range along it, outside no dart's disk).
                for (const bool swap : {false, true}) {
                    const int side = swap ? p.y : p.x;
                    const glm::ivec2 c = shared::swizzle(disks[i], swap);
                    const std::int64_t gap = std::int64_t(side) - c.x;
                    if (std::uint64_t(gap * gap) > r2) continue;
                    const std::uint64_t nn = r2 - std::uint64_t(gap * gap);
                    for (const int tau : {-1, 1}) {
                        shared::t_steps = 0;
                        const bool kernel =
                            shared::side_crossing_uncovered(disks[i], i, side, -far, far, swap, tau, n, r2, false);
                        const double root = double(tau) * std::sqrt(double(nn));
                        const bool four =
                            shared::lanes_side_crossing_uncovered(swap ? lanes.y : lanes.x, swap ? lanes.x : lanes.y, n,
                                                                  side, c.y, root, tau, nn, i, r2, swap);
                        INFO("s " << s << " circle " << i << " swap " << swap << " tau " << tau);
                        REQUIRE(four == kernel);
                        (kernel ? uncovered : covered)++;
                    }
                }
            }
        }
    }
    // Crossings of both kinds, and estimates within 1 of 0 (the exact signs' cases) by the thousand.
    CHECK(covered > 1000);
    CHECK(uncovered > 1000);
    CHECK(ties > 1000);
#endif
}
