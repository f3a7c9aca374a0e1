// The Vulkan engine: each round of the schedule as three submits of compute dispatches over
// compacted lists (active cells, darts, undecided darts). The host reads back only counts.
#include <array>
#include <cstddef>
#include <cstring>

#include <fmt/format.h>

#include "engine.h"
#include "shared/kernels.h"
#include "vulkan_context.h"

#include "apply_decisions.h"
#include "commit_cells.h"
#include "count_darts.h"
#include "emit_samples.h"
#include "flag_dart_cells.h"
#include "flag_free_cells.h"
#include "init_cells.h"
#include "list_dart_cells.h"
#include "mark_ranges.h"
#include "refine_cells.h"
#include "resolve_darts.h"
#include "scan_add.h"
#include "scan_blocks.h"
#include "scan_sums.h"
#include "scatter_cells.h"
#include "sort_histogram.h"
#include "sort_scatter.h"
#include "throw_darts.h"
#include "work_args.h"

namespace vrpd::detail {
namespace {

using namespace shared;

// Push-constant layouts must match std430 as glslang lays them out.
static_assert(sizeof(Domain) == 48 && offsetof(Domain, cover2) == 8 && offsetof(Domain, lattice_x) == 16 &&
              offsetof(Domain, seed) == 44);
static_assert(sizeof(CellArgs) == 128 && offsetof(CellArgs, cells) == 48 && offsetof(CellArgs, cell_count) == 112);
static_assert(sizeof(DartArgs) == 128 && offsetof(DartArgs, darts) == 48 && offsetof(DartArgs, dart_count) == 112);
static_assert(sizeof(ScanArgs) == 40 && offsetof(ScanArgs, count) == 24);
static_assert(sizeof(WorkArgs) == 16 && offsetof(WorkArgs, slot) == 8);
static_assert(sizeof(SortArgs) == 56 && offsetof(SortArgs, count) == 40);
static_assert(sizeof(CellArgs) <= 128 && sizeof(DartArgs) <= 128, "push constants: 128 bytes is the guaranteed minimum");

constexpr std::uint32_t kResolvePassesPerSubmit = 4;

std::uint32_t groups(std::uint64_t n, std::uint32_t per_group) { return std::uint32_t((n + per_group - 1) / per_group); }

template <std::size_t N> std::span<const std::uint32_t> words(const std::uint32_t (&code)[N]) { return {code, N}; }

class VulkanEngine final : public Engine {
public:
    VulkanEngine(const Plan& plan, const std::string& selector) : plan_(plan), ctx_(selector) {
        if (estimated_device_bytes(plan) > ctx_.device_heap_bytes())
            throw Error(fmt::format("the run needs about {:.1f} GiB but {} has {:.1f} GiB of device memory",
                                    double(estimated_device_bytes(plan)) / (1 << 30), ctx_.device_name(),
                                    double(ctx_.device_heap_bytes()) / (1 << 30)));
        counters_ = Buffer(ctx_, COUNTER_WORDS * 4, true);
        grid_ = Buffer(ctx_, plan.base_cells * sizeof(uvec2), false);
    }

    std::string device_name() const override { return ctx_.device_name(); }

    std::uint64_t start() override {
        const std::uint64_t n = plan_.base_cells;
        ensure(cells_[0], n * sizeof(uvec2));
        VkCommandBuffer cmd = ctx_.begin();
        // Every grid word starts empty: (GRID_EMPTY, GRID_EMPTY); no dart has been too complex.
        ctx_.vk().vkCmdFillBuffer(cmd, grid_.handle(), 0, VK_WHOLE_SIZE, GRID_EMPTY);
        ctx_.vk().vkCmdFillBuffer(cmd, counters_.handle(), COUNTER_TOO_COMPLEX * 4, 4, 0);
        CellArgs a = cell_args(cells_[0], std::uint32_t(n), 0, 0, 0);
        ctx_.dispatch(init_cells_, &a, groups(n, WORKGROUP_SIZE));
        ctx_.barrier();  // grid fill and first active list before the first round reads them
        ctx_.submit_and_wait();
        active_ = std::uint32_t(n);
        return n;
    }

    RoundResult round(const RoundSpec& spec) override {
        const bool two = two_radii(plan_.domain);
        // One radius: the darts go to the active cells. Two: to the base cells near them.
        const std::uint32_t n = two ? list_dart_cells(spec) : active_;
        const Buffer& targets = two ? dart_cells_ : cells_[0];
        const std::uint32_t side = two ? 1u << plan_.domain.cell_bits : spec.side;
        ensure_scan(std::uint64_t(n) + 1, false);

        // Submit 1: dart counts and their prefix sums.
        ctx_.begin();
        CellArgs a = cell_args(targets, n, spec.round, side, spec.exp_neg_lambda);
        ctx_.dispatch(count_darts_, &a, groups(std::uint64_t(n) + 1, WORKGROUP_SIZE));
        ctx_.barrier();  // counts before the scan
        scan(scan_, std::uint64_t(n) + 1, COUNTER_DARTS);
        ctx_.submit_and_wait();
        const std::uint32_t darts = counter(COUNTER_DARTS);
        if (darts >= MAX_ROUND_DARTS) throw Error("a round would throw more than 2^30 darts");

        // Submit 2..: throw (rejecting darts covered by earlier samples), resolve in arrival order.
        ensure_scan(std::uint64_t(darts) + 1, true);
        ensure(darts_, std::uint64_t(darts) * sizeof(uvec4));
        ensure(work_[0], std::uint64_t(darts) * 4);
        ensure(work_[1], std::uint64_t(darts) * 4);
        VkCommandBuffer cmd = ctx_.begin();
        ctx_.vk().vkCmdFillBuffer(cmd, counters_.handle(), (COUNTER_WORK0 + 3) * 4, 4, 0);
        a = cell_args(targets, n, spec.round, side, darts);
        ctx_.dispatch(mark_ranges_, &a, groups(n, WORKGROUP_SIZE));
        ctx_.barrier();  // dart ranges and the empty work list before throw_darts reads and appends
        ctx_.dispatch(throw_darts_, &a, groups(n, WORKGROUP_SIZE));
        ctx_.barrier();  // darts, grid dart ranges and work list before resolution
        DartArgs d;
        std::uint32_t in = 0;
        for (;;) {
            for (std::uint32_t p = 0; p < kResolvePassesPerSubmit; ++p, in ^= 1) {
                const std::uint32_t in_slot = in ? COUNTER_WORK1 : COUNTER_WORK0;
                const std::uint32_t out_slot = in ? COUNTER_WORK0 : COUNTER_WORK1;
                WorkArgs w{counters_.address(), in_slot, out_slot};
                ctx_.dispatch(work_args_, &w, 1);
                ctx_.barrier();  // indirect command and emptied output list before the pass
                d = dart_args(darts, in_slot, out_slot, 0);
                d.work_in = work_[in].address();
                d.work_out = work_[in ^ 1].address();
                ctx_.dispatch_indirect(resolve_darts_, &d, counters_, in_slot * 4);
                ctx_.barrier();  // decisions before they are applied
                ctx_.dispatch_indirect(apply_decisions_, &d, counters_, in_slot * 4);
                ctx_.barrier();  // states and the next work list before the next pass
            }
            ctx_.submit_and_wait();
            if (counter((in ? COUNTER_WORK1 : COUNTER_WORK0) + 3) == 0) break;
            ctx_.begin();
        }

        // Last submit: commit, emit the accepted darts as samples, keep or refine the cells.
        const std::uint32_t active = active_;
        const std::uint32_t fanout = spec.refine ? 4 : 1;
        const std::uint64_t slots = std::uint64_t(active) * fanout;
        if (slots >= GRID_TAG) throw Error("more than 2^31 active cells");
        ensure_scan(std::uint64_t(std::max(darts, active)) + 1, true);
        ensure(masks_, std::uint64_t(active) * 4);
        ensure(samples_, (emitted_ + darts) * sizeof(uvec2), true);
        ensure(keys_, std::uint64_t(darts) * 4);
        ensure(cells_[1], slots * sizeof(uvec2));
        ctx_.begin();
        ctx_.dispatch(commit_cells_, &a, groups(n, WORKGROUP_SIZE));
        ctx_.barrier();  // accepted flags and grid words before the scan and the cover tests
        scan(scan_, std::uint64_t(darts) + 1, COUNTER_ACCEPTED);
        d = dart_args(darts, 0, 0, std::uint32_t(emitted_));
        ctx_.dispatch(emit_samples_, &d, groups(darts, WORKGROUP_SIZE));
        ctx_.barrier();  // emission has read the flags' ranks before refine overwrites them
        const std::uint32_t child_side = spec.refine ? spec.side / 2 : spec.side;
        a = cell_args(cells_[0], active, spec.round, child_side, fanout);
        ctx_.dispatch(refine_cells_, &a, groups(std::uint64_t(active) + 1, WORKGROUP_SIZE));
        ctx_.barrier();  // surviving-children counts and masks before their scan
        scan(scan_, std::uint64_t(active) + 1, COUNTER_ACTIVE);
        ctx_.dispatch(scatter_cells_, &a, groups(active, WORKGROUP_SIZE));
        ctx_.barrier();  // the next active list before the next round and the host
        ctx_.submit_and_wait();
        if (counter(COUNTER_TOO_COMPLEX)) throw Error(kTooComplex);
        const std::uint32_t accepted = counter(COUNTER_ACCEPTED);
        sort_round(accepted);
        emitted_ += accepted;
        active_ = counter(COUNTER_ACTIVE);
        std::swap(cells_[0], cells_[1]);
        return {darts, active_};
    }

    std::vector<uvec2> samples() override {
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

private:
    // Two radii: lists the base cells that get darts this round (flag_dart_cells or
    // flag_free_cells, a scan of the flags, list_dart_cells) and returns their count.
    std::uint32_t list_dart_cells(const RoundSpec& spec) {
        const std::uint64_t bases = plan_.base_cells;
        ensure(flags_, (bases + 1) * 4);
        ensure(block_sums_, std::uint64_t(groups(bases + 1, SCAN_BLOCK)) * 4);
        ensure(dart_cells_, bases * sizeof(uvec2));
        VkCommandBuffer cmd = ctx_.begin();
        CellArgs a = cell_args(cells_[0], active_, spec.round, spec.side, 0);
        a.scan = flags_.address();
        if (spec.every_free_cell) {
            a.cell_count = std::uint32_t(bases);
            ctx_.dispatch(flag_free_cells_, &a, groups(bases + 1, WORKGROUP_SIZE));
        } else {
            ctx_.vk().vkCmdFillBuffer(cmd, flags_.handle(), 0, (bases + 1) * 4, 0);
            ctx_.barrier();  // cleared flags before they are set
            ctx_.dispatch(flag_dart_cells_, &a, groups(std::uint64_t(active_) + 1, WORKGROUP_SIZE));
        }
        ctx_.barrier();  // flags before their scan
        scan(flags_, bases + 1, COUNTER_DART_CELLS);
        a = cell_args(cells_[0], std::uint32_t(bases), spec.round, spec.side, 0);
        a.scan = flags_.address();
        a.cells_out = dart_cells_.address();
        ctx_.dispatch(list_dart_cells_, &a, groups(bases, WORKGROUP_SIZE));
        ctx_.barrier();  // the list before the round's kernels read it
        ctx_.submit_and_wait();
        return counter(COUNTER_DART_CELLS);
    }

    CellArgs cell_args(const Buffer& cells, std::uint32_t n, std::uint32_t round, std::uint32_t side, std::uint32_t param) const {
        return {plan_.domain, cells.address(), cells_[1].address(), darts_.address(), scan_.address(),
                grid_.address(), work_[0].address(), counters_.address(), masks_.address(), n, round, side, param};
    }

    DartArgs dart_args(std::uint32_t darts, std::uint32_t in_slot, std::uint32_t out_slot, std::uint32_t base) const {
        return {plan_.domain, darts_.address(), grid_.address(), work_[0].address(), work_[0].address(),
                counters_.address(), scan_.address(), samples_.address(), keys_.address(), darts, in_slot, out_slot, base};
    }

    std::uint32_t counter(std::uint32_t slot) const { return static_cast<const std::uint32_t*>(counters_.mapped())[slot]; }

    // Exclusive prefix sum of data[0, count) in place; the total goes to counters[total_slot].
    void scan(Buffer& data, std::uint64_t count, std::uint32_t total_slot) {
        const std::uint32_t blocks = groups(count, SCAN_BLOCK);
        if (data.size() < count * 4 || block_sums_.size() < std::uint64_t(blocks) * 4)
            throw Error("internal: scan buffers not sized before recording");
        ScanArgs s{data.address(), block_sums_.address(), counters_.address(), std::uint32_t(count), blocks, total_slot, 0};
        ctx_.dispatch(scan_blocks_, &s, blocks);
        ctx_.barrier();  // block scans and sums before the sums are scanned
        ctx_.dispatch(scan_sums_, &s, 1);
        ctx_.barrier();  // block offsets before they are added
        ctx_.dispatch(scan_add_, &s, groups(count, WORKGROUP_SIZE));
        ctx_.barrier();  // the prefix sums before their readers
    }

    // Puts this round's `count` samples (at emitted_, emitted in spatial order) in arrival order:
    // a stable radix sort by key on the device, 4 passes of 8 bits, ping-ponging with sort_tmp_.
    void sort_round(std::uint32_t count) {
        if (count < 2) return;
        const std::uint32_t tiles = groups(count, SCAN_BLOCK);
        const std::uint64_t bins = std::uint64_t(SORT_BUCKETS) * tiles;
        ensure(sort_points_, std::uint64_t(count) * sizeof(uvec2));
        ensure(sort_keys_, std::uint64_t(count) * 4);
        ensure(histogram_, (bins + 1) * 4);
        ensure(block_sums_, std::uint64_t(groups(bins + 1, SCAN_BLOCK)) * 4);
        const std::uint64_t points = samples_.address() + emitted_ * sizeof(uvec2);
        SortArgs s{points, keys_.address(), sort_points_.address(), sort_keys_.address(), histogram_.address(),
                   count, 0, tiles, 0};
        ctx_.begin();
        for (std::uint32_t pass = 0; pass < 4; ++pass) {
            s.shift = 8 * pass;
            ctx_.dispatch(sort_histogram_, &s, tiles);
            ctx_.barrier();  // digit counts before their scan
            scan(histogram_, bins, COUNTER_SORT);
            ctx_.dispatch(sort_scatter_, &s, tiles);
            ctx_.barrier();  // this pass's output before the next pass reads it
            std::swap(s.src_points, s.dst_points);
            std::swap(s.src_keys, s.dst_keys);
        }
        ctx_.submit_and_wait();
    }

    // The scan buffer (kept when it holds prefix sums still to be read) and its block sums.
    void ensure_scan(std::uint64_t count, bool preserve) {
        ensure(scan_, count * 4, preserve);
        ensure(block_sums_, std::uint64_t(groups(count, SCAN_BLOCK)) * 4);
    }

    // Grows a buffer to at least `bytes` (doubling), optionally keeping its contents. Never called
    // while recording: a replaced buffer may not be referenced by a pending command buffer.
    void ensure(Buffer& b, std::uint64_t bytes, bool preserve = false) {
        if (b.size() >= bytes && b.handle()) return;
        Buffer bigger(ctx_, std::max<std::uint64_t>(bytes, b.size() * 2), false);
        if (preserve && b.size() > 0) {
            VkCommandBuffer cmd = ctx_.begin();
            VkBufferCopy all{0, 0, b.size()};
            ctx_.vk().vkCmdCopyBuffer(cmd, b.handle(), bigger.handle(), 1, &all);
            ctx_.barrier();  // the copy before later shader use
            ctx_.submit_and_wait();
        }
        b = std::move(bigger);
    }

    Plan plan_;
    VulkanContext ctx_;
    Kernel init_cells_{ctx_, words(spirv_init_cells), sizeof(CellArgs), WORKGROUP_SIZE};
    Kernel flag_dart_cells_{ctx_, words(spirv_flag_dart_cells), sizeof(CellArgs), WORKGROUP_SIZE};
    Kernel flag_free_cells_{ctx_, words(spirv_flag_free_cells), sizeof(CellArgs), WORKGROUP_SIZE};
    Kernel list_dart_cells_{ctx_, words(spirv_list_dart_cells), sizeof(CellArgs), WORKGROUP_SIZE};
    Kernel count_darts_{ctx_, words(spirv_count_darts), sizeof(CellArgs), WORKGROUP_SIZE};
    Kernel mark_ranges_{ctx_, words(spirv_mark_ranges), sizeof(CellArgs), WORKGROUP_SIZE};
    Kernel apply_decisions_{ctx_, words(spirv_apply_decisions), sizeof(DartArgs), WORKGROUP_SIZE};
    Kernel throw_darts_{ctx_, words(spirv_throw_darts), sizeof(CellArgs), WORKGROUP_SIZE};
    Kernel work_args_{ctx_, words(spirv_work_args), sizeof(WorkArgs), 1};
    Kernel resolve_darts_{ctx_, words(spirv_resolve_darts), sizeof(DartArgs), WORKGROUP_SIZE};
    Kernel commit_cells_{ctx_, words(spirv_commit_cells), sizeof(CellArgs), WORKGROUP_SIZE};
    Kernel emit_samples_{ctx_, words(spirv_emit_samples), sizeof(DartArgs), WORKGROUP_SIZE};
    Kernel refine_cells_{ctx_, words(spirv_refine_cells), sizeof(CellArgs), WORKGROUP_SIZE};
    Kernel scatter_cells_{ctx_, words(spirv_scatter_cells), sizeof(CellArgs), WORKGROUP_SIZE};
    Kernel scan_blocks_{ctx_, words(spirv_scan_blocks), sizeof(ScanArgs), 64};
    Kernel scan_sums_{ctx_, words(spirv_scan_sums), sizeof(ScanArgs), 64};
    Kernel scan_add_{ctx_, words(spirv_scan_add), sizeof(ScanArgs), 64};
    Kernel sort_histogram_{ctx_, words(spirv_sort_histogram), sizeof(SortArgs), 64};
    Kernel sort_scatter_{ctx_, words(spirv_sort_scatter), sizeof(SortArgs), 1};
    Buffer flags_, dart_cells_;  // two radii: per base cell flags, and the cells that get darts
    Buffer counters_, grid_, darts_, scan_, block_sums_, masks_, samples_, keys_, sort_points_, sort_keys_, histogram_;
    std::array<Buffer, 2> cells_, work_;
    std::uint64_t emitted_ = 0;
    std::uint32_t active_ = 0;
};

}  // namespace

std::unique_ptr<Engine> make_vulkan_engine(const Plan& plan, const std::string& device) {
    return std::make_unique<VulkanEngine>(plan, device);
}

}  // namespace vrpd::detail
