// The sizing-field sampler on a Vulkan device: the host's rounds (field/engine.cpp) as compute
// dispatches over compacted lists, the same cells, darts and samples point for point. Each round
// balances the active list (split where a cell expects too many darts), counts and throws the
// darts (each tested against the samples), resolves them in arrival order by passes, appends the
// accepted ones as samples in that order (sorted by key), and refines the list. The host reads
// back counts, the cells per exponent (for the rate) and the undecided darts; it computes the
// rate with the host sampler's arithmetic (field/rate.h). The kernels' tests: shared/field_run.h.
#include "vulkan/field_engine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "field/power_sum.h"
#include "field/quadtree.h"
#include "field/rate.h"
#include "field_accepted.h"
#include "field_compact.h"
#include "field_count_darts.h"
#include "field_emit.h"
#include "field_fates.h"
#include "field_first_darts.h"
#include "field_histogram.h"
#include "field_place.h"
#include "field_resolve.h"
#include "field_scatter.h"
#include "field_throw.h"
#include "field_touch.h"
#include "field_unmark.h"
#include "shared/field_run.h"
#include "shared/kernels.h"
#include "vulkan/buffer.h"
#include "vulkan/device.h"
#include "vulkan/kernel.h"
#include "vulkan/primitives.h"

namespace vrpd::detail {

namespace {

using namespace shared;
using field::ExponentCounts;

static_assert(sizeof(FieldArgs) == 80 && offsetof(FieldArgs, count) == 56 && offsetof(FieldArgs, p2) == 72);
static_assert(sizeof(FieldRun) == 176 && offsetof(FieldRun, tree) == 80 && offsetof(FieldRun, lattice) == 112 &&
              offsetof(FieldRun, leaf_sample) == 144);

constexpr std::uint32_t kMaxGroups = 65535;  // the least maxComputeWorkGroupCount[0] Vulkan allows
constexpr std::uint32_t kPassesPerSubmit = 4;
constexpr std::uint32_t kMaxRounds = 1000000;  // a bug guard, far above any run
// Search steps an invocation may take on lavapipe, whose loops stop after 65 535 passes of a
// SIMD vector of 8 invocations (shared/field_search.h): a vector passes its loops at most as often
// as its lanes do in all, and a lane's passes are its steps and a few hundred in loops of fixed
// length, so 8 x (6 000 + 500) stays below the limit. Elsewhere searches are not cut short.
constexpr std::uint32_t kLavapipeBudget = 6000;
// Cell fates (field_fates.comp).
constexpr std::uint32_t kKeep = 0x10;
// Counter slots of the scans' totals.
constexpr std::uint32_t kCellsTotal = FIELD_COUNTER_TOTAL, kDartsTotal = FIELD_COUNTER_TOTAL + 1,
                        kKeptTotal = FIELD_COUNTER_TOTAL + 2, kAcceptedTotal = FIELD_COUNTER_TOTAL + 3,
                        kSortTotal = FIELD_COUNTER_TOTAL + 4;

template <typename T>
T device_ref(std::uint64_t address) {
    return T{reinterpret_cast<decltype(T::value)>(address)};
}

}  // namespace

class FieldVulkan {
public:
    FieldVulkan(const SampleOptions& o, std::uint32_t budget)
        : o_(o),
          ctx_(o.device, o.vulkan),
          counters_(ctx_, FIELD_COUNTER_WORDS * 4, true),
          primitives_(ctx_, counters_),
          VRPD_KERNEL(field_histogram, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_fates, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_scatter, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_count_darts, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_throw, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_compact, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_first_darts, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_resolve, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_unmark, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_accepted, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_emit, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_touch, FieldArgs, WORKGROUP_SIZE),
          VRPD_KERNEL(field_place, FieldArgs, WORKGROUP_SIZE),
          density_(o.sizing->weighting == Weighting::Density) {
        if (o.profile) ctx_.start_profile();
        budget_ = budget != 0                                                ? budget
                  : ctx_.device_name().find("llvmpipe") != std::string::npos ? kLavapipeBudget
                                                                             : UINT32_MAX - 1;
    }

    // One run (a hierarchy's level) on the field t and its leaves, from `given` (FieldDevice::run).
    Sampling run(const FieldTable& t, const FieldQuadtree& tree, const std::vector<glm::uvec2>& given,
                 std::uint32_t first_round);
    VulkanContext& context() { return ctx_; }

private:
    // Records kernel k over items [begin, end) (chunks of at most kMaxGroups workgroups).
    void dispatch(const Kernel& k, FieldArgs args, std::uint64_t begin, std::uint64_t end) {
        args.count = std::uint32_t(end);
        for (std::uint64_t from = begin; from < end; from += std::uint64_t(kMaxGroups) * WORKGROUP_SIZE) {
            args.first = std::uint32_t(from);
            ctx_.dispatch(
                k, &args,
                dispatch_groups(std::min<std::uint64_t>(end - from, std::uint64_t(kMaxGroups) * WORKGROUP_SIZE),
                                WORKGROUP_SIZE));
        }
    }
    FieldArgs args() const {
        FieldArgs a{};
        a.run = run_.address();
        a.counters = counters_.address();
        return a;
    }
    std::uint32_t* counters() const { return static_cast<std::uint32_t*>(counters_.mapped()); }
    // A device-local copy of `bytes` of host data (at least 16 bytes), its upload recorded.
    Buffer upload(const void* data, std::uint64_t bytes, std::vector<Buffer>& staging);
    // Throws Error if a kernel's search passed its budget.
    void check_budget() const;
    // Clears the counters the next kernels add to.
    void clear_counters();
    ExponentCounts exponents() const {
        ExponentCounts e{};
        for (std::size_t k = 0; k < e.size(); ++k) e[k] = counters()[FIELD_COUNTER_EXPONENTS + k];
        return e;
    }
    double weighted_area(const ExponentCounts& e);
    // Balances the active list as the host's balance does; returns the round's rate.
    double balance();
    // Writes each cell's fate (p1: 0 balance, 1 refine; p2 and p3 its parameters) into the next
    // list, which becomes the active one; returns false, keeping the list, if balance split none.
    bool refine_list(std::uint32_t mode, std::uint32_t param, std::uint32_t stamp, std::uint64_t darts_offsets);
    // Throws and resolves the darts of round `round` (its key), stamping its samples' leaves with
    // `stamp`.
    void throw_and_resolve(std::uint32_t round, std::uint32_t stamp);
    // Places the given samples, stamps their leaves with `stamp` and drops the cells they cover.
    void place_given(const std::vector<glm::uvec2>& given, std::uint32_t stamp);
    void write_run();

    const FieldTable* t_ = nullptr;  // the run's
    const SampleOptions& o_;
    VulkanContext ctx_;
    Buffer counters_;
    Primitives primitives_;
    Kernel field_histogram_, field_fates_, field_scatter_, field_count_darts_, field_throw_, field_compact_,
        field_first_darts_, field_resolve_, field_unmark_, field_accepted_, field_emit_, field_touch_, field_place_;
    bool density_;
    std::uint32_t budget_;        // the search steps an invocation may take
    std::vector<Buffer> tables_;  // the table's arrays
    Buffer run_, roots_, nodes_, leaf_sample_, leaf_first_, touched_, points_, radii_;
    Buffer cells_, next_, fates_, counts_, offsets_, raw_, flags_, darts_, states_, pairs_, keys_, sort_tmp_;
    std::uint64_t active_ = 0, samples_ = 0, capacity_ = 0, darts_thrown_ = 0, thrown_ = 0;  // thrown_: this round's
    std::uint32_t least_bits_ = UINT32_MAX;
    FieldRun run_args_{};
};

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

void FieldVulkan::clear_counters() {
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), counters_.handle(), FIELD_COUNTER_UNDECIDED * 4,
                              (FIELD_COUNTER_WORDS - FIELD_COUNTER_UNDECIDED) * 4, 0);
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), counters_.handle(), FIELD_COUNTER_LEAST_BITS * 4, 4, UINT32_MAX);
    ctx_.barrier();
}

void FieldVulkan::write_run() {
    run_args_.points = device_ref<FieldPoints>(points_.address());
    run_args_.radii = device_ref<FieldWords>(radii_.address());
    std::memcpy(run_.mapped(), &run_args_, sizeof(run_args_));
}

double FieldVulkan::weighted_area(const ExponentCounts& e) {
    if (const auto sum = field::exact_power_sum(e, field::kExponentBias)) return *sum;
    // As the host adds them: each cell's 2^exponent in list order.
    Buffer copy(ctx_, active_ * 16, true);
    ctx_.begin();
    const VkBufferCopy all{0, 0, active_ * 16};
    ctx_.vk().vkCmdCopyBuffer(ctx_.recording(), cells_.handle(), copy.handle(), 1, &all);
    ctx_.submit_and_wait();
    const auto* cells = static_cast<const glm::uvec4*>(copy.mapped());
    double area = 0;
    for (std::uint64_t i = 0; i < active_; ++i)
        area += field::pow2(2 * int(cells[i].z) - (density_ ? 2 * int(cells[i].w) : 0));
    return area;
}

bool FieldVulkan::refine_list(std::uint32_t mode, std::uint32_t param, std::uint32_t stamp,
                              std::uint64_t darts_offsets) {
    grow(ctx_, fates_, active_ * 4);
    grow(ctx_, counts_, active_ * 4);
    primitives_.reserve_scan(active_);
    ctx_.begin();
    clear_counters();
    FieldArgs a = args();
    a.cells = cells_.address();
    a.words0 = counts_.address();
    a.words1 = fates_.address();
    a.words2 = darts_offsets;
    a.p0 = density_ ? 1 : 0;
    a.p1 = mode;
    a.p2 = param;
    a.p3 = stamp;
    dispatch(field_fates_, a, 0, active_);
    ctx_.barrier();
    primitives_.scan(counts_.address(), active_, kCellsTotal);
    ctx_.submit_and_wait();
    check_budget();
    const std::uint64_t total = counters()[kCellsTotal];
    if (mode == 0 && counters()[FIELD_COUNTER_SPLITS] == 0) return false;
    // Scatter into the next list; it counts the cells per exponent and their least side afresh.
    grow(ctx_, next_, std::max<std::uint64_t>(total, 1) * 16);
    ctx_.begin();
    clear_counters();
    a.target = next_.address();
    dispatch(field_scatter_, a, 0, active_);
    ctx_.barrier();
    ctx_.submit_and_wait();
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
        if (!refine_list(0, std::uint32_t(split), 0, 0)) return rate;
    }
}

void FieldVulkan::throw_and_resolve(std::uint32_t round, std::uint32_t stamp) {
    const double rate = balance();
    std::uint32_t exp_neg[128];
    field::exp_neg_table(rate, exp_neg);
    const std::uint32_t key = round_key(o_.seed, round);
    // Each cell's darts, their offsets by a scan.
    Buffer table(ctx_, sizeof(exp_neg), true);
    std::memcpy(table.mapped(), exp_neg, sizeof(exp_neg));
    grow(ctx_, offsets_, active_ * 4);
    primitives_.reserve_scan(active_);
    ctx_.begin();
    FieldArgs a = args();
    a.cells = cells_.address();
    a.words0 = offsets_.address();
    a.words1 = table.address();
    a.p0 = key;
    a.p1 = density_ ? 1 : 0;
    dispatch(field_count_darts_, a, 0, active_);
    ctx_.barrier();
    primitives_.scan(offsets_.address(), active_, kDartsTotal);
    ctx_.submit_and_wait();
    const std::uint64_t thrown = counters()[kDartsTotal];
    thrown_ = thrown;
    darts_thrown_ += thrown;
    if (thrown == 0) return;
    // The throw: every dart at its slot, flagged if it stays; the kept ones compacted in order.
    grow(ctx_, raw_, thrown * 16);
    grow(ctx_, flags_, thrown * 4);
    primitives_.reserve_scan(thrown);
    ctx_.begin();
    clear_counters();
    a.target = raw_.address();
    a.words1 = flags_.address();
    a.p2 = std::uint32_t(thrown);
    dispatch(field_throw_, a, 0, active_);
    ctx_.barrier();
    primitives_.scan(flags_.address(), thrown, kKeptTotal);
    ctx_.submit_and_wait();
    check_budget();
    const std::uint64_t kept = counters()[kKeptTotal];
    if (kept == 0) return;
    grow(ctx_, darts_, kept * 16);
    grow(ctx_, states_, kept * 4);
    grow(ctx_, pairs_, kept * 8);
    grow(ctx_, keys_, kept * 4);
    grow(ctx_, sort_tmp_, kept * 12);
    primitives_.reserve_scan(kept);
    primitives_.reserve_sort(std::uint32_t(kept));
    ctx_.begin();
    FieldArgs c = args();
    c.cells = raw_.address();
    c.target = darts_.address();
    c.words0 = flags_.address();
    c.p0 = std::uint32_t(kept);
    dispatch(field_compact_, c, 0, thrown);
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), states_.handle(), 0, kept * 4, DART_UNDECIDED);
    ctx_.barrier();
    // Each leaf with darts: its first dart, and its path marked fresh.
    FieldArgs d = args();
    d.cells = darts_.address();
    d.words0 = leaf_first_.address();
    d.words1 = states_.address();
    dispatch(field_first_darts_, d, 0, kept);
    ctx_.barrier();
    // Resolution passes until no dart is undecided.
    for (;;) {
        for (std::uint32_t pass = 0; pass < kPassesPerSubmit; ++pass) {
            ctx_.vk().vkCmdFillBuffer(ctx_.recording(), counters_.handle(), FIELD_COUNTER_UNDECIDED * 4, 4, 0);
            ctx_.barrier();
            dispatch(field_resolve_, d, 0, kept);
            ctx_.barrier();
        }
        ctx_.submit_and_wait();
        check_budget();
        if (counters()[FIELD_COUNTER_UNDECIDED] == 0) break;
        ctx_.begin();
    }
    // The leaves' fresh marks off; the accepted darts ranked, sorted into arrival order, and
    // appended as samples (their leaves marked occupied and fresh).
    ctx_.begin();
    FieldArgs u = d;
    u.p0 = 0;
    dispatch(field_unmark_, u, 0, kept);
    FieldArgs f = d;
    f.words0 = flags_.address();
    f.p0 = 0;
    dispatch(field_accepted_, f, 0, kept);
    ctx_.barrier();
    primitives_.scan(flags_.address(), kept, kAcceptedTotal);
    ctx_.submit_and_wait();
    const std::uint64_t accepted = counters()[kAcceptedTotal];
    if (accepted == 0) return;
    if (samples_ + accepted > capacity_) {
        capacity_ = std::max(samples_ + accepted, capacity_ + capacity_ / 4);
        grow(ctx_, points_, capacity_ * 8, true);
        grow(ctx_, radii_, capacity_ * 4, true);
        write_run();
    }
    ctx_.begin();
    f.p0 = 1;
    f.p1 = std::uint32_t(accepted);
    f.target = pairs_.address();
    f.words2 = keys_.address();
    dispatch(field_accepted_, f, 0, kept);
    ctx_.barrier();
    if (accepted > 1)
        primitives_.sort(pairs_.address(), keys_.address(), sort_tmp_.address(), std::uint32_t(accepted), kSortTotal);
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
    ctx_.submit_and_wait();
    check_budget();
    samples_ += accepted;
}

void FieldVulkan::place_given(const std::vector<glm::uvec2>& given, std::uint32_t stamp) {
    const std::uint64_t n = given.size();
    Buffer staging(ctx_, n * 8, true);
    std::memcpy(staging.mapped(), given.data(), n * 8);
    grow(ctx_, offsets_, active_ * 4);
    ctx_.begin();
    const VkBufferCopy all{0, 0, n * 8};
    ctx_.vk().vkCmdCopyBuffer(ctx_.recording(), staging.handle(), points_.handle(), 1, &all);
    // No cell took a dart: the refinement's dart offsets are all 0.
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), offsets_.handle(), 0, VK_WHOLE_SIZE, 0);
    ctx_.barrier();
    FieldArgs p = args();
    dispatch(field_place_, p, 0, n);
    ctx_.barrier();
    FieldArgs t = args();
    t.p0 = stamp;
    dispatch(field_touch_, t, 0, n);
    ctx_.barrier();
    ctx_.submit_and_wait();
    check_budget();
    samples_ = n;
    refine_list(1, 0, stamp, offsets_.address());
    ctx_.begin();
    FieldArgs u = args();
    u.p0 = 1;
    dispatch(field_unmark_, u, 0, n);
    ctx_.barrier();
    ctx_.submit_and_wait();
}

Sampling FieldVulkan::run(const FieldTable& table, const FieldQuadtree& tree, const std::vector<glm::uvec2>& given,
                          std::uint32_t first_round) {
    const auto start = std::chrono::steady_clock::now();
    t_ = &table;
    tables_.clear();
    samples_ = darts_thrown_ = thrown_ = 0;
    least_bits_ = UINT32_MAX;
    run_args_ = {};
    // The table, the tree's words and every leaf as an active cell (in leaf order, as the host's).
    std::vector<glm::uvec4> cells(tree.leaves());
    tree.each_leaf([&](std::uint32_t leaf, glm::uvec2 corner, std::uint32_t bits) {
        std::uint32_t w = 0;
        if (density_) {
            const glm::uvec2 far(std::uint32_t(std::min<std::uint64_t>(corner.x + (std::uint64_t(1) << bits) - 1,
                                                                       t_->lattice.extent_x - 1)),
                                 std::uint32_t(std::min<std::uint64_t>(corner.y + (std::uint64_t(1) << bits) - 1,
                                                                       t_->lattice.extent_y - 1)));
            const std::uint32_t lo = t_->min_over(corner, far);
            while (w < 31 && (std::uint64_t(t_->r_lo) << (w + 1)) <= lo) ++w;
        }
        cells[leaf] = {corner.x, corner.y, bits, w};
    });
    active_ = cells.size();
    capacity_ = std::max<std::uint64_t>({1024, active_ / 4, given.size()});
    std::vector<Buffer> staging;
    run_ = Buffer(ctx_, sizeof(FieldRun), true);
    ctx_.begin();
    auto words = [&](const auto& v) { return upload(v.data(), v.size() * sizeof(v[0]), staging); };
    const FieldTableView tv = t_->view();
    run_args_.table = tv;
    for (auto [member, array] : {std::pair{&FieldTableView::nodes, &t_->nodes},
                                 {&FieldTableView::patch_rank, &t_->patch_rank},
                                 {&FieldTableView::patch_nodes, &t_->patch_nodes},
                                 {&FieldTableView::pyramid_lo, &t_->pyramid_lo},
                                 {&FieldTableView::pyramid_hi, &t_->pyramid_hi},
                                 {&FieldTableView::pyramid_start, &t_->pyramid_start}}) {
        tables_.push_back(words(*array));
        run_args_.table.*member = device_ref<FieldWords>(tables_.back().address());
    }
    tables_.push_back(words(t_->patched));
    run_args_.table.patched = device_ref<FieldBits>(tables_.back().address());
    tables_.push_back(upload(t_->patches.data(), t_->patches.size() * sizeof(FieldTable::Patch), staging));
    run_args_.table.patches = device_ref<FieldWords>(tables_.back().address());
    roots_ = words(tree.root_words());
    nodes_ = words(tree.node_words());
    cells_ = words(cells);
    const FieldTreeView view = tree.view();
    run_args_.tree = {view.tile_bits, view.tiles_x, view.tiles_y, device_ref<FieldWords>(roots_.address()),
                      device_ref<FieldWords>(nodes_.address())};
    run_args_.lattice = t_->lattice;
    run_args_.rule = t_->rule;
    run_args_.r_hi = t_->r_hi;
    run_args_.r_lo = t_->r_lo;
    // 1 / (1 - L) rounded up in 2^-16 units (a larger factor only widens the searches).
    if (t_->lipschitz < 1 && 65536.0 / (1 - t_->lipschitz) < 4294967295.0)
        run_args_.growth = std::uint32_t(std::ceil(65536.0 / (1 - t_->lipschitz)));
    run_args_.budget = budget_;
    leaf_sample_ = Buffer(ctx_, std::max<std::uint64_t>(tree.leaves(), 4) * 4, false);
    leaf_first_ = Buffer(ctx_, std::max<std::uint64_t>(tree.leaves(), 4) * 4, false);
    touched_ = Buffer(ctx_, std::max<std::uint64_t>(tree.leaves(), 4) * 4, false);
    run_args_.touched = device_ref<FieldWords>(touched_.address());
    points_ = Buffer(ctx_, capacity_ * 8, false);
    radii_ = Buffer(ctx_, capacity_ * 4, false);
    run_args_.leaf_sample = device_ref<FieldWords>(leaf_sample_.address());
    write_run();
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), leaf_sample_.handle(), 0, VK_WHOLE_SIZE, FIELD_NO_SAMPLE);
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), touched_.handle(), 0, VK_WHOLE_SIZE, 0);
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), counters_.handle(), 0, FIELD_COUNTER_WORDS * 4, 0);
    ctx_.barrier();
    FieldArgs h = args();
    h.cells = cells_.address();
    h.p0 = density_ ? 1 : 0;
    dispatch(field_histogram_, h, 0, active_);
    ctx_.barrier();
    ctx_.submit_and_wait();
    staging.clear();
    // Stamps: 1 for the given samples, round k's 2 + k (0: a leaf no sample has stamped).
    if (!given.empty()) place_given(given, 1);
    std::uint32_t round = 0, deepest = 0;
    while (active_ > 0) {
        if (round == kMaxRounds) throw Error("internal: the sizing-field sampler did not converge");
        const std::uint64_t first = samples_;
        throw_and_resolve(first_round + round, round + 2);
        // Refinement, then this round's samples settle (their fresh marks cleared).
        refine_list(1, std::uint32_t(thrown_), round + 2, offsets_.address());
        if (active_ > 0) deepest = std::max(deepest, t_->tile_bits - least_bits_);
        if (samples_ > first) {
            ctx_.begin();
            FieldArgs u = args();
            u.p0 = 1;
            dispatch(field_unmark_, u, first, samples_);
            ctx_.barrier();
            ctx_.submit_and_wait();
        }
        ++round;
    }
    Sampling s;
    s.lattice.resize(samples_);
    if (samples_ > 0) {
        Buffer copy(ctx_, samples_ * 8, true);
        ctx_.begin();
        const VkBufferCopy all{0, 0, samples_ * 8};
        ctx_.vk().vkCmdCopyBuffer(ctx_.recording(), points_.handle(), copy.handle(), 1, &all);
        ctx_.submit_and_wait();
        std::memcpy(s.lattice.data(), copy.mapped(), samples_ * 8);
    }
    ctx_.check_validation();
    s.stats.levels = deepest;
    s.stats.rounds = round;
    s.stats.darts = darts_thrown_;
    s.stats.peak_bytes = ctx_.peak_allocated_bytes();
    s.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return s;
}

FieldDevice::FieldDevice(const SampleOptions& o, std::uint32_t budget)
    : impl_(std::make_unique<FieldVulkan>(o, budget)), threads_(o.threads) {}
FieldDevice::~FieldDevice() = default;

Sampling FieldDevice::run(const FieldTable& t, std::uint64_t max_leaves, const std::vector<glm::uvec2>& given,
                          std::uint32_t first_round) {
    ThreadPool pool(threads_);
    const FieldQuadtree tree(t, max_leaves, pool);
    return impl_->run(t, tree, given, first_round);
}

std::string FieldDevice::device_name() { return impl_->context().device_name(); }
std::uint64_t FieldDevice::round_trips() { return impl_->context().submits(); }
std::vector<PhaseTime> FieldDevice::profile() { return impl_->context().profile(); }

}  // namespace vrpd::detail
