// Generic device primitives the sampler's rounds are built from: an exclusive prefix sum over
// uints (three passes: block scans, a scan of the block sums, their addition; the first alone for
// one block, as the lists of a run's late rounds are) and a stable LSD radix sort of points by
// 32-bit key (8 bits a pass: digit histograms per tile, their scan, a stable scatter; a few points
// ranked in one workgroup instead). Both record into the context's command buffer; the caller
// submits. The block scans use subgroup arithmetic where the device has it
// (VulkanContext::subgroup_scan), with the same result.
#pragma once

#include <cstdint>

#include "buffer.h"
#include "device.h"
#include "kernel.h"
#include "shared/kernels.h"

namespace vrpd::detail {

class Primitives {
public:
    // `counters`: the host-visible buffer whose slots receive the scans' totals.
    Primitives(VulkanContext& ctx, const Buffer& counters);
    // Sizes the scan's block sums for `count` elements; call before recording such a scan.
    void reserve_scan(std::uint64_t count);
    // Exclusive prefix sum of the `count` uints at device address `data`, in place; the total
    // goes to counters[total_slot].
    void scan(std::uint64_t data, std::uint64_t count, std::uint32_t total_slot);
    // Sizes the sort's histogram (and the scan over it) for `count` elements: sort_bytes(count).
    void reserve_sort(std::uint32_t count);
    static std::uint64_t sort_bytes(std::uint32_t count);
    // Sorts the `count` points at `points` (uvec2) by their keys at `keys`, stably, in 4 passes,
    // ping-ponging with `tmp` (count points, then count keys): after the fourth pass the sorted
    // points and keys are back in place. `total_slot` is a counters slot the histogram scans use.
    // Up to SORT_SMALL points, one dispatch ranks them in place.
    void sort(std::uint64_t points, std::uint64_t keys, std::uint64_t tmp, std::uint32_t count,
              std::uint32_t total_slot);
    // Gives back the sort's histogram.
    void release_sort() { histogram_ = Buffer(); }

private:
    VulkanContext& ctx_;
    const Buffer& counters_;
    Kernel scan_blocks_, scan_sums_, scan_add_, sort_histogram_, sort_scatter_, sort_small_;
    Buffer block_sums_;
    Buffer histogram_;
};

}  // namespace vrpd::detail
