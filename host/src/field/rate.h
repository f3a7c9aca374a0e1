// The field samplers' darts per round (the host's, field/engine.cpp, and the Vulkan one,
// vulkan/field_engine.cpp): one definition, so that both throw the same darts.
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace vrpd::detail::field {

// Poisson mean of darts per active cell per round, and the most one cell takes before it is split.
// Below one: a leaf holds one sample, and the first round's leaves are several per sample, so at
// one dart a cell most darts of a round would land in leaves taken earlier in it.
constexpr double kLambda = 0.3;
constexpr double kSplitAbove = 4.0;

// Refinement splits the open cells that took darts; once the active cells are at most a
// kSplitEveryBelow-th of the leaves, it splits every open cell, as the one-radius sampler does at
// each level. A cell without a dart then need not wait for one to shrink towards its gaps, so
// the tail's rounds, each a few submits on a device however few its cells, are fewer; earlier,
// when most cells would take no dart, searching each for its children's covers costs more than
// the rounds it spares.
constexpr std::uint64_t kSplitEveryBelow = 16;
inline bool splits_every_cell(std::uint64_t cells, std::uint64_t leaves) { return cells * kSplitEveryBelow <= leaves; }

// Cells counted by the exponent of their weighted area, entry e + kExponentBias.
constexpr int kExponentBias = 64;
using ExponentCounts = std::array<std::uint64_t, 128>;

// 2^e, exactly, for |e| < 1023 (std::ldexp's value without its call).
inline double pow2(int e) { return std::bit_cast<double>(std::uint64_t(1023 + e) << 52); }

// The least biased exponent whose cells expect more than kSplitAbove darts at `rate` (128 if
// none): rate 2^e grows with e, so the cells split are those at or above it.
inline int split_exponent(double rate) {
    for (int e = 0; e < 128; ++e)
        if (rate * pow2(e - kExponentBias) > kSplitAbove) return e;
    return 128;
}

// e^-(rate 2^e) in 2^-32 units per biased exponent: a cell's dart count's draw (shared/darts.h).
inline void exp_neg_table(double rate, std::uint32_t out[128]) {
    for (int e = 0; e < 128; ++e)
        out[e] = std::uint32_t(std::floor(std::exp(-rate * std::ldexp(1.0, e - kExponentBias)) * 4294967296.0));
}

}  // namespace vrpd::detail::field
