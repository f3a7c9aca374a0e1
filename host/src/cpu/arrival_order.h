// One radius on one thread: a round's darts decided one at a time in arrival order, the textbook
// process itself, at the cost of the throw's test per dart (see arrival_order.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "shared/kernels.h"

namespace vrpd::detail {

// Decides the undecided darts among the round's `count` (one radius) in arrival order: each
// accepted dart takes its base cell's grid word as its sample at once, so a dart is rejected iff
// the samples near it (earlier rounds' and this round's so far) hold one within Rf. Appends the
// accepted darts to `out` in arrival order, the round's emission. Returns the bytes its lists held.
std::uint64_t decide_in_arrival_order(const shared::Domain& dom, shared::Grid grid, shared::Darts darts,
                                      shared::uint count, std::vector<shared::uvec2>& out);

// Sorts values whose high 32 bits are a key and low 32 bits an index, listed in ascending index
// order, into ascending (key, index) order: a stable radix sort on the key (3 passes of 11 bits).
void sort_by_key(std::vector<std::uint64_t>& values);

}  // namespace vrpd::detail
