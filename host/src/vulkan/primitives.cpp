// Device primitives: see primitives.h.
#include "primitives.h"

#include "scan_add.h"
#include "scan_blocks.h"
#include "scan_blocks_subgroup.h"
#include "scan_sums.h"
#include "sort_histogram.h"
#include "sort_scatter.h"
#include "sort_small.h"

namespace vrpd::detail {

using namespace shared;

Primitives::Primitives(VulkanContext& ctx, const Buffer& counters)
    : ctx_(ctx),
      counters_(counters),
      scan_blocks_(ctx_, "scan_blocks",
                   ctx.subgroup_scan() ? spirv_words(spirv_scan_blocks_subgroup) : spirv_words(spirv_scan_blocks),
                   sizeof(ScanArgs), 64),
      VRPD_KERNEL(scan_sums, ScanArgs, 64),
      VRPD_KERNEL(scan_add, ScanArgs, 64),
      VRPD_KERNEL(sort_histogram, SortArgs, 64),
      VRPD_KERNEL(sort_scatter, SortArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(sort_small, SortArgs, 128) {}

void Primitives::reserve_scan(std::uint64_t count) {
    grow(ctx_, block_sums_, std::uint64_t(dispatch_groups(count, SCAN_BLOCK)) * 4);
}

void Primitives::scan(std::uint64_t data, std::uint64_t count, std::uint32_t total_slot) {
    const std::uint32_t blocks = dispatch_groups(count, SCAN_BLOCK);
    if (block_sums_.size() < std::uint64_t(blocks) * 4)
        throw Error("internal: scan buffers not sized before recording");
    ScanArgs s{data, block_sums_.address(), counters_.address(), std::uint32_t(count), blocks, total_slot, 0};
    ctx_.dispatch(scan_blocks_, &s, blocks);
    ctx_.barrier();  // block scans and sums before their readers
    // One block is scanned whole by the first pass, which writes its total.
    if (blocks == 1) return;
    ctx_.dispatch(scan_sums_, &s, 1);
    ctx_.barrier();  // block offsets before they are added
    ctx_.dispatch(scan_add_, &s, blocks);
    ctx_.barrier();  // the prefix sums before their readers
}

std::uint64_t Primitives::sort_bytes(std::uint32_t count) {
    return (std::uint64_t(SORT_BUCKETS) * dispatch_groups(count, SCAN_BLOCK) + 1) * 4;
}

void Primitives::reserve_sort(std::uint32_t count) {
    grow(ctx_, histogram_, sort_bytes(count));
    reserve_scan(sort_bytes(count) / 4);
}

void Primitives::sort(std::uint64_t points, std::uint64_t keys, std::uint64_t tmp, std::uint32_t count,
                      std::uint32_t total_slot) {
    const std::uint32_t tiles = dispatch_groups(count, SCAN_BLOCK);
    SortArgs s{points, keys, tmp, tmp + std::uint64_t(count) * sizeof(uvec2), histogram_.address(), count, 0, tiles, 0};
    if (count <= SORT_SMALL) {
        ctx_.dispatch(sort_small_, &s, 1);
        ctx_.barrier();  // the sorted points before their readers
        return;
    }
    const std::uint64_t bins = std::uint64_t(SORT_BUCKETS) * tiles;
    for (std::uint32_t pass = 0; pass < 4; ++pass) {
        s.shift = 8 * pass;
        ctx_.dispatch(sort_histogram_, &s, tiles);
        ctx_.barrier();  // digit counts before their scan
        scan(histogram_.address(), bins, total_slot);
        ctx_.dispatch(sort_scatter_, &s, dispatch_groups(tiles, WORKGROUP_SIZE));
        ctx_.barrier();  // this pass's output before the next pass reads it
        std::swap(s.src_points, s.dst_points);
        std::swap(s.src_keys, s.dst_keys);
    }
}

}  // namespace vrpd::detail
