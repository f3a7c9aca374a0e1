// Mask mode's refinements into 4 or 16 sub-cells on the host (one radius), by scattering each
// sample's cover to the base cells around it rather than gathering the samples around each base
// cell: the first refinement keeps about three active base cells a sample, so a pass over the
// samples does a third of the work. The masks are refine_masked_base's, bit for bit.
#pragma once

#include <cstdint>

#include "shared/kernels.h"
#include "thread_pool.h"

namespace vrpd::detail {

// Writes to masks[i] the surviving children (side a.side; a.param: 4 children, or 1, the cell
// itself) of each base cell i's active sub-cells, as refine_masked_base(a, grid, i).x gives them,
// for refinements into at most 16 sub-cells (not the last mask level's, masked_leaves); the
// samples' covers are scattered where cells split. Returns the active sub-cells' count.
// `vector_bodies`: the AVX2 bodies may run where the processor has them (tests run both).
std::uint64_t refine_masked_scattered(ThreadPool& pool, const shared::CellArgs& a, shared::Grid grid,
                                      shared::uint* masks, bool vector_bodies = true);

}  // namespace vrpd::detail
