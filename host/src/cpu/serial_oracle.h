// The oracle: a round's darts decided by the textbook definition of random sequential adsorption
// (paper Eq. 4; with two radii, Eq. 9), one at a time in arrival order, each given the samples and
// the darts accepted before it. The `serial` backend resolves every round this way; the parity
// tests hold the parallel resolutions of the cpu and gpu backends to its answers.
#pragma once

#include <cstdint>

#include "shared/kernels.h"

namespace vrpd::detail {

// Decides the undecided darts among the round's `count` in arrival order. Returns the bytes its
// work list held, for the engine's peak.
std::uint64_t resolve_in_arrival_order(const shared::Domain& dom, shared::Grid grid, shared::Darts darts,
                                       shared::uint count);

}  // namespace vrpd::detail
