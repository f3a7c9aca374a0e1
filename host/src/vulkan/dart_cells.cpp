// Two radii's dart cells on the Vulkan engine: the base cells near the active cells, which a
// round's darts go to (shared/dart_cells.h).
#include "shared/dart_cells.h"
#include "vulkan/vulkan_engine.h"

namespace vrpd::detail {

using namespace shared;

// Two radii: lists the base cells that get darts this round (flag_dart_cells or
// flag_free_cells, a scan of the flags, list_dart_cells), counts the round's darts over them, and
// returns their count. The flags lie at the start of the scratch buffer, where the counts then
// go. Where the list is small even at its worst-case size (each active base cell flags at most
// the (2 cover_reach + 1)^2 cells around it), it takes that size, its unused entries
// (GRID_EMPTY, GRID_EMPTY), to whose counts the prefix sums add nothing: one submit. Else the
// flags' total sizes the list in a submit of its own.
std::uint32_t VulkanEngine::list_dart_cells(const RoundSpec& spec) {
    const std::uint64_t bases = plan_.base_cells;
    grow(ctx_, scratch_, (bases + 1) * 4);
    primitives_.reserve_scan(bases + 1);
    const std::uint64_t flags = scratch_.address();
    const std::uint64_t around = 2 * std::uint64_t(cover_reach(plan_.domain.radii)) + 1;
    std::uint64_t size = spec.every_free_cell ? bases : std::min(bases, active_ * around * around);
    const bool worst_case = within_share(size * sizeof(uvec2));
    auto allocate = [&] {
        dart_cells_ = Buffer();  // free first: the peak is then the new size, not both
        dart_cells_ = Buffer(ctx_, std::max<std::uint64_t>(size, 1) * sizeof(uvec2), false);
    };
    if (worst_case) allocate();
    VkCommandBuffer cmd = ctx_.begin();
    if (worst_case) ctx_.vk().vkCmdFillBuffer(cmd, dart_cells_.handle(), 0, VK_WHOLE_SIZE, GRID_EMPTY);
    CellArgs a = cell_args(cells_.address(), {}, active_, spec.round, spec.side, 0);
    a.scan = flags;
    if (spec.every_free_cell) {
        a.cell_count = std::uint32_t(bases);
        ctx_.dispatch(flag_free_cells_, &a, dispatch_groups(bases + 1, WORKGROUP_SIZE));
    } else {
        ctx_.vk().vkCmdFillBuffer(cmd, scratch_.handle(), 0, (bases + 1) * 4, 0);
        ctx_.barrier();  // cleared flags before they are set
        ctx_.dispatch(flag_dart_cells_, &a, dispatch_groups(std::uint64_t(active_) + 1, WORKGROUP_SIZE));
    }
    ctx_.barrier();  // flags (and the list's fill) before their scan
    primitives_.scan(flags, bases + 1, COUNTER_DART_CELLS);
    if (!worst_case) {
        ctx_.submit_and_wait();
        size = counter(COUNTER_DART_CELLS);
        allocate();
        ctx_.begin();
    }
    a.cell_count = std::uint32_t(bases);
    a.cells_out = dart_cells_.address();
    ctx_.dispatch(list_dart_cells_, &a, dispatch_groups(bases, WORKGROUP_SIZE));
    ctx_.barrier();  // the list before its counts overwrite the flags' ranks
    record_counts(spec, count_darts_, dart_cells_.address(), std::uint32_t(size));
    ctx_.submit_and_wait();
    return counter(COUNTER_DART_CELLS);
}

}  // namespace vrpd::detail
