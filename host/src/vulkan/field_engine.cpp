// The sizing-field sampler on a Vulkan device: a round's steps (field_vulkan.h).
#include <bit>
#include <cstring>

#include <fmt/format.h>

#include "field/power_sum.h"
#include "field_accepted.h"
#include "field_accepted_kinks.h"
#include "field_balance.h"
#include "field_balance_kinks.h"
#include "field_compact.h"
#include "field_compact_kinks.h"
#include "field_count_darts.h"
#include "field_count_darts_kinks.h"
#include "field_emit.h"
#include "field_emit_kinks.h"
#include "field_fates.h"
#include "field_fates_kinks.h"
#include "field_first_darts.h"
#include "field_first_darts_kinks.h"
#include "field_histogram.h"
#include "field_histogram_kinks.h"
#include "field_place.h"
#include "field_place_kinks.h"
#include "field_resolve.h"
#include "field_resolve_kinks.h"
#include "field_scatter.h"
#include "field_scatter_kinks.h"
#include "field_throw.h"
#include "field_throw_kinks.h"
#include "field_touch.h"
#include "field_touch_kinks.h"
#include "field_triage.h"
#include "field_triage_kinks.h"
#include "field_unmark.h"
#include "field_unmark_kinks.h"
#include "vulkan/field_vulkan.h"
#include "work_args.h"

namespace vrpd::detail {

using namespace shared;
using field::ExponentCounts;

static_assert(sizeof(FieldArgs) == 80 && offsetof(FieldArgs, count) == 56 && offsetof(FieldArgs, p2) == 72);
static_assert(sizeof(FieldRun) == 216 && offsetof(FieldRun, tree) == 104 && offsetof(FieldRun, lattice) == 136 &&
              offsetof(FieldRun, leaf_sample) == 168 && offsetof(FieldRun, keys) == 200 &&
              offsetof(FieldRun, leaf_first) == 208);

namespace {
constexpr std::uint32_t kPassesPerSubmit = 4;
// Search steps an invocation may take on lavapipe, whose loops stop after 65 535 passes of a
// SIMD vector of 8 invocations (shared/field_search.h): a vector passes its loops at most as often
// as its lanes do in all, and a lane's passes are its steps and a few hundred in loops of fixed
// length, so 8 x (6 000 + 500) stays below the limit. Elsewhere searches are not cut short.
constexpr std::uint32_t kLavapipeBudget = 6000;
}  // namespace

std::uint32_t FieldVulkan::variant_of(const SampleOptions& o) {
    return field_variant(std::uint32_t(o.sizing->rule), o.box.boundary == Boundary::Periodic,
                         o.sizing->weighting == Weighting::Density);
}

// The initializer of field kernel member name_: its build for kinked cells (NAME_kinks) where the
// tables have them, in the run's variant.
#define VRPD_FIELD_KERNEL(name)                                                                                     \
    name##_(ctx_, #name, kinks_ ? spirv_words(spirv_##name##_kinks) : spirv_words(spirv_##name), sizeof(FieldArgs), \
            WORKGROUP_SIZE, variant_of(o))

FieldVulkan::FieldVulkan(const SampleOptions& o, bool kinks, std::uint32_t budget, std::uint32_t work_groups)
    : o_(o),
      kinks_(kinks),
      lease_(o.device, o.vulkan),
      ctx_(lease_.get()),
      counters_(ctx_, FIELD_COUNTER_WORDS * 4, true),
      primitives_(ctx_, counters_),
      VRPD_FIELD_KERNEL(field_histogram),
      VRPD_FIELD_KERNEL(field_fates),
      VRPD_FIELD_KERNEL(field_balance),
      VRPD_FIELD_KERNEL(field_scatter),
      VRPD_FIELD_KERNEL(field_count_darts),
      VRPD_FIELD_KERNEL(field_throw),
      VRPD_FIELD_KERNEL(field_compact),
      VRPD_FIELD_KERNEL(field_first_darts),
      VRPD_FIELD_KERNEL(field_resolve),
      VRPD_FIELD_KERNEL(field_unmark),
      VRPD_FIELD_KERNEL(field_accepted),
      VRPD_FIELD_KERNEL(field_emit),
      VRPD_FIELD_KERNEL(field_touch),
      VRPD_FIELD_KERNEL(field_place),
      VRPD_FIELD_KERNEL(field_triage),
      VRPD_KERNEL(work_args, WorkArgs, 1),
      density_(o.sizing->weighting == Weighting::Density) {
    if (o.profile) ctx_.start_profile();
    gate_ = Buffer(ctx_, VulkanContext::kGateDispatches * 12, true);
    exp_table_ = Buffer(ctx_, 128 * 4, true);
    work_groups_ = work_groups != 0 ? work_groups : kMaxWorkgroups;
    ctx_.set_row_groups(work_groups_);
    budget_ = budget != 0                                                ? budget
              : ctx_.device_name().find("llvmpipe") != std::string::npos ? kLavapipeBudget
                                                                         : UINT32_MAX - 1;
}

Buffer FieldVulkan::upload(const void* data, std::uint64_t bytes, std::vector<Buffer>& staging) {
    Buffer b(ctx_, std::max<std::uint64_t>(bytes, 16), false);
    if (bytes == 0) return b;
    Buffer& s = staging.emplace_back(ctx_, bytes, true);
    std::memcpy(s.mapped(), data, bytes);
    const VkBufferCopy all{0, 0, bytes};
    ctx_.vk().vkCmdCopyBuffer(ctx_.recording(), s.handle(), b.handle(), 1, &all);
    return b;
}

void FieldVulkan::check_budget() const {
    if (counters()[FIELD_COUNTER_OVERFLOW] != 0)
        throw Error(
            fmt::format("a search of the field's kernels passed its {} steps on {}: this field is too steep "
                        "for the device; use --device cpu",
                        run_args_.budget, ctx_.device_name()));
}

void FieldVulkan::clear_counters(std::uint32_t from) {
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), counters_.handle(), from * 4, (FIELD_COUNTER_WORDS - from) * 4, 0);
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), counters_.handle(), FIELD_COUNTER_LEAST_BITS * 4, 4, UINT32_MAX);
    ctx_.barrier();
}

void FieldVulkan::write_run() {
    run_args_.points = device_ref<FieldPoints>(points_.address());
    run_args_.radii = device_ref<FieldWords>(radii_.address());
    std::memcpy(run_.mapped(), &run_args_, sizeof(run_args_));
}

std::uint32_t FieldVulkan::weight(glm::uvec2 corner, std::uint32_t bits) const {
    if (!density_) return 0;
    return field_cell_weight(t_->r_lo, t_->min_over(corner, field_far_corner(t_->lattice, corner, bits)));
}

double FieldVulkan::weighted_area(const ExponentCounts& e) {
    if (const auto sum = field::exact_power_sum(e, field::kExponentBias)) return *sum;
    // As the host adds them: each cell's 2^exponent in list order.
    Buffer copy(ctx_, active_ * 8, true);
    ctx_.begin();
    const VkBufferCopy all{0, 0, active_ * 8};
    ctx_.vk().vkCmdCopyBuffer(ctx_.recording(), cells_.handle(), copy.handle(), 1, &all);
    ctx_.submit_and_wait();
    const auto* words = static_cast<const glm::uvec2*>(copy.mapped());
    double area = 0;
    for (std::uint64_t i = 0; i < active_; ++i) {
        const std::uint32_t bits = std::uint32_t(std::countr_zero(words[i].x));
        const glm::uvec2 corner((words[i].x & (words[i].x - 1)) >> 1, words[i].y);
        area += field::pow2(2 * int(bits) - 2 * int(weight(corner, bits)));
    }
    return area;
}

void FieldVulkan::reserve_refinement() {
    grow(ctx_, fates_, active_ * 4);
    grow(ctx_, counts_, active_ * 4);
    grow(ctx_, searches_, active_ * 4);
    primitives_.reserve_scan(active_);
}

bool FieldVulkan::refine_list(std::uint32_t mode, std::uint32_t param, std::uint32_t stamp, std::uint64_t darts_offsets,
                              std::uint64_t settle_from, bool open) {
    if (!open) {
        reserve_refinement();
        ctx_.begin();
    }
    clear_counters();
    FieldArgs a = args();
    a.cells = cells_.address();
    a.words0 = counts_.address();
    a.words1 = fates_.address();
    a.words2 = darts_offsets;
    a.p2 = param;
    a.p3 = stamp;
    if (mode == 0) {
        dispatch(field_balance_, a, 0, active_);
    } else {
        // The cells whose fate needs a search listed, those that search for a cover apart from
        // those that only split, and each list dispatched to field_fates.
        a.target = searches_.address();
        const std::uint32_t every = field::splits_every_cell(active_, leaves_) ? FIELD_SPLIT_EVERY : 0u;
        a.p0 = every;
        dispatch(field_triage_, a, 0, active_);
        ctx_.barrier();
        for (std::uint32_t list = 0; list < 2; ++list) {
            const std::uint32_t slot = FIELD_COUNTER_WORK + 4 * list;
            const WorkArgs w{counters_.address(), slot, slot, work_groups_};
            ctx_.dispatch(work_args_, &w, 1);
        }
        ctx_.barrier();
        a.first = 0;
        a.p1 = std::uint32_t(active_);
        for (std::uint32_t list = 0; list < 2; ++list) {
            a.p0 = list | every;
            ctx_.dispatch_indirect(field_fates_, &a, counters_, (FIELD_COUNTER_WORK + 4 * list) * 4);
        }
    }
    ctx_.barrier();
    primitives_.scan(counts_.address(), active_, kCellsTotal);
    // Scatter into the next list; it counts the cells per exponent and their least side afresh.
    // With the next list at its worst case (every cell split in four) it goes into the same
    // submit, where that keeps the device's arrays within their peak so far (the deep rounds).
    const std::uint64_t worst = std::max<std::uint64_t>(active_ * 4, 1) * 8;
    const bool one_submit = mode == 1 && (next_.size() >= worst ||
                                          ctx_.allocated_bytes() - next_.size() + worst <= ctx_.peak_allocated_bytes());
    auto scatter = [&] {
        a.target = next_.address();
        dispatch(field_scatter_, a, 0, active_);
        if (settle_from < samples_) {
            // The samples from settle_from on settle: their fresh marks, read by the fates, cleared.
            FieldArgs u = args();
            u.p0 = 1;
            dispatch(field_unmark_, u, settle_from, samples_);
        }
        ctx_.barrier();
    };
    if (one_submit) {
        grow(ctx_, next_, worst);  // no command recorded reads the list it replaces
        clear_counters(FIELD_COUNTER_EXPONENTS);  // the scatter's only: the scan's total is read below
        scatter();
    }
    ctx_.submit_and_wait();
    check_budget();
    const std::uint64_t total = counters()[kCellsTotal];
    if (!one_submit) {
        if (mode == 0 && counters()[FIELD_COUNTER_SPLITS] == 0) return false;
        grow(ctx_, next_, std::max<std::uint64_t>(total, 1) * 8);
        ctx_.begin();
        clear_counters();
        scatter();
        ctx_.submit_and_wait();
    }
    std::swap(cells_, next_);
    active_ = total;
    least_bits_ = counters()[FIELD_COUNTER_LEAST_BITS];
    return true;
}

double FieldVulkan::balance() {
    for (;;) {
        const ExponentCounts e = exponents();
        const double rate = field::kLambda * double(active_) / weighted_area(e);
        std::size_t top = e.size();
        while (top > 0 && e[top - 1] == 0) --top;
        const int split = field::split_exponent(rate);
        if (top == 0 || int(top) - 1 < split) return rate;
        if (!refine_list(0, std::uint32_t(split), 0, 0, UINT64_MAX)) return rate;
    }
}

bool FieldVulkan::throw_and_resolve(std::uint32_t round, std::uint32_t stamp) {
    const double rate = balance();
    std::uint32_t exp_neg[128];
    field::exp_neg_table(rate, exp_neg);
    const std::uint32_t key = round_key(o_.seed, round);
    // Each cell's darts, their offsets by a scan, and the cells with darts listed (in counts_,
    // free until the refinement).
    std::memcpy(exp_table_.mapped(), exp_neg, sizeof(exp_neg));
    grow(ctx_, offsets_, active_ * 4);
    grow(ctx_, counts_, active_ * 4);
    primitives_.reserve_scan(active_);
    ctx_.begin();
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), counters_.handle(), FIELD_COUNTER_DART_CELLS * 4, 4, 0);
    ctx_.barrier();
    FieldArgs a = args();
    a.cells = cells_.address();
    a.words0 = offsets_.address();
    a.words1 = exp_table_.address();
    a.words2 = counts_.address();
    a.p0 = key;
    dispatch(field_count_darts_, a, 0, active_);
    ctx_.barrier();
    primitives_.scan(offsets_.address(), active_, kDartsTotal);
    ctx_.submit_and_wait();
    const std::uint64_t thrown = counters()[kDartsTotal], dart_cells = counters()[FIELD_COUNTER_DART_CELLS];
    thrown_ = thrown;
    darts_thrown_ += thrown;
    if (thrown == 0) return false;
    // The throw: every dart at its slot, flagged if it stays; the kept ones compacted in order and
    // resolved in the same submit, their count on the device (FIELD_COUNTED), their arrays sized
    // for every dart thrown (raw_: the thrown darts, then the resolution's summaries, work lists
    // and the darts' r, field_resolve.comp).
    grow(ctx_, raw_, thrown * 28);
    grow(ctx_, flags_, thrown * 4);
    grow(ctx_, darts_, thrown * 16);
    grow(ctx_, states_, thrown * 4);
    primitives_.reserve_scan(thrown);
    ctx_.begin();
    clear_counters();
    a.target = raw_.address();
    a.words1 = flags_.address();
    a.p1 = std::uint32_t(samples_);
    a.p2 = std::uint32_t(thrown);
    a.p3 = std::uint32_t(active_);
    dispatch(field_throw_, a, 0, dart_cells);
    ctx_.barrier();
    primitives_.scan(flags_.address(), thrown, kKeptTotal);
    FieldArgs c = args();
    c.cells = raw_.address();
    c.target = darts_.address();
    c.words0 = flags_.address();
    c.p0 = FIELD_COUNTED | kKeptTotal;
    dispatch(field_compact_, c, 0, thrown);
    // Past the kept darts too: their flags below are then 0.
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), states_.handle(), 0, VK_WHOLE_SIZE, DART_UNDECIDED);
    ctx_.barrier();
    // Each leaf with darts: its first dart, its path marked fresh, and its accepted dart (none).
    // The compaction's flags and the thrown darts are spent: the resolution keeps its leaves'
    // summaries in them (field_resolve.comp).
    FieldArgs d = args();
    d.cells = darts_.address();
    d.words0 = leaf_first_.address();
    d.words1 = states_.address();
    d.words2 = flags_.address();
    d.target = raw_.address();
    d.p2 = std::uint32_t(thrown);
    dispatch_counted(field_first_darts_, d, thrown, kKeptTotal);
    // Each pass reads one pair of summary regions and writes the other, emptied before it. The
    // first and the one before it read every dart; the others, the work list the pass before
    // left (`reads` - 1), dispatched from its counter slots (work_args.comp).
    auto pass = [&](std::uint32_t writes, bool first, std::uint32_t reads) {
        ctx_.vk().vkCmdFillBuffer(ctx_.recording(), raw_.handle(), writes * thrown * 8, thrown * 8, UINT32_MAX);
        FieldArgs r = d;
        r.p0 = first ? 1 : 0;
        r.p1 = writes;
        r.p3 = reads;
        if (reads == 0) {
            ctx_.vk().vkCmdFillBuffer(ctx_.recording(), counters_.handle(), (FIELD_COUNTER_WORK + 3) * 4, 4, 0);
            ctx_.barrier();
            dispatch_counted(field_resolve_, r, thrown, kKeptTotal);
        } else {
            const std::uint32_t slot = FIELD_COUNTER_WORK + 4 * (reads - 1);
            WorkArgs w{counters_.address(), slot, FIELD_COUNTER_WORK + 4 * (2 - reads), work_groups_};
            ctx_.dispatch(work_args_, &w, 1);
            ctx_.barrier();
            r.count = FIELD_COUNTED | kKeptTotal;
            r.first = 0;
            ctx_.dispatch_indirect(field_resolve_, &r, counters_, slot * 4);
        }
        ctx_.barrier();
    };
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), node_keys_.handle(), 0, VK_WHOLE_SIZE, UINT32_MAX);
    pass(0, true, 0);
    // Resolution passes until no dart is undecided. Each submit also carries the next step behind
    // a gate that holds while darts are undecided: the leaves' fresh marks off, and the accepted
    // darts flagged and ranked.
    for (std::uint32_t passes = 0;;) {
        for (std::uint32_t k = 0; k < kPassesPerSubmit; ++k) {
            ctx_.vk().vkCmdFillBuffer(ctx_.recording(), counters_.handle(), FIELD_COUNTER_UNDECIDED * 4, 4, 0);
            ++passes;
            pass(passes & 1, false, passes == 1 ? 0 : 1 + (passes & 1));
        }
        ctx_.open_gate(gate_, counters_.address(), FIELD_COUNTER_UNDECIDED);
        FieldArgs u = d;
        u.p0 = 0;
        dispatch_counted(field_unmark_, u, thrown, kKeptTotal);
        FieldArgs f = d;
        f.words0 = flags_.address();
        f.p0 = 0;
        dispatch(field_accepted_, f, 0, thrown);
        ctx_.barrier();
        primitives_.scan(flags_.address(), thrown, kAcceptedTotal);
        ctx_.close_gate();
        ctx_.submit_and_wait();
        check_budget();
        if (counters()[FIELD_COUNTER_UNDECIDED] == 0) break;
        ctx_.begin();
    }
    const std::uint64_t kept = counters()[kKeptTotal], accepted = counters()[kAcceptedTotal];
    if (accepted == 0) return false;
    if (samples_ + accepted > capacity_) {
        capacity_ = std::max(samples_ + accepted, capacity_ + capacity_ / 4);
        grow(ctx_, points_, capacity_ * 8, true);
        grow(ctx_, radii_, capacity_ * 4, true);
        write_run();
    }
    // The sort's arrays, and the refinement's, sized before their submit holds commands on the
    // arrays they replace. The sort's scratch (12 bytes a dart) is the thrown darts' array (16 a
    // dart), which only the compaction read.
    grow(ctx_, pairs_, kept * 8);
    grow(ctx_, keys_, kept * 4);
    primitives_.reserve_sort(std::uint32_t(kept));
    reserve_refinement();
    ctx_.begin();
    FieldArgs f = d;
    f.words0 = flags_.address();
    f.p0 = 1;
    f.p1 = std::uint32_t(accepted);
    f.target = pairs_.address();
    f.words2 = keys_.address();
    dispatch(field_accepted_, f, 0, kept);
    ctx_.barrier();
    if (accepted > 1)
        primitives_.sort(pairs_.address(), keys_.address(), raw_.address(), std::uint32_t(accepted), kSortTotal);
    FieldArgs e = args();
    e.cells = darts_.address();
    e.target = pairs_.address();
    e.p0 = std::uint32_t(samples_);
    dispatch(field_emit_, e, 0, accepted);
    ctx_.barrier();
    // The leaves the new samples may cover or conflict with, stamped.
    FieldArgs t = args();
    t.p0 = stamp;
    dispatch(field_touch_, t, samples_, samples_ + accepted);
    ctx_.barrier();
    samples_ += accepted;
    return true;
}

}  // namespace vrpd::detail
