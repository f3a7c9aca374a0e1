// The sizing-field sampler on a Vulkan device: its state and steps (field_engine.cpp: a round's
// steps; field_device.cpp: a run and FieldDevice). The host's rounds (field/engine.cpp) as compute
// dispatches over compacted lists, the same cells, darts and samples point for point. Each round
// balances the active list (split where a cell expects too many darts), counts and throws the
// darts (each tested against the samples), resolves them in arrival order by passes, appends the
// accepted ones as samples in that order (sorted by key), and refines the list. The host reads
// back counts, the cells per exponent (for the rate) and the undecided darts; it computes the
// rate with the host sampler's arithmetic (field/rate.h). The kernels' tests: shared/field_run.h.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "field/quadtree.h"
#include "field/rate.h"
#include "shared/field_run.h"
#include "shared/kernels.h"
#include "vulkan/buffer.h"
#include "vulkan/device.h"
#include "vulkan/kernel.h"
#include "vulkan/primitives.h"

namespace vrpd::detail {

class FieldVulkan {
public:
    // On the options' device (or the application's), its kernels the builds that read kinked
    // cells where `kinks`; `budget`: FieldDevice's.
    FieldVulkan(const SampleOptions& o, bool kinks, std::uint32_t budget, std::uint32_t work_groups);

    // One run (a hierarchy's level) on the field t and its leaves, from `given` (FieldDevice::run).
    Sampling run(const FieldTable& t, const FieldQuadtree& tree, const std::vector<glm::uvec2>& given,
                 std::uint32_t first_round);
    VulkanContext& context() { return ctx_; }

private:
    // The kernels' variant (kernel.h) for the run's rule, box and weighting (shared/field_run.h).
    static std::uint32_t variant_of(const SampleOptions& o);
    // Counter slots of the scans' totals.
    static constexpr std::uint32_t kCellsTotal = shared::FIELD_COUNTER_TOTAL, kDartsTotal = kCellsTotal + 1,
                                   kKeptTotal = kCellsTotal + 2, kAcceptedTotal = kCellsTotal + 3,
                                   kSortTotal = kCellsTotal + 4;
    // A device address as the shared headers' buffer type T (its member `value`).
    template <typename T>
    static T device_ref(std::uint64_t address) {
        return T{reinterpret_cast<decltype(T::value)>(address)};
    }
    // Records kernel k over items [begin, end).
    void dispatch(const Kernel& k, shared::FieldArgs args, std::uint64_t begin, std::uint64_t end) {
        args.count = std::uint32_t(end);
        record(k, args, begin, end);
    }
    // Records kernel k over a list whose length a scan leaves in counter `slot` within the submit:
    // the dispatch covers `bound` items, and the kernel reads its count from the counter.
    void dispatch_counted(const Kernel& k, shared::FieldArgs args, std::uint64_t bound, std::uint32_t slot) {
        args.count = shared::FIELD_COUNTED | slot;
        record(k, args, 0, bound);
    }
    void record(const Kernel& k, shared::FieldArgs args, std::uint64_t begin, std::uint64_t end) {
        args.first = std::uint32_t(begin);
        ctx_.dispatch(k, &args, dispatch_groups(end - begin, shared::WORKGROUP_SIZE));
    }
    shared::FieldArgs args() const {
        shared::FieldArgs a{};
        a.run = run_.address();
        a.counters = counters_.address();
        return a;
    }
    std::uint32_t* counters() const { return static_cast<std::uint32_t*>(counters_.mapped()); }
    // A device-local copy of `bytes` of host data (at least 16 bytes), its upload recorded.
    Buffer upload(const void* data, std::uint64_t bytes, std::vector<Buffer>& staging);
    // Throws Error if a kernel's search passed its budget.
    void check_budget() const;
    // Clears the counters the next kernels add to, from slot `from` on (the least side's bits
    // to UINT32_MAX).
    void clear_counters(std::uint32_t from = shared::FIELD_COUNTER_UNDECIDED);
    field::ExponentCounts exponents() const {
        field::ExponentCounts e{};
        for (std::size_t k = 0; k < e.size(); ++k) e[k] = counters()[shared::FIELD_COUNTER_EXPONENTS + k];
        return e;
    }
    double weighted_area(const field::ExponentCounts& e);
    // Eq. 12's weight of the cell of side 2^bits at `corner` (field.glsl's field_weight).
    std::uint32_t weight(glm::uvec2 corner, std::uint32_t bits) const;
    // Balances the active list as the host's balance does; returns the round's rate.
    double balance();
    // Writes each cell's fate (mode 0: field_balance, 1: field_fates; p2 and p3 their parameters)
    // into the next list, which becomes the active one; returns false, keeping the list, if
    // balance split none.
    // With the list written, the samples from `settle_from` on settle (UINT64_MAX: none).
    // `open`: its first commands go into the submit already begun, not one of their own, its
    // arrays sized (reserve_refinement).
    bool refine_list(std::uint32_t mode, std::uint32_t param, std::uint32_t stamp, std::uint64_t darts_offsets,
                     std::uint64_t settle_from, bool open = false);
    // Sizes the refinement's arrays for the active list, before its submit is begun.
    void reserve_refinement();
    // Throws and resolves the darts of round `round` (its key), stamping its samples' leaves with
    // `stamp`. Returns true if it leaves its last commands recorded in a submit begun for the
    // refinement to continue (the active list's fates and scan are then sized).
    bool throw_and_resolve(std::uint32_t round, std::uint32_t stamp);
    // Places the given samples, stamps their leaves with `stamp` and drops the cells they cover.
    void place_given(const std::vector<glm::uvec2>& given, std::uint32_t stamp);
    void write_run();

    const FieldTable* t_ = nullptr;  // the run's
    const SampleOptions& o_;
    bool kinks_;  // the kernels read kinked cells
    ContextLease lease_;
    VulkanContext& ctx_;
    Buffer counters_;
    Primitives primitives_;
    Kernel field_histogram_, field_fates_, field_balance_, field_scatter_, field_count_darts_, field_throw_,
        field_compact_, field_first_darts_, field_resolve_, field_unmark_, field_accepted_, field_emit_, field_touch_,
        field_place_, field_triage_, work_args_;
    bool density_;
    std::uint32_t budget_;        // the search steps an invocation may take
    std::uint32_t work_groups_;   // the most workgroups in a row of a dispatch or a pass over a work list
    std::vector<Buffer> tables_;  // the table's arrays
    Buffer run_, roots_, nodes_, node_keys_, leaf_sample_, leaf_first_, touched_, points_, radii_;
    Buffer gate_;       // the commands of gated dispatches (VulkanContext::open_gate)
    Buffer exp_table_;  // the round's exp(-rate 2^k) table (field::exp_neg_table), host-visible
    Buffer cells_, next_, fates_, counts_, offsets_, raw_, flags_, darts_, states_, pairs_, keys_;
    Buffer searches_;  // the refinement's work list: the cells whose fate needs a search
    std::uint64_t active_ = 0, samples_ = 0, capacity_ = 0, darts_thrown_ = 0, thrown_ = 0;  // thrown_: this round's
    // The run's leaves, against which the active cells' count decides whether every open cell splits.
    std::uint64_t leaves_ = 0;
    std::uint32_t least_bits_ = UINT32_MAX;
    shared::FieldRun run_args_{};
};

}  // namespace vrpd::detail
