// The Vulkan engine: see engine.h.
#include "vulkan/vulkan_engine.h"

#include <cstddef>
#include <cstring>

#include <fmt/format.h>

#include "apply_masks.h"
#include "commit_cells.h"
#include "commit_masked.h"
#include "count_darts.h"
#include "count_masked.h"
#include "emit_samples.h"
#include "flag_dart_cells.h"
#include "flag_free_cells.h"
#include "flag_masked.h"
#include "init_cells.h"
#include "place_samples.h"
#include "list_dart_cells.h"
#include "list_masked.h"
#include "mark_masked.h"
#include "mark_ranges.h"
#include "refine_cells.h"
#include "refine_cells_one.h"
#include "refine_masked.h"
#include "resolve_darts.h"
#include "resolve_darts_one.h"
#include "scatter_cells.h"
#include "scatter_covers.h"
#include "scatter_masked.h"
#include "throw_sited.h"
#include "throw_sited_empty.h"
#include "work_args.h"

namespace vrpd::detail {

using namespace shared;

VulkanEngine::VulkanEngine(const Plan& plan, const std::string& selector, const VulkanTarget* target,
                           std::uint32_t passes_per_submit, std::uint32_t work_groups)
    : plan_(plan),
      passes_per_submit_(std::max<std::uint32_t>(passes_per_submit, 1)),
      work_groups_(std::max<std::uint32_t>(work_groups, 1)),
      lease_(selector, target),
      ctx_(lease_.get()),
      VRPD_KERNEL(init_cells, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(place_samples, DartArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(flag_dart_cells, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(flag_free_cells, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(list_dart_cells, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(count_darts, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(mark_ranges, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(throw_sited, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(work_args, WorkArgs, 1),
      resolve_darts_(ctx_, "resolve_darts",
                     two_ ? spirv_words(spirv_resolve_darts) : spirv_words(spirv_resolve_darts_one), sizeof(DartArgs),
                     WORKGROUP_SIZE),
      VRPD_KERNEL(commit_cells, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(emit_samples, DartArgs, WORKGROUP_SIZE),
      refine_cells_(ctx_, "refine_cells", two_ ? spirv_words(spirv_refine_cells) : spirv_words(spirv_refine_cells_one),
                    sizeof(CellArgs), WORKGROUP_SIZE),
      VRPD_KERNEL(scatter_cells, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(count_masked, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(mark_masked, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(throw_sited_empty, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(commit_masked, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(refine_masked, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(scatter_covers, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(apply_masks, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(scatter_masked, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(flag_masked, CellArgs, WORKGROUP_SIZE),
      VRPD_KERNEL(list_masked, CellArgs, WORKGROUP_SIZE),
      masked_(!two_radii(plan.domain.radii)) {
    if (estimated_device_bytes(plan) > ctx_.device_heap_bytes())
        throw Error(fmt::format("the run needs about {:.1f} GiB but {} has {:.1f} GiB of device memory",
                                double(estimated_device_bytes(plan)) / (1 << 30), ctx_.device_name(),
                                double(ctx_.device_heap_bytes()) / (1 << 30)));
    ctx_.set_row_groups(work_groups_);
    counters_ = Buffer(ctx_, COUNTER_WORDS * 4, true);
    gate_ = Buffer(ctx_, VulkanContext::kGateDispatches * 12, true);
    grid_ = Buffer(ctx_, plan.base_cells * sizeof(uvec2), false);
}

std::uint64_t VulkanEngine::start(const Plan& plan, const std::vector<uvec2>& initial) {
    // The kernels' variants (two_) stay the constructor's: a step's plan has two radii only if
    // the engine's has.
    plan_ = plan;
    masked_ = !two_radii(plan.domain.radii);
    listed_bases_ = 0;
    counted_.reset();
    const std::uint64_t n = plan_.base_cells;
    grow(ctx_, grid_, n * sizeof(uvec2));
    // The samples' buffer starts at the expected count and grows by a quarter if a round overflows it.
    grow(ctx_, samples_, std::max<std::uint64_t>(expected_samples(plan_), initial.size()) * sizeof(uvec2));
    // Given samples: uploaded, and (list mode) the first active list made here, leaving out the
    // base cells that hold one, whose grid word a round's darts word would replace.
    Buffer staging, list;
    std::uint64_t listed = n;
    if (!initial.empty()) {
        staging = Buffer(ctx_, initial.size() * sizeof(uvec2), true);
        std::memcpy(staging.mapped(), initial.data(), initial.size() * sizeof(uvec2));
        if (!masked_) {
            std::vector<char> occupied(n, 0);
            for (const uvec2& p : initial) occupied[base_of_point(plan_.domain, p)] = 1;
            list = Buffer(ctx_, std::max<std::uint64_t>(1, n - initial.size()) * sizeof(uvec2), true);
            auto* out = static_cast<uvec2*>(list.mapped());
            listed = 0;
            for (std::uint64_t b = 0; b < n; ++b)
                if (!occupied[b]) out[listed++] = base_corner(plan_.domain, std::uint32_t(b));
        }
    }
    if (!masked_) grow(ctx_, cells_, n * sizeof(uvec2));
    if (masked_) grow(ctx_, scratch_, n * 4);
    VkCommandBuffer cmd = ctx_.begin();
    // Every grid word starts empty: (GRID_EMPTY, GRID_EMPTY); no dart has been too complex, and
    // no base cell crowded.
    ctx_.vk().vkCmdFillBuffer(cmd, grid_.handle(), 0, VK_WHOLE_SIZE, GRID_EMPTY);
    ctx_.vk().vkCmdFillBuffer(cmd, counters_.handle(), COUNTER_TOO_COMPLEX * 4, 8, 0);
    if (masked_) {
        // Mask mode: every base cell's mask is 1, its one level-0 cell.
        ctx_.vk().vkCmdFillBuffer(cmd, scratch_.handle(), 0, n * 4, 1u);
        ctx_.barrier();  // the fills before apply_masks reads and writes them
        CellArgs a = cell_args(0, Regions{0, 0, 0, scratch_.address()}, std::uint32_t(n), 0, 0, 0);
        ctx_.dispatch(apply_masks_, &a, dispatch_groups(n, WORKGROUP_SIZE));
    } else {
        if (initial.empty()) {
            CellArgs a = cell_args(cells_.address(), {}, std::uint32_t(n), 0, 0, 0);
            ctx_.dispatch(init_cells_, &a, dispatch_groups(n, WORKGROUP_SIZE));
        } else if (listed > 0) {
            const VkBufferCopy all{0, 0, listed * sizeof(uvec2)};
            ctx_.vk().vkCmdCopyBuffer(cmd, list.handle(), cells_.handle(), 1, &all);
        }
    }
    if (!initial.empty()) {
        const VkBufferCopy all{0, 0, initial.size() * sizeof(uvec2)};
        ctx_.vk().vkCmdCopyBuffer(cmd, staging.handle(), samples_.handle(), 1, &all);
        ctx_.barrier();  // the grid's fill and masks, and the samples' copy, before place_samples
        DartArgs d = dart_args(0, std::uint32_t(initial.size()), 0);
        ctx_.dispatch(place_samples_, &d, dispatch_groups(initial.size(), WORKGROUP_SIZE));
    }
    ctx_.barrier();  // grid words and first active list before the first round reads them
    ctx_.submit_and_wait();
    emitted_ = initial.size();
    active_ = std::uint32_t(listed);
    cells_free_bases_ = !masked_;
    return listed;
}

RoundResult VulkanEngine::round(const RoundSpec& spec, const RoundSpec* next) {
    const bool two = two_radii(plan_.domain.radii);
    const bool masked = masked_;
    // One radius: the darts go to the active cells, or in mask mode to the base cells' active
    // sub-cells. Two radii: to the base cells near the active cells; to every base cell without a
    // sample while the active list is still start's list of them, which then serves (no list to
    // make, nor the submit that counts it).
    const std::uint32_t bases = std::uint32_t(plan_.base_cells);
    // Mask mode's kernels run over the base cells, or over the list of the active ones (masked.glsl).
    const bool by_list = masked && listed_bases_ > 0;
    const bool dart_cells = two && !(spec.every_free_cell && cells_free_bases_);
    const std::uint32_t n = masked ? (by_list ? listed_bases_ : bases) : (dart_cells ? list_dart_cells(spec) : active_);
    const std::uint64_t targets =
        masked ? (by_list ? base_list_.address() : 0) : (dart_cells ? dart_cells_.address() : cells_.address());
    const std::uint32_t side = two ? 1u << plan_.domain.cell_bits : spec.side;
    // Cells whose children refinement counts: the list's, or in mask mode none (the masks go
    // to the ranks region, over the base cells).
    const std::uint32_t listed = masked ? 0 : active_;
    // List mode: when the next active list is small even at its worst-case size (every cell
    // keeping all its children), this round's last submit writes it at that size, one round trip
    // fewer; with one radius it also counts the next round's darts over it (`precount`), so that
    // the next round starts with its throw, one more (two radii's darts go to the base cells near
    // the list, which the next round lists first). Larger lists (the first levels) are written at
    // their exact size.
    const bool counted = counted_ && *counted_ == spec;
    counted_.reset();
    const std::uint64_t bound = std::uint64_t(active_) * spec.fanout();
    const bool worst_case = !masked && within_share(bound * sizeof(uvec2));
    const RoundSpec* precount = !masked && !two ? next : nullptr;

    // Submit 1, unless counted: dart counts and their prefix sums.
    if (!counted) {
        grow(ctx_, scratch_, Scratch(n, 0, listed, masked).end);
        primitives_.reserve_scan(std::uint64_t(n) + 1);
        ctx_.begin();
        record_counts(spec, masked ? count_masked_ : count_darts_, targets, n);
        ctx_.submit_and_wait();
        counted_.reset();
    }
    if (counter(COUNTER_CROWDED)) throw Error("internal: a base cell got more than 65535 darts in one round");
    const std::uint32_t darts = counter(COUNTER_DARTS);
    if (darts >= MAX_ROUND_DARTS) throw Error("a round would throw more than 2^30 darts");

    // The commit shares a submit with the emission when the darts are few (an eighth
    // of the peak device memory, at the sort's 12 bytes each) and the samples' buffer has room for
    // every dart. The emission then sorts all the darts' key slots, those of darts not accepted
    // keyed past every dart (2^32 - 1, after any accepted dart by stability), for the accepted
    // count is not known when it is recorded. Else the commit takes a submit of its own, whose
    // count sizes the emission and the sort.
    const bool few = within_share(std::uint64_t(darts) * 12);
    const std::uint64_t room = (emitted_ + darts) * sizeof(uvec2);
    // Submit 2..: throw (rejecting darts covered by earlier samples), resolve in arrival order.
    const Scratch at(n, darts, listed, masked);
    // Keeps the prefix sums; makes room for the next round's (precount).
    grow(ctx_, scratch_, worst_case && precount ? std::max(at.end, (bound + 1) * 4) : at.end, true);
    primitives_.reserve_scan(std::uint64_t(std::max(darts, active_)) + 1);
    if (worst_case && precount) primitives_.reserve_scan(bound + 1);  // the next round's counts (record_refinement)
    // The darts get a buffer of their own, freed once they are emitted: the next active list
    // is then allocated in their place. When mask mode ends, refine_masked parks half of each
    // base cell's 64-bit mask there too.
    const bool leaves = masked && masked_leaves(plan_.domain, spec.child_side(), spec.fanout());
    darts_ = Buffer(ctx_, std::max<std::uint64_t>(dart_words(darts) * 4, leaves ? std::uint64_t(n) * 4 : 0), false);
    const std::uint64_t ranks = scratch_.address() + at.ranks;
    const std::uint64_t dart_list = darts_.address();
    const std::uint64_t work[2] = {scratch_.address() + at.work0, scratch_.address() + at.work1};
    // Near the end of a run, past the expected count, the samples' buffer may lack room for every
    // dart: it grows by a quarter, its copy recorded at the start of the round, if that keeps the
    // device memory within its peak so far (the sort's histogram and the next active list at its
    // worst-case size included).
    const std::uint64_t grown = std::max(room, samples_.size() + samples_.size() / 4);
    const std::uint64_t later = (worst_case ? bound * sizeof(uvec2) : 0) + Primitives::sort_bytes(darts);
    const bool grow_samples =
        few && samples_.size() < room && ctx_.allocated_bytes() + grown + later <= ctx_.peak_allocated_bytes();
    const bool one_submit = few && (samples_.size() >= room || grow_samples);
    // Gated (the deep rounds): each submit of resolution passes also carries the whole end of the
    // round, its next active list at the worst-case size, behind a gate that zeroes the end's
    // dispatches while darts are left undecided. Most such rounds are then one round trip (two
    // radii: one more, which lists the round's dart cells); one whose passes outrun a submit runs
    // the end with the submit that finishes them.
    const bool gated = one_submit && worst_case;
    if (one_submit) primitives_.reserve_sort(darts);
    VkCommandBuffer cmd = ctx_.begin();
    Buffer spent_samples;  // the samples' buffer before grow_samples, kept until the round's submits end
    if (grow_samples) {
        spent_samples = std::move(samples_);
        samples_ = Buffer(ctx_, grown, false);
        const VkBufferCopy all{0, 0, emitted_ * sizeof(uvec2)};
        if (emitted_ > 0) ctx_.vk().vkCmdCopyBuffer(cmd, spent_samples.handle(), samples_.handle(), 1, &all);
    }
    ctx_.vk().vkCmdFillBuffer(cmd, darts_.handle(), 0, VK_WHOLE_SIZE, 0);  // the darts' states start undecided
    ctx_.vk().vkCmdFillBuffer(cmd, counters_.handle(), (COUNTER_WORK0 + 3) * 4, 4, 0);
    ctx_.vk().vkCmdFillBuffer(cmd, counters_.handle(), COUNTER_ACTIVE * 4, 4, 0);  // refine_masked's sum
    ctx_.barrier();  // the zeroed darts before the marking writes their sites
    // param: exp(-lambda) for mark_masked, which counts each sub-cell's darts again for their sites.
    CellArgs a = cell_args(targets, at.in(scratch_, dart_list), n, spec.round, side, spec.exp_neg_lambda);
    ctx_.dispatch(masked ? mark_masked_ : mark_ranges_, &a, dispatch_groups(n, WORKGROUP_SIZE));
    ctx_.barrier();  // dart ranges, sites and the empty work list before throw_sited reads and appends
    CellArgs per_dart = a;
    per_dart.cell_count = darts;
    ctx_.dispatch(emitted_ == 0 ? throw_sited_empty_ : throw_sited_, &per_dart, dispatch_groups(darts, WORKGROUP_SIZE));
    ctx_.barrier();  // darts, grid dart ranges and work list before resolution
    const std::uint32_t fanout = spec.fanout(), child_side = spec.child_side();
    a.param = darts;  // the commit kernels end the flags with a 0 at flags[darts]
    DartArgs d = dart_args(dart_list, darts, std::uint32_t(emitted_));
    d.scan = ranks;
    d.sample_keys = scratch_.address() + at.keys;
    const Regions regions = at.in(scratch_, 0);
    // List mode: the round's end up to its last submit; returns the next active list.
    auto record_end = [&] {
        record_emission(a, d, one_submit);
        return record_refinement(spec, regions, ranks, child_side, fanout, precount, worst_case);
    };
    Buffer list;  // gated: the next active list
    std::uint32_t in = 0;
    // Each pass decides at least the earliest undecided dart, so `darts` passes end any round;
    // more means corrupted states (a bug), which fails the run instead of looping.
    for (std::uint64_t passes = 0;; passes += passes_per_submit_) {
        if (passes > darts) throw Error("internal: the resolution of a round did not end");
        for (std::uint32_t p = 0; p < passes_per_submit_; ++p, in ^= 1) {
            const std::uint32_t in_slot = in ? COUNTER_WORK1 : COUNTER_WORK0;
            const std::uint32_t out_slot = in ? COUNTER_WORK0 : COUNTER_WORK1;
            WorkArgs w{counters_.address(), in_slot, out_slot, work_groups_};
            ctx_.dispatch(work_args_, &w, 1);
            ctx_.barrier();  // indirect command and emptied output list before the pass
            DartArgs r = dart_args(dart_list, darts, passes == 0 && p == 0 ? 1u : 0u);
            r.work_in = work[in];
            r.work_out = work[in ^ 1];
            r.work_in_slot = in_slot;
            r.work_out_slot = out_slot;
            ctx_.dispatch_indirect(resolve_darts_, &r, counters_, in_slot * 4);
            ctx_.barrier();  // states and the next work list before the next pass
        }
        const std::uint32_t undecided = (in ? COUNTER_WORK1 : COUNTER_WORK0) + 3;
        if (gated) {
            ctx_.open_gate(gate_, counters_.address(), undecided);
            list = record_end();
            ctx_.close_gate();
        }
        ctx_.submit_and_wait();
        if (counter(undecided) == 0) break;
        if (gated) ++shut_gates_;
        ctx_.begin();
    }
    if (gated) {
        active_ = adopt(std::move(list));
    } else if (masked) {
        ctx_.begin();
        record_emission(a, d, one_submit);
        active_ = refine_masked(spec, ranks, child_side, fanout, n, targets, next);
    } else {
        ctx_.begin();
        list = record_end();
        ctx_.submit_and_wait();
        active_ = adopt(std::move(list));
    }
    // Two radii: a dart whose T test passed its bounds (flagged by the commit) fails the run.
    if (counter(COUNTER_TOO_COMPLEX)) throw Error(kTooComplex);
    emitted_ += counter(COUNTER_ACCEPTED);
    return {darts, active_};
}

// Records the commit (grid words become samples or empty again; the accepted darts are flagged
// and ranked), the emission of the accepted darts as samples and their sort into arrival order,
// into the submit begun. Unless `one_submit`, the commit is submitted first and its count sizes
// the rest.
void VulkanEngine::record_emission(const CellArgs& a, const DartArgs& d, bool one_submit) {
    const std::uint32_t darts = d.dart_count;
    ctx_.dispatch(masked_ ? commit_masked_ : commit_cells_, &a, dispatch_groups(a.cell_count, WORKGROUP_SIZE));
    ctx_.barrier();  // accepted flags and grid words before the scan
    primitives_.scan(d.scan, std::uint64_t(darts) + 1, COUNTER_ACCEPTED);
    if (!one_submit) {
        ctx_.submit_and_wait();
        const std::uint64_t need = (emitted_ + counter(COUNTER_ACCEPTED)) * sizeof(uvec2);
        if (samples_.size() < need) grow(ctx_, samples_, std::max(need, samples_.size() + samples_.size() / 4), true);
        primitives_.reserve_sort(counter(COUNTER_ACCEPTED));
        ctx_.begin();
    }
    DartArgs e = d;
    e.samples = samples_.address();
    ctx_.dispatch(emit_samples_, &e, dispatch_groups(darts, WORKGROUP_SIZE));
    ctx_.barrier();  // the round's samples and keys before the sort; the ranks are read
    // The round's samples into arrival order (stable by key), through the spent darts' buffer.
    const std::uint32_t sorted = one_submit ? darts : counter(COUNTER_ACCEPTED);
    if (sorted > 1)
        primitives_.sort(e.samples + emitted_ * sizeof(uvec2), e.sample_keys, e.darts, sorted, COUNTER_SORT);
}

std::vector<uvec2> VulkanEngine::samples() {
    // The round's working memory is not needed for the read-back: free it first.
    scratch_ = Buffer();
    primitives_.release_sort();
    darts_ = Buffer();
    std::vector<uvec2> out(emitted_);
    if (emitted_ == 0) return out;
    Buffer staging(ctx_, emitted_ * sizeof(uvec2), true);
    VkCommandBuffer cmd = ctx_.begin();
    VkBufferCopy all{0, 0, emitted_ * sizeof(uvec2)};
    ctx_.vk().vkCmdCopyBuffer(cmd, samples_.handle(), staging.handle(), 1, &all);
    ctx_.barrier();  // the copy before the host reads the staging buffer
    ctx_.submit_and_wait();
    std::memcpy(out.data(), staging.mapped(), emitted_ * sizeof(uvec2));
    return out;
}

// Records the count of each listed active cell's surviving children and the writing of the
// next active list, which it returns: at its worst-case size in the submit begun, or at its
// exact size (in the place of the spent darts) after a submit of the counts. With `next`, it
// also counts the next round's darts over the list (when the scratch buffer holds the counts).
// The caller's submit ends the recording; adopt then makes the list the engine's.
Buffer VulkanEngine::record_refinement(const RoundSpec& spec, const Regions& r, std::uint64_t ranks,
                                       std::uint32_t child_side, std::uint32_t fanout, const RoundSpec* next,
                                       bool worst_case) {
    const std::uint32_t active = active_;
    if (std::uint64_t(active) * fanout >= GRID_TAG) throw Error("more than 2^31 active cells");
    CellArgs a = cell_args(cells_.address(), r, active, spec.round, child_side, fanout);
    ctx_.dispatch(refine_cells_, &a, dispatch_groups(std::uint64_t(active) + 1, WORKGROUP_SIZE));
    ctx_.barrier();  // surviving-children counts and masks before their scan
    primitives_.scan(ranks, std::uint64_t(active) + 1, COUNTER_ACTIVE);
    Buffer list;
    std::uint64_t length = std::uint64_t(active) * fanout;
    bool count = next != nullptr;  // worst case: round made room for the counts and their scan
    if (worst_case) {
        // The entries past the kept cells stay (GRID_EMPTY, GRID_EMPTY), which count_darts gives
        // no darts: the counts' prefix sums over the whole list end in the next round's total,
        // and their first kept + 1 are that round's.
        list = Buffer(ctx_, length * sizeof(uvec2), false);
        ctx_.vk().vkCmdFillBuffer(ctx_.recording(), list.handle(), 0, VK_WHOLE_SIZE, GRID_EMPTY);
        ctx_.barrier();  // the fill and the ranks before the scatter
    } else {
        ctx_.submit_and_wait();
        darts_ = Buffer();
        length = counter(COUNTER_ACTIVE);
        list = Buffer(ctx_, length * sizeof(uvec2), false);
        count = prepare_counts(next, length);
        ctx_.begin();
    }
    a.cells_out = list.address();
    ctx_.dispatch(scatter_cells_, &a, dispatch_groups(active, WORKGROUP_SIZE));
    ctx_.barrier();  // the next active list before the next round and the host; the ranks are read
    if (count) record_counts(*next, count_darts_, list.address(), std::uint32_t(length));
    return list;
}

// After the submit that wrote it: `list` becomes the active list, the spent darts are freed.
// Returns the list's length.
std::uint32_t VulkanEngine::adopt(Buffer list) {
    darts_ = Buffer();
    cells_ = std::move(list);
    cells_free_bases_ = false;
    return counter(COUNTER_ACTIVE);
}

// Can the next round's darts be counted over n targets in the submit about to be recorded? Only
// with `next`, and where the scratch buffer holds their n + 1 counts; then reserves their scan,
// which must happen before recording begins.
bool VulkanEngine::prepare_counts(const RoundSpec* next, std::uint64_t n) {
    if (!next || scratch_.size() < (n + 1) * 4) return false;
    primitives_.reserve_scan(n + 1);
    return true;
}

// Records the counting of round `next`'s darts over the `n` targets at `targets` by `counter`
// (count_darts or count_masked), as round's first submit does: the prefix sums at the start of
// the scratch buffer (n + 1 words; the caller reserved the scan), the total in COUNTER_DARTS.
// That round then skips its first submit.
void VulkanEngine::record_counts(const RoundSpec& next, const Kernel& counter, std::uint64_t targets,
                                 std::uint32_t n) {
    CellArgs c = cell_args(targets, Regions{scratch_.address(), 0, 0, 0}, n, next.round, next.side,
                           next.exp_neg_lambda);
    ctx_.dispatch(counter, &c, dispatch_groups(std::uint64_t(n) + 1, WORKGROUP_SIZE));
    ctx_.barrier();  // counts before their scan
    primitives_.scan(scratch_.address(), std::uint64_t(n) + 1, COUNTER_DARTS);
    counted_ = next;
}

CellArgs VulkanEngine::cell_args(std::uint64_t cells, const Regions& r, std::uint32_t n, std::uint32_t round,
                   std::uint32_t side, std::uint32_t param) const {
    return {plan_.domain, cells, 0, r.darts, r.scan, grid_.address(), r.work, counters_.address(), r.masks,
            n, round_key(plan_.seed, round), side, param};
}

DartArgs VulkanEngine::dart_args(std::uint64_t darts, std::uint32_t count, std::uint32_t param) const {
    return {plan_.domain, darts, grid_.address(), 0, 0, counters_.address(), 0, samples_.address(), 0, count, 0, 0,
            param};
}

std::unique_ptr<Engine> make_vulkan_engine(const Plan& plan, const std::string& device, const VulkanTarget* target) {
    return std::make_unique<VulkanEngine>(plan, device, target);
}

}  // namespace vrpd::detail
