// The host engines: `cpu` runs the GPU's kernel bodies (shaders/shared/sampler.h) over a thread
// pool, in mask mode at levels 0-2 as the GPU does, deciding each dart once (see resolve; on few
// threads in arrival order, arrival_order.h); `serial` accepts the same darts one at a time in
// arrival order (serial_oracle.h): the textbook process over explicit lists, kept simple as the oracle.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <queue>
#include <tuple>
#include <type_traits>
#include <utility>

#include "engine.h"
#include "arrival_order.h"
#include "cover_scatter.h"
#include "dart_flags.h"
#include "free_bases.h"
#include "parallel_resolution.h"
#include "shared/sampler.h"
#include "serial_oracle.h"
#include "thread_pool.h"
#include "uninitialised.h"

namespace vrpd::detail {
namespace {
using namespace shared;

// The engine's arrays: a resize leaves them unwritten, for the pool to fill; from 2 MiB on they
// take kept blocks (blocks.h), so that a round's arrays reuse the memory the last round's freed.
using Words = std::vector<uvec2, Uninitialised<uvec2, true>>;
using Counts = std::vector<uint, Uninitialised<uint, true>>;

// Up to this many threads the darts are decided in arrival order, a strip of base-cell rows a
// thread (arrival_order.h); more resolve in parallel (docs/performance.md).
constexpr unsigned kArrivalOrderThreads = 2;

class HostEngine final : public Engine {
public:
    HostEngine(const Plan& plan, Resolution resolution, unsigned threads)
        : plan_(plan), resolution_(resolution), pool_(threads) {}

    std::string device_name() const override {
        if (resolution_ == Resolution::Serial) return "serial (host, one dart at a time)";
        return pool_.device_name();
    }

    std::uint64_t start(const Plan& plan, const std::vector<uvec2>& initial) override {
        plan_ = plan;
        masked_ = resolution_ != Resolution::Serial && !two_radii(plan.domain.radii);
        const Domain& d = plan_.domain;
        // Reserving the expected count avoids the vector doubling past the end (more samples grow it).
        out_.reserve(std::max<std::uint64_t>(expected_samples(plan_), initial.size()));
        out_.assign(initial.begin(), initial.end());
        flags_.release();
        // Each base cell: empty, with (mask mode) its one level-0 cell active.
        const std::size_t bases = plan_.base_cells;
        Words(bases).swap(grid_);
        const uvec2 empty(GRID_EMPTY, masked_ ? 1u : GRID_EMPTY);
        pool_.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned) {
            std::fill(grid_.begin() + b, grid_.begin() + e, empty);
        });
        for (const uvec2& p : initial) place_sample(d, grid(), p);
        if (masked_) return bases;  // a sample's word holds no active mask
        // Two radii (cpu): the free base cells stay unlisted until the first refinement
        // (free_bases.h). The serial oracle lists them, leaving out the base cells that hold a
        // sample, as mask mode does: a round's darts word would replace the sample's.
        Words().swap(cells_);
        free_bases_ = resolution_ != Resolution::Serial;
        if (free_bases_) return free_base_offsets(pool_, grid_.data(), bases).back();
        list_free_bases(pool_, d, grid_.data(), bases, cells_);
        cells_free_bases_ = true;
        return cells_.size();
    }

    RoundResult round(const RoundSpec& spec, const RoundSpec*) override {
        const std::uint64_t total = timed("throw", [&] { return masked_ ? throw_masked(spec) : throw_listed(spec); });
        note_peak();
        timed("resolve", [&] { resolve(); });
        timed("commit", [&] { commit(spec); });
        if (!in_arrival_order()) timed("emit", [&] { emit(); });
        // The darts are spent: give their memory back before refinement.
        Counts().swap(darts_);
        dart_count_ = 0;
        Words().swap(dart_cells_);
        darts_on_cells_ = false;
        const std::uint64_t active = timed("refine", [&] { return masked_ ? refine_masked(spec) : refine(spec); });
        return {total, active};
    }

    std::vector<uvec2> samples() override { return std::move(out_); }
    std::uint64_t peak_bytes() const override { return peak_; }
    void start_profile() override { profiling_ = true; }
    std::vector<PhaseTime> profile() const override { return times_.phases(); }

private:
    // Runs f, adding its wall time to phase `name` when profiling.
    template <class F> std::invoke_result_t<F> timed(const char* name, F&& f) {
        if (!profiling_) return f();
        const auto t0 = std::chrono::steady_clock::now();
        struct Stop {
            PhaseTimes& times;
            const char* name;
            std::chrono::steady_clock::time_point t0;
            ~Stop() { times.add(name, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()); }
        } stop{times_, name, t0};
        return f();
    }

    // Sizes the darts' array to `total` darts, every state 0 (undecided), on the pool's threads.
    // Only the blocks' state words are cleared: throwing writes every dart's record, and ors its
    // state into its block's word.
    void clear_darts(std::uint64_t total) {
        if (total >= MAX_ROUND_DARTS) throw Error("a round would throw more than 2^30 darts");
        darts_.resize(dart_words(total));
        dart_count_ = total;
        pool_.parallel_for(darts_.size() / DART_BLOCK_WORDS, [&](std::size_t b, std::size_t e, unsigned) {
            for (std::size_t k = b; k < e; ++k) darts_[dart_state_word(uint(16 * k))] = 0u;
        });
    }

    // A kernel's arguments for `count` cells of side `side` in round `spec` (param: the kernel's).
    CellArgs cell_args(const RoundSpec& spec, std::uint64_t count, uint side, uint param) const {
        return {plan_.domain, 0, 0, 0, 0, 0, 0, 0, 0, uint(count), round_key(plan_.seed, spec.round), side, param};
    }

    // Records the memory held by the engine's arrays now, plus `extra` bytes held elsewhere.
    void note_peak(std::uint64_t extra = 0) {
        const std::uint64_t held = capacity_bytes(grid_) + capacity_bytes(cells_) + capacity_bytes(next_) +
                                   capacity_bytes(dart_cells_) + capacity_bytes(darts_) + capacity_bytes(scan_) +
                                   flags_.bytes() + capacity_bytes(masks_) + capacity_bytes(out_) + extra;
        peak_ = std::max(peak_, held);
    }

    // Lists the round's darts for the active cells (one radius) or the base cells near them (two
    // radii), throws them, and returns their count.
    std::uint64_t throw_listed(const RoundSpec& spec) {
        const Domain dom = plan_.domain;
        if (free_bases_ && spec.every_free_cell) {  // two radii's dart cells are base cells
            const CellArgs args = cell_args(spec, plan_.base_cells, 1u << dom.cell_bits, spec.exp_neg_lambda);
            clear_darts(mark_free_base_darts(pool_, args, grid_.data()));
            throw_free_base_darts(pool_, args, grid(), darts(), out_.empty());
            return dart_count_;
        }
        if (free_bases_) {  // a first round near the active cells: given samples fill most base cells
            list_free_bases(pool_, dom, grid_.data(), plan_.base_cells, cells_);
            free_bases_ = false;
        }
        if (two_radii(dom.radii)) list_dart_cells(spec);
        Words& targets = dart_targets();
        const uint n = uint(targets.size());
        const bool single = two_radii(dom.radii);  // dart cells: base cells, an entry each
        const uint side = single ? 1u << dom.cell_bits : spec.side;
        const uint key = round_key(plan_.seed, spec.round);
        CellArgs args{dom, 0, 0, 0, 0, 0, 0, 0, 0, n, key, side, spec.exp_neg_lambda};
        const Cells cells{targets.data()};

        fit(scan_, std::size_t(n) + 1);
        pool_.parallel_for(n, [&](std::size_t b, std::size_t e, unsigned) {
            cell_dart_counts(key, &targets[b], uint(e - b), spec.exp_neg_lambda, &scan_[b]);
        });
        const std::uint64_t total = exclusive_scan(n);
        clear_darts(total);
        // Only base cells that get darts are marked and thrown into: one left empty reads as dartless.
        pool_.parallel_for(n, [&](std::size_t b, std::size_t e, unsigned) {
            for_each_base_group(dom, cells, b, e, n, single, [&](uint g, uint end) {
                if (scan_[g] != scan_[end]) mark_dart_range(args, cells, scan(), grid(), g, end);
            });
        });
        // Throw, rejecting darts covered by earlier rounds.
        pool_.parallel_for(n, [&](std::size_t b, std::size_t e, unsigned) {
            for_each_base_group(dom, cells, b, e, n, single, [&](uint g, uint end) {
                if (scan_[g] != scan_[end]) throw_base_cell(args, cells, scan(), darts(), grid(), g, end);
            });
        });
        Counts().swap(scan_);
        return total;
    }

    // Mask mode: counts each base cell's darts into its word, numbers them chunk by chunk in base
    // cell order (the explicit list's order), throws them, and returns their count.
    std::uint64_t throw_masked(const RoundSpec& spec) {
        const uint bases = uint(plan_.base_cells);
        const CellArgs args = cell_args(spec, bases, spec.side, spec.exp_neg_lambda);
        std::vector<std::uint64_t> first(pool_.chunks(bases) + 1, 0);
        std::atomic<bool> crowded = false;
        const uint* masks = masks_.empty() ? nullptr : masks_.data();  // the last refinement's
        pool_.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
            bool many = false;
            first[w + 1] = count_masked_range(args, grid_.data(), masks, uint(b), uint(e), many);
            if (many) crowded = true;
        });
        Counts().swap(masks_);
        if (crowded) throw Error("internal: a base cell got more than 65535 darts in one round");
        const std::uint64_t total = chunk_offsets(first);
        clear_darts(total);
        // Numbering is a pass of its own: throwing reads the neighbours' words.
        pool_.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
            std::uint64_t next = first[w];
            for (std::size_t i = b; i < e; ++i) {
                uvec2& word = grid_[i];
                if (!masked_active(word)) continue;
                word = numbered_word(word, uint(next));
                next += packed_dart_count(word);
            }
        });
        const bool no_samples = out_.empty();
        pool_.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned) {
            for (std::size_t i = b; i < e; ++i) {
                const uvec2 w = grid_[i];
                if (grid_is_darts(w) && packed_dart_count(w) != 0u)  // most base cells get none
                    throw_masked_base(args, darts(), grid(), uint(i), grid_darts(w).x, no_samples);
            }
        });
        return total;
    }

    // Each base cell with darts keeps its accepted dart as its sample, or is empty again (in
    // arrival order an accepted dart took its word at once: a darts word left holds none).
    void commit(const RoundSpec& spec) {
        const Domain dom = plan_.domain;
        const bool taken = in_arrival_order();
        auto commit_word = [&](uvec2& w) { w = taken ? empty_after_round(w) : committed_word(darts(), w); };
        if (masked_) {
            // In arrival order, refinement and the next count pass read a darts word left here as
            // the empty word this would make of it; the explicit list after the last level cannot.
            if (taken && !masked_leaves(dom, spec.child_side(), spec.fanout())) return;
            pool_.parallel_for(plan_.base_cells, [&](std::size_t b, std::size_t e, unsigned) {
                for (std::size_t i = b; i < e; ++i)
                    if (grid_is_darts(grid_[i])) commit_word(grid_[i]);
            });
            return;
        }
        // The base cells that got darts (most listed cells got none), by their first darts.
        pool_.parallel_for(dart_count_, [&](std::size_t b, std::size_t e, unsigned) {
            uint last = b == 0 ? GRID_EMPTY : base_of_point(dom, dart_point(uint(b - 1)));
            for (std::size_t j = b; j < e; ++j) {
                const uint base = base_of_point(dom, dart_point(uint(j)));
                if (base != last && grid_is_darts(grid_[base])) commit_word(grid_[base]);
                last = base;
            }
        });
    }

    // Appends the round's accepted darts to the samples in arrival order: by (key, dart index),
    // dart index being spatial order, both in one 64-bit word. Each chunk of the darts is sorted
    // on the threads; their merge goes to out_. A dart left DART_TOO_COMPLEX (two radii) fails the run.
    void emit() {
        const std::size_t total = dart_count_;
        std::vector<std::vector<std::uint64_t>> accepted(pool_.chunks(total));
        std::atomic<bool> too_complex = false;
        pool_.parallel_for(total, [&](std::size_t b, std::size_t e, unsigned w) {
            std::size_t count = 0;
            for (std::size_t j = b; j < e; ++j) {
                const uint state = dart_at(darts(), uint(j)).w;
                count += state == DART_ACCEPTED ? 1 : 0;
                if (state == DART_TOO_COMPLEX) too_complex = true;
            }
            accepted[w].reserve(count);
            for (std::size_t j = b; j < e; ++j) {
                const uvec4 dart = dart_at(darts(), uint(j));
                if (dart.w == DART_ACCEPTED) accepted[w].push_back(std::uint64_t(dart.z) << 32 | j);
            }
            std::sort(accepted[w].begin(), accepted[w].end());
        });
        if (too_complex) throw Error(kTooComplex);
        std::uint64_t lists_bytes = 0;
        for (auto& a : accepted) lists_bytes += capacity_bytes(a);
        note_peak(lists_bytes);
        // The merge: a heap of each chunk's next word (distinct: it holds the dart index).
        using Head = std::tuple<std::uint64_t, std::size_t, std::size_t>;  // the word, its chunk and place
        std::priority_queue<Head, std::vector<Head>, std::greater<>> heads;
        for (std::size_t c = 0; c < accepted.size(); ++c)
            if (!accepted[c].empty()) heads.emplace(accepted[c][0], c, 0);
        while (!heads.empty()) {
            const auto [word, c, at] = heads.top();
            heads.pop();
            if (at + 1 < accepted[c].size()) heads.emplace(accepted[c][at + 1], c, at + 1);
            out_.emplace_back(dart_at(darts(), std::uint32_t(word)));
        }
    }

    // Mask mode: each base cell's word gets the mask of its surviving children (or cells, when they
    // do not split); at level MASK_LEVELS they go to an explicit list. Returns the active count.
    std::uint64_t refine_masked(const RoundSpec& spec) {
        const Domain dom = plan_.domain;
        const uint bases = uint(plan_.base_cells);
        const uint fanout = spec.fanout(), side = spec.child_side();
        const CellArgs args = cell_args(spec, bases, side, fanout);
        std::vector<std::uint64_t> first(pool_.chunks(bases) + 1, 0);
        if (!cover_tested(dom, fanout, side)) {
            // Every cell stays (surviving_children: active cells lie on the lattice), so the words
            // already hold the masks, and only their cells are counted.
            pool_.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
                std::uint64_t sum = 0;
                for (std::size_t i = b; i < e; ++i)
                    if (masked_active(grid_[i])) sum += uint(bitCount(grid_[i].y & GRID_MASK_BITS));
                first[w + 1] = sum;
            });
            return chunk_offsets(first);
        }
        if (!masked_leaves(dom, side, fanout)) {
            // The next round's count pass writes the masks to the words (refinement reads the
            // neighbours' words, so not this pass).
            fit(masks_, bases);
            note_peak();
            return refine_masked_scattered(pool_, args, grid(), masks_.data());
        }
        // Each chunk of base cells keeps its nonzero masks, in order, then writes their children.
        std::vector<std::vector<std::pair<uint, uvec2>>> kept(pool_.chunks(bases));
        pool_.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
            std::uint64_t sum = 0;
            for (std::size_t i = b; i < e; ++i) {
                const uvec2 mask = refine_masked_base(args, grid(), uint(i));
                if (mask == uvec2(0u, 0u)) continue;
                kept[w].emplace_back(uint(i), mask);
                sum += subcell_count(mask);
            }
            first[w + 1] = sum;
        });
        if (chunk_offsets(first) >= GRID_TAG) throw Error("more than 2^31 active cells");
        fit(cells_, first.back());
        std::uint64_t lists_bytes = 0;
        for (auto& k : kept) lists_bytes += capacity_bytes(k);
        note_peak(lists_bytes);
        pool_.parallel_for(bases, [&](std::size_t, std::size_t, unsigned w) {
            std::uint64_t next = first[w];
            for (const auto& [i, mask] : kept[w]) {
                scatter_subcells(dom, Cells{cells_.data()}, uint(next), mask, i, side);
                next += subcell_count(mask);
            }
        });
        masked_ = false;
        return cells_.size();
    }

    Cells cells() { return {cells_.data()}; }
    // The cells the round's darts are thrown into: the active cells, or with two radii the base
    // cells list_dart_cells lists.
    Words& dart_targets() { return two_radii(plan_.domain.radii) && !darts_on_cells_ ? dart_cells_ : cells_; }
    Darts darts() { return {darts_.data()}; }
    uvec2 dart_point(uint j) const { return {darts_[dart_record(j)], darts_[dart_record(j) + 1u]}; }
    Grid grid() { return {grid_.data()}; }
    Uints scan() { return {scan_.data()}; }

    // Two radii: the base cells that get darts this round, from the active cells (see flag_dart_cells).
    void list_dart_cells(const RoundSpec& spec) {
        // Darts for every free base cell, while the active list is still start's list of them:
        // that list serves, and a copy of it (8 bytes a base cell) would be the run's peak.
        darts_on_cells_ = spec.every_free_cell && cells_free_bases_;
        if (darts_on_cells_) return;
        const Domain dom = plan_.domain;
        const uint n = uint(cells_.size());
        const uint bases = uint(plan_.base_cells);
        const Uints flags = flags_.zeroed(pool_, bases);
        const CellArgs args = cell_args(spec, n, spec.side, 0);
        if (spec.every_free_cell) {
            pool_.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned) {
                for (std::size_t i = b; i < e; ++i) flag_free_cell(grid(), flags, uint(i));
            });
        } else {
            const std::vector<int> rows = dart_scan_rows(dom);
            pool_.parallel_for(n, [&](std::size_t b, std::size_t e, unsigned) {
                for_each_base_group(dom, cells(), b, e, n, false, [&](uint g, uint end) {
                    flag_dart_runs(args, rows.data(), cells(), flags, grid(), g, end);
                });
            });
        }
        flags_.list(pool_, dom, dart_cells_);
    }

    // Exclusive prefix sum of scan_[0, n) in place; scan_[n] becomes the total. Unrolled: with two
    // radii each round scans every base cell's flag.
    std::uint64_t exclusive_scan(uint n) {
        std::uint64_t sum = 0;
#pragma GCC unroll 8
        for (uint i = 0; i < n; ++i) sum += std::exchange(scan_[i], uint(sum));
        scan_[n] = uint(sum);
        return sum;
    }

    // The darts decided and emitted in arrival order (arrival_order.h), at half the instructions
    // of the parallel resolution, which only more threads repay.
    bool in_arrival_order() const {
        return resolution_ == Resolution::ArrivalOrder ||
               (resolution_ == Resolution::Parallel && pool_.size() <= kArrivalOrderThreads);
    }

    // Decides the round's undecided darts: in arrival order, or on many threads in parallel.
    void resolve() {
        const Domain dom = plan_.domain;
        const std::size_t total = dart_count_;
        if (resolution_ == Resolution::Serial) {
            note_peak(resolve_in_arrival_order(dom, grid(), darts(), uint(total)));
            return;
        }
        if (in_arrival_order()) {
            note_peak(decide_in_arrival_order(dom, grid(), darts(), uint(total), out_, pool_, plan_.strip_darts));
            return;
        }
        decide_in_parallel(dom, grid(), darts(), total, pool_);
    }

    // Keeps or splits the active cells of the list; returns their count.
    std::uint64_t refine(const RoundSpec& spec) {
        const Domain dom = plan_.domain;
        const uint fanout = spec.fanout(), side = spec.child_side();
        if (free_bases_) {
            note_peak(refine_free_bases(pool_, cell_args(spec, plan_.base_cells, side, fanout), grid(), cells_));
            free_bases_ = false;
            return cells_.size();
        }
        const uint n = uint(cells_.size());
        if (std::size_t(n) * fanout >= GRID_TAG) throw Error("more than 2^31 active cells");
        fit(scan_, std::size_t(n) + 1);
        fit(masks_, n);
        const CellArgs args = cell_args(spec, n, side, fanout);
        pool_.parallel_for(n, [&](std::size_t b, std::size_t e, unsigned) {
            for_each_base_group(dom, cells(), b, e, n, false, [&](uint g, uint end) {
                refine_cells_of_base(args, cells(), scan(), Uints{masks_.data()}, grid(), g, end);
            });
        });
        const std::uint64_t kept = exclusive_scan(n);
        fit(next_, kept);
        note_peak();
        pool_.parallel_for(n, [&](std::size_t b, std::size_t e, unsigned) {
            for (std::size_t i = b; i < e; ++i)
                scatter_children(args, cells(), scan(), Uints{masks_.data()}, Cells{next_.data()}, uint(i));
        });
        cells_.swap(next_);
        Words().swap(next_);
        cells_free_bases_ = false;
        Counts().swap(masks_);
        return cells_.size();
    }

    BlocksReleased released_;  // first, so that it goes last
    Plan plan_;
    Resolution resolution_;
    ThreadPool pool_;
    // Mask mode (sampler.h) at levels 0 to MASK_LEVELS - 1, for the cpu backend with one radius
    // (set by start); the serial backend, the oracle, keeps the explicit list that the GPU runs.
    bool masked_ = false;
    Words grid_;
    Words cells_;
    Words next_;
    Words dart_cells_;               // two radii: the base cells that get darts this round
    bool cells_free_bases_ = false;  // cells_ is start's list of the base cells without a sample
    bool free_bases_ = false;        // two radii: the active cells are the free base cells, unlisted
    bool darts_on_cells_ = false;    // two radii: this round's darts go to cells_ (dart_targets)
    Counts darts_;                   // this round's darts, stored as darts.h says
    std::uint64_t dart_count_ = 0;
    Counts scan_;
    DartFlags flags_;  // two radii: the base cells that get darts this round
    Counts masks_;
    std::vector<uvec2> out_;  // samples in acceptance order
    std::uint64_t peak_ = 0;  // see note_peak
    bool profiling_ = false;
    PhaseTimes times_;
};

}  // namespace

std::unique_ptr<Engine> make_host_engine(const Plan& plan, Resolution resolution, unsigned threads) {
    return std::make_unique<HostEngine>(plan, resolution, threads);
}

}  // namespace vrpd::detail
