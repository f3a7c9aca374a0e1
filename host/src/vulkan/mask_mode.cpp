// The Vulkan engine's mask mode (shared/mask_mode.h): at levels 0 to MASK_LEVELS - 1 the
// active cells are masks in the grid words, and the kernels run over the base cells, or at the
// last level over the list of those with active sub-cells.
#include "shared/mask_mode.h"
#include "shared/quadtree.h"
#include "vulkan/vulkan_engine.h"

namespace vrpd::detail {

using namespace shared;

// Mask mode's counterpart: the base cells' new masks go to the ranks region and then to their
// words. At the last mask-mode level the children go to an explicit active list instead: their
// 64-bit masks pass through the ranks region and the spent darts' buffer (see round) to the
// words, their counts are ranked, and mask mode ends. Returns the active count.
// The round's targets are `n` base cells, or the `n` listed at `targets` (masked.glsl).
std::uint32_t VulkanEngine::refine_masked(const RoundSpec& spec, std::uint64_t ranks, std::uint32_t child_side,
                                          std::uint32_t fanout, std::uint32_t n, std::uint64_t targets,
                                          const RoundSpec* next) {
    CellArgs a = cell_args(targets, Regions{ranks, 0, darts_.address(), ranks}, n, spec.round, child_side, fanout);
    const bool leaves = masked_leaves(plan_.domain, child_side, fanout);
    // Children of the last mask-mode level: from the next round on, the kernels run over the
    // list of the base cells that hold them (a superset of the active ones while the level's
    // rounds last: masks only lose bits).
    const bool last_level = fanout == 4u && (child_side << (MASK_LEVELS - 1u)) == (1u << plan_.domain.cell_bits);
    const bool tested = cover_tested(plan_.domain, fanout, child_side);
    const ScatterBox box = scatter_box(plan_.domain, child_side, fanout);
    const bool scattered = targets == 0 && box_any(box);
    // Level 0's rounds before its last: without a cover test every base cell without a sample
    // stays active, its one sub-cell, and nothing runs: the count is the base cells less the
    // samples (each in a base cell of its own).
    const bool whole = !tested && !leaves && child_side == (1u << plan_.domain.cell_bits);
    if (!whole) {
        // Scattered: the boxed cells' masks start full, for apply_masks to keep the children of
        // the active sub-cells that no sample covers; refine_masked refines the box's border.
        CellArgs r = a;
        if (scattered) {
            ctx_.vk().vkCmdFillBuffer(ctx_.recording(), scratch_.handle(), ranks - scratch_.address(),
                                      std::uint64_t(n) * 4, ~0u);
            ctx_.barrier();  // the fill before refine_masked writes the border's masks
            r.cell_count = border_count(plan_.domain, box);
        }
        ctx_.dispatch(refine_masked_, &r, dispatch_groups(std::uint64_t(r.cell_count) + 1, WORKGROUP_SIZE));
        ctx_.barrier();  // the new masks (and the active sum) before they reach the words
    }
    // Over every base cell into 4 or 16 sub-cells, the samples clear the covered children from
    // the boxed cells' masks (refine_masked.comp); apply_masks then counts the sub-cells. The
    // samples, emitted_ and this round's, number at most the n base cells.
    if (scattered) {
        CellArgs s = a;
        s.cells = samples_.address();
        s.cell_count = std::uint32_t(emitted_);
        ctx_.dispatch(scatter_covers_, &s, dispatch_groups(n, WORKGROUP_SIZE));
        ctx_.barrier();  // the masks before apply_masks reads them
    }
    if (tested) {
        ctx_.dispatch(apply_masks_, &a, dispatch_groups(n, WORKGROUP_SIZE));
        ctx_.barrier();  // the words (and the counts) before the next round, or the scan
    }
    if (leaves) primitives_.scan(ranks, std::uint64_t(n) + 1, COUNTER_ACTIVE);
    // The next round runs over the same base cells: its darts are counted here (as in round's
    // first submit, into the start of the scratch buffer, which holds n + 1 words), so that it
    // starts with its throw. The new masks there are spent.
    if (next && !leaves && !last_level) record_counts(*next, count_masked_, targets, n);
    ctx_.submit_and_wait();
    darts_ = Buffer();
    const std::uint32_t kept =
        whole ? std::uint32_t(plan_.base_cells - emitted_ - counter(COUNTER_ACCEPTED)) : counter(COUNTER_ACTIVE);
    if (!leaves) {
        if (last_level && kept > 0) list_active_bases();
        return kept;
    }
    if (kept >= GRID_TAG) throw Error("more than 2^31 active cells");
    cells_ = Buffer(ctx_, std::uint64_t(kept) * sizeof(uvec2), false);
    a.cells_out = cells_.address();
    // The next round runs over this list: its darts are counted here too.
    const bool count = prepare_counts(next, kept);
    ctx_.begin();
    ctx_.dispatch(scatter_masked_, &a, dispatch_groups(n, WORKGROUP_SIZE));
    ctx_.barrier();  // the active list and the emptied words before the next round
    if (count) record_counts(*next, count_darts_, cells_.address(), kept);
    ctx_.submit_and_wait();
    masked_ = false;
    base_list_ = Buffer();
    listed_bases_ = 0;
    return kept;
}

// Lists the base cells with active sub-cells, in base cell order (flag_masked, a scan of the
// flags, list_masked), for the kernels of the last mask-mode level. At r = 0.001 a quarter of
// the base cells are active there (474 k of 2.0 M); over all of them, most SIMD batches of a
// kernel ran for one or two working lanes. The flags lie at the start of the scratch buffer;
// the list gets a buffer of its exact size.
void VulkanEngine::list_active_bases() {
    const std::uint64_t bases = plan_.base_cells;
    grow(ctx_, scratch_, (bases + 1) * 4);
    primitives_.reserve_scan(bases + 1);
    ctx_.begin();
    CellArgs a = cell_args(0, {}, std::uint32_t(bases), 0, 0, 0);
    a.scan = scratch_.address();
    ctx_.dispatch(flag_masked_, &a, dispatch_groups(bases + 1, WORKGROUP_SIZE));
    ctx_.barrier();  // flags before their scan
    primitives_.scan(a.scan, bases + 1, COUNTER_LISTED);
    ctx_.submit_and_wait();
    listed_bases_ = counter(COUNTER_LISTED);
    base_list_ = Buffer();  // free first: the peak is then the new size, not both
    base_list_ = Buffer(ctx_, std::uint64_t(listed_bases_) * sizeof(uint), false);
    a.work = base_list_.address();
    ctx_.begin();
    ctx_.dispatch(list_masked_, &a, dispatch_groups(bases, WORKGROUP_SIZE));
    ctx_.barrier();  // the list before the round's kernels read it
    ctx_.submit_and_wait();
}

}  // namespace vrpd::detail
