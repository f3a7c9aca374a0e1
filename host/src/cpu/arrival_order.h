// A round's darts decided one at a time in arrival order, the textbook process itself, each
// against the samples alone (see arrival_order.cpp): the cpu backend's resolution on few threads.
#pragma once

#include <cstdint>
#include <vector>

#include "shared/kernels.h"
#include "thread_pool.h"
#include "uninitialised.h"

namespace vrpd::detail {

// Decides the undecided darts among the round's `count` in arrival order: each accepted dart
// takes its base cell's grid word as its sample at once, so a dart is judged by the samples near
// it (earlier rounds' and this round's so far): rejected iff one lies within Rf or, with two
// radii, it is outside T given them. Appends the accepted darts to `out` in arrival order, the
// round's emission; the darts' states stay as the throw left them, since nothing after reads
// them (HostEngine::commit empties the darts' words). The pool's threads each take a strip of
// base-cell rows where the grid has room for them and the round has `strip_darts` darts a
// thread (Plan::strip_darts; see arrival_order.cpp); the decisions are those of one thread.
// Throws Error where a T test passes its bounds. Returns the bytes its lists held.
std::uint64_t decide_in_arrival_order(const shared::Domain& dom, shared::Grid grid, shared::Darts darts,
                                      shared::uint count, std::vector<shared::uvec2>& out, ThreadPool& pool,
                                      shared::uint strip_darts);

// Darts' sort keys: a key in the high 32 bits, the dart's index in the low.
using Keys = std::vector<std::uint64_t, Uninitialised<std::uint64_t, true>>;

// Sorts values whose high 32 bits are a key and low 32 bits an index, listed in ascending index
// order, into ascending (key, index) order: a stable radix sort on the key (3 passes of 11 bits).
void sort_by_key(Keys& values);

}  // namespace vrpd::detail
