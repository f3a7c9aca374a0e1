// The exact sum of powers of two, for sums the engine must give as one thread adding in list
// order would (field/engine.cpp, weighted_area).
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <optional>

namespace vrpd::detail::field {

// The powers 2^(e - bias), count[e] of each, summed, when that sum is a whole number below
// 2^53 of the least power present: then every partial sum, in any order, is such a number too,
// exact in a double, and so every order of additions gives this value. Otherwise nullopt (the
// caller adds in its order).
template <std::size_t N>
std::optional<double> exact_power_sum(const std::array<std::uint64_t, N>& count, int bias) {
    constexpr std::uint64_t kExact = std::uint64_t(1) << 53;
    std::size_t least = 0;
    while (least < N && count[least] == 0) ++least;
    if (least == N) return 0.0;
    std::uint64_t units = 0;
    for (std::size_t e = least; e < N; ++e) {
        if (count[e] == 0) continue;
        if (e - least >= 53 || count[e] >= (kExact >> (e - least))) return std::nullopt;
        units += count[e] << (e - least);
        if (units >= kExact) return std::nullopt;
    }
    // 2^(least - bias) times a whole number below 2^53: exact, for the exponents of normal doubles.
    const int e = int(least) - bias;
    return double(units) * std::bit_cast<double>(std::uint64_t(1023 + e) << 52);
}

}  // namespace vrpd::detail::field
