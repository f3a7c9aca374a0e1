// The Vulkan engine: each round of the schedule as a few submits of compute dispatches over
// compacted lists (active cells, darts, undecided darts). The host reads back only counts, which
// size the next arrays exactly. Its mask mode is in mask_mode.cpp.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "buffer.h"
#include "device.h"
#include "engine.h"
#include "kernel.h"
#include "primitives.h"
#include "shared/kernels.h"

namespace vrpd::detail {

class VulkanEngine final : public Engine {
public:
    // Resolution passes recorded in one submit: most rounds end within 8, and a pass with no dart
    // left is three dispatches of no work (indirect, zero groups), far cheaper than a round trip.
    static constexpr std::uint32_t kResolvePassesPerSubmit = 8;
    // On the device `selector` picks, or on the application's (target, if not null). Tests set
    // fewer passes a submit to make gated round ends wait for later submits, and fewer workgroups
    // a row to make every dispatch and pass take several rows.
    VulkanEngine(const Plan& plan, const std::string& selector, const VulkanTarget* target = nullptr,
                 std::uint32_t passes_per_submit = kResolvePassesPerSubmit, std::uint32_t work_groups = kMaxWorkgroups);
    std::string device_name() const override { return ctx_.device_name(); }
    void start_profile() override { ctx_.start_profile(); }
    std::vector<PhaseTime> profile() const override { return ctx_.profile(); }
    std::uint64_t start(const Plan& plan, const std::vector<shared::uvec2>& initial) override;
    RoundResult round(const RoundSpec& spec, const RoundSpec* next) override;
    std::vector<shared::uvec2> samples() override;
    std::uint64_t peak_bytes() const override { return ctx_.peak_allocated_bytes(); }
    std::uint64_t round_trips() const override { return ctx_.submits(); }
    // Submits whose gated round end did not run, darts being left undecided (round).
    std::uint64_t shut_gates() const { return shut_gates_; }

private:
    // A round writes a list at its worst-case size, or sorts all its darts' slots (round), only
    // while those bytes are at most 1 / kWorstCaseShare of the most device memory held so far:
    // the early rounds, whose arrays make the peak, keep their exact sizes.
    static constexpr std::uint64_t kWorstCaseShare = 8;
    bool within_share(std::uint64_t bytes) const { return bytes <= ctx_.peak_allocated_bytes() / kWorstCaseShare; }
    // The device addresses of the scratch regions that the kernels over cells read.
    struct Regions {
        std::uint64_t scan = 0, darts = 0, work = 0, masks = 0;
    };
    // Where a round's transient arrays lie in the scratch buffer, as byte offsets. Arrays whose
    // lives do not overlap share a region:
    //   ranks: the targets' dart prefix sums (count_darts, mark_ranges), work list 1 (resolution),
    //          the accepted flags and their ranks (commit, emit), the surviving-children counts
    //          and their ranks (refine, scatter);
    //   list:  work list 0 (throw, resolution), the round's sample keys (emit, sort), the child
    //          masks (refine, scatter).
    // In mask mode throwing does not read the prefix sums, so everything shares the ranks region:
    // work lists 0 and 1 at [0, D) and [D, 2 D), then the flags at [0, D] and the keys after
    // them, then the base cells' new masks.
    // The darts have a buffer of their own (darts_), which the sort reuses for its second buffers.
    struct Scratch {
        std::uint64_t ranks = 0, work0, work1, keys, masks, end;
        Scratch(std::uint32_t targets, std::uint32_t dart_count, std::uint32_t active, bool masked) {
            const std::uint64_t d = dart_count;
            if (masked) {
                work0 = 0;
                work1 = d * 4;
                keys = (d + 1) * 4;
                masks = 0;
                end = std::max<std::uint64_t>(targets, 2 * d) * 4 + 4;
                return;
            }
            const std::uint64_t most = std::max(std::max(targets, dart_count), active);
            work0 = keys = masks = ((most + 1) * 4 + 15) / 16 * 16;
            work1 = 0;
            end = work0 + std::max<std::uint64_t>(d, active) * 4;
        }
        Regions in(const Buffer& b, std::uint64_t darts) const {
            return {b.address() + ranks, darts, b.address() + work0, b.address() + masks};
        }
    };

    // The end of a round after its resolution (engine.cpp): the commit, emission and sort, then
    // (list mode) the refinement into the next active list, which adopt makes the engine's.
    void record_emission(const shared::CellArgs& a, const shared::DartArgs& d, bool one_submit);
    Buffer record_refinement(const RoundSpec& spec, const Regions& r, std::uint64_t ranks, std::uint32_t child_side,
                             std::uint32_t fanout, const RoundSpec* next, bool worst_case);
    std::uint32_t adopt(Buffer list);
    bool prepare_counts(const RoundSpec* next, std::uint64_t n);
    void record_counts(const RoundSpec& next, const Kernel& counter, std::uint64_t targets, std::uint32_t n);
    // Mask mode's counterpart (mask_mode.cpp); with `next`, it counts the next round's darts
    // when that round runs over the same base cells.
    std::uint32_t refine_masked(const RoundSpec& spec, std::uint64_t ranks, std::uint32_t child_side,
                                std::uint32_t fanout, std::uint32_t n, std::uint64_t targets, const RoundSpec* next);
    void list_active_bases();
    // dart_cells.cpp: two radii's dart cells, and the round's darts counted over them.
    std::uint32_t list_dart_cells(const RoundSpec& spec);
    shared::CellArgs cell_args(std::uint64_t cells, const Regions& r, std::uint32_t n, std::uint32_t round,
                               std::uint32_t side, std::uint32_t param) const;
    shared::DartArgs dart_args(std::uint64_t darts, std::uint32_t count, std::uint32_t param) const;
    std::uint32_t counter(std::uint32_t slot) const {
        return static_cast<const std::uint32_t*>(counters_.mapped())[slot];
    }

    Plan plan_;
    std::uint32_t passes_per_submit_;
    std::uint32_t work_groups_;  // the most workgroups in a row of a dispatch or a pass over a work list
    std::uint64_t shut_gates_ = 0;
    ContextLease lease_;
    VulkanContext& ctx_;
    bool two_ = shared::two_radii(plan_.domain.radii);  // picks the kernels' variants (CMakeLists.txt)
    Buffer counters_, grid_;
    Buffer gate_;        // the commands of gated dispatches (round, VulkanContext::open_gate)
    Buffer cells_;       // the active cells, ordered by base cell
    bool cells_free_bases_ = false;  // cells_ is start's list of the base cells without a sample
    Buffer dart_cells_;  // two radii: the base cells that get darts this round
    Buffer samples_;     // all samples so far, in acceptance order
    Buffer scratch_;     // each round's transient arrays (see Scratch)
    Buffer darts_;       // this round's darts
    // The round whose darts the last round's final submit counted (prefix sums at the start of
    // scratch_, total in COUNTER_DARTS), if it did.
    std::optional<RoundSpec> counted_;
    Primitives primitives_{ctx_, counters_};
    // One radius runs refine_cells_one and resolve_darts_one (CMakeLists.txt); profiles name
    // both variants by their source.
    Kernel init_cells_, place_samples_, flag_dart_cells_, flag_free_cells_, list_dart_cells_, count_darts_,
        mark_ranges_, throw_sited_, work_args_, resolve_darts_, commit_cells_, emit_samples_, refine_cells_,
        scatter_cells_, count_masked_, mark_masked_, throw_sited_empty_, commit_masked_, refine_masked_,
        scatter_covers_, apply_masks_, scatter_masked_, flag_masked_, list_masked_;
    std::uint64_t emitted_ = 0;
    std::uint32_t active_ = 0;
    // Mask mode (shared/mask_mode.h) at levels 0 to MASK_LEVELS - 1, with one radius: no active list there.
    bool masked_ = false;
    Buffer base_list_;             // mask mode's last level: the base cells its kernels run over
    std::uint32_t listed_bases_ = 0;
};

}  // namespace vrpd::detail
