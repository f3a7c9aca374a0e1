// The 128-bit arithmetic that exact membership in T rests on (shared/t_membership.h): products
// from 32-bit halves, and the sign of a sqrt(l) + b sqrt(m), on the host and on the device.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>

#include "root_sum_probe.h"
#include "shared/sampler.h"
#include "vulkan/buffer.h"
#include "vulkan/device.h"
#include "vulkan/kernel.h"

using namespace vrpd;

namespace {

int reference_sign(std::int64_t a, std::uint64_t l, std::int64_t b, std::uint64_t m) {
    const long double approx = (long double)a * std::sqrt((long double)l) + (long double)b * std::sqrt((long double)m);
    const int sa = l == 0 ? 0 : (a > 0) - (a < 0);
    const int sb = m == 0 ? 0 : (b > 0) - (b < 0);
    if (sa == sb || sb == 0) return sa;
    if (sa == 0) return sb;
    using u128 = unsigned __int128;
    const u128 ua = u128(std::uint64_t(a < 0 ? -a : a));
    const u128 ub = u128(std::uint64_t(b < 0 ? -b : b));
    const u128 lhs = ua * ua * l;
    const u128 rhs = ub * ub * m;
    if (lhs == rhs) return 0;
    const int exact = lhs > rhs ? sa : sb;
    // The long double estimate must agree wherever it is clearly away from 0 (guards the reference).
    if (std::abs(approx) > 1e-6L * (std::abs((long double)a) * std::sqrt((long double)l)))
        REQUIRE(exact == (approx > 0 ? 1 : -1));
    return exact;
}

}  // namespace

// The device multiplies 64-bit words through 32-bit halves; the host natively.
TEST_CASE("the 128-bit product from 32-bit halves is exact", "[two-radii]") {
    std::mt19937_64 rng(11);
    for (int i = 0; i < 200000; ++i) {
        const int bits_a = 1 + int(rng() % 64);
        const int bits_b = 1 + int(rng() % 64);
        const std::uint64_t a = bits_a == 64 ? rng() : rng() % (std::uint64_t(1) << bits_a);
        const std::uint64_t b = bits_b == 64 ? rng() : rng() % (std::uint64_t(1) << bits_b);
        std::uint64_t hi, lo;
        shared::mul_wide_halves(a, b, hi, lo);
        const unsigned __int128 p = static_cast<unsigned __int128>(a) * b;
        INFO(a << " * " << b);
        REQUIRE((hi == std::uint64_t(p >> 64) && lo == std::uint64_t(p)));
    }
    std::uint64_t hi, lo;
    shared::mul_wide_halves(~std::uint64_t(0), ~std::uint64_t(0), hi, lo);
    CHECK((hi == ~std::uint64_t(0) - 1 && lo == 1));
}

TEST_CASE("sign of a sqrt(l) + b sqrt(m) is exact up to the 2^124 products the test meets", "[two-radii]") {
    std::mt19937_64 rng(7);
    const std::uint64_t r2 = shared::MAX_COVER2;
    for (int i = 0; i < 200000; ++i) {
        // |a|, |b| up to 2^42 and l, m up to 4 r2 = 2^40: the bounds t_membership.h relies on.
        const std::int64_t a = std::int64_t(rng() % (std::uint64_t(1) << 43)) - (std::int64_t(1) << 42);
        const std::int64_t b = std::int64_t(rng() % (std::uint64_t(1) << 43)) - (std::int64_t(1) << 42);
        const std::uint64_t l = rng() % (4 * r2 + 1);
        // Half the cases near the tie a^2 l = b^2 m, where a float test would go wrong.
        std::uint64_t m = rng() % (4 * r2 + 1);
        if (i % 2 && b != 0 && l != 0) {
            const long double t = (long double)a * a * l / ((long double)b * b);
            if (t < 4.0L * r2) m = std::uint64_t(t) + rng() % 3 - 1;
        }
        INFO(a << " " << l << " " << b << " " << m);
        REQUIRE(shared::sign_of_root_sum(a, l, b, m) == reference_sign(a, l, b, m));
    }
    // Exact ties: 3 sqrt(4) - 2 sqrt(9) = 0, at the largest magnitudes as well.
    CHECK(shared::sign_of_root_sum(3, 4, -2, 9) == 0);
    const std::int64_t big = std::int64_t(1) << 41;
    CHECK(shared::sign_of_root_sum(big, 4 * r2, -2 * big, r2) == 0);
    CHECK(shared::sign_of_root_sum(big, 4 * r2, -2 * big, r2 + 1) == -1);
    CHECK(shared::sign_of_root_sum(big, 4 * r2 + 1, -2 * big, r2) == 1);
}

// The host's crossing test reads signs from a double estimate and falls back on the exact test
// within 1 of 0 (t_membership.h). Crossings on a third circle (D = 0 exactly: circles of radius
// 5k through one lattice point) must take the exact answer, open disks not covering their
// boundary; a centre moved by one unit covers the crossing or leaves it, up to the largest Rc. The
// same for a crossing on the dart's own circle, which the pair loop keeps (closed disk).

TEST_CASE("the device's sign of a sqrt(l) + b sqrt(m) is exact, near ties as well", "[two-radii][gpu]") {
    std::mt19937_64 rng(11);
    const std::uint64_t r2 = shared::MAX_COVER2;
    std::vector<glm::i64vec4> cases;
    // The host test's draws (|a|, |b| up to 2^42, l, m up to 4 r2), most near the tie a^2 l = b^2 m,
    // at every scale down to single digits; exact ties; and a tie missed by one at the largest.
    for (int i = 0; i < 60000; ++i) {
        const int bits = 2 + int(rng() % 41);
        const std::uint64_t span = std::uint64_t(1) << bits;
        const std::int64_t a = std::int64_t(rng() % (2 * span + 1)) - std::int64_t(span);
        const std::int64_t b = std::int64_t(rng() % (2 * span + 1)) - std::int64_t(span);
        const std::uint64_t l = rng() % (4 * r2 + 1) >> (rng() % 40);
        std::uint64_t m = rng() % (4 * r2 + 1);
        if (i % 4 != 0 && b != 0 && l != 0) {
            const long double t = (long double)a * a * l / ((long double)b * b);
            if (t < 4.0L * r2) m = std::uint64_t(t) + rng() % 3 - 1;
        }
        cases.push_back({a, std::int64_t(l), b, std::int64_t(m)});
    }
    const std::int64_t big = std::int64_t(1) << 41;
    for (const glm::i64vec4 c :
         {glm::i64vec4{3, 4, -2, 9}, glm::i64vec4{big, 4 * r2, -2 * big, r2},
          glm::i64vec4{big, 4 * r2, -2 * big, r2 + 1}, glm::i64vec4{big, 4 * r2 + 1, -2 * big, r2},
          glm::i64vec4{-3, 4, 2, 9}, glm::i64vec4{0, 5, -1, 7}, glm::i64vec4{1, 0, -1, 7}})
        cases.push_back(c);
    detail::VulkanContext ctx("");
    detail::Kernel probe(ctx, "root_sum_probe", {spirv_root_sum_probe, std::size(spirv_root_sum_probe)}, 20, 64);
    detail::Buffer in(ctx, cases.size() * sizeof(glm::i64vec4), true);
    detail::Buffer out(ctx, cases.size() * 4, true);
    std::memcpy(in.mapped(), cases.data(), cases.size() * sizeof(glm::i64vec4));
    struct {
        std::uint64_t cases, signs;
        std::uint32_t count;
    } push{in.address(), out.address(), std::uint32_t(cases.size())};
    ctx.begin();
    ctx.dispatch(probe, &push, std::uint32_t((cases.size() + 63) / 64));
    ctx.barrier();  // signs before the host reads them
    ctx.submit_and_wait();
    ctx.check_validation();
    const auto* signs = static_cast<const std::int32_t*>(out.mapped());
    std::size_t close = 0, ties = 0;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const glm::i64vec4 c = cases[i];
        const int exact = reference_sign(c.x, std::uint64_t(c.y), c.z, std::uint64_t(c.w));
        INFO(c.x << " sqrt(" << c.y << ") + " << c.z << " sqrt(" << c.w << ")");
        REQUIRE(signs[i] == exact);
        // The cases where a single-precision estimate could not tell the sign: the sum within
        // 2^-16 of the terms.
        const long double ea = (long double)c.x * std::sqrt((long double)c.y);
        const long double eb = (long double)c.z * std::sqrt((long double)c.w);
        close += std::fabs(ea + eb) <= (std::fabs(ea) + std::fabs(eb)) * 0x1p-16L ? 1 : 0;
        ties += exact == 0 ? 1 : 0;
    }
    CHECK(close > 10000);
    CHECK(ties > 50);
}
