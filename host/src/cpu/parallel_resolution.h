// A round's darts decided on many threads, each dart's state written as the kernels' passes write
// it (see parallel_resolution.cpp): the cpu backend's resolution past a few threads, where arrival
// order's strips (arrival_order.h) no longer keep the threads busy.
#pragma once

#include <cstddef>

#include "shared/kernels.h"
#include "thread_pool.h"

namespace vrpd::detail {

// Decides every undecided dart among the round's `count`: accepted iff every earlier dart in
// conflict with it is rejected (resolve_dart), the sequential process's states. Throws Error if a
// dart waits for no dart while none is decided (a bug).
void decide_in_parallel(const shared::Domain& dom, shared::Grid grid, shared::Darts darts, std::size_t count,
                        ThreadPool& pool);

}  // namespace vrpd::detail
