// The sampler of a sizing field (paper section 5): arrival-order random sequential adsorption on
// the lattice, exact under the rule, maximal on the lattice. Rounds of darts, a Poisson process
// over the active cells (uniform in the weighted measure), resolved in arrival order; active
// cells dropped when one sample covers them under the rule, split where darts fell or, once few
// are left, all open ones (the tests against the samples: field/cover.cpp; resolution:
// field/resolve.cpp). Design and bounds: docs/design.md, "Sizing fields".
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "field.h"
#include "power_sum.h"
#include "rate.h"
#include "shared/field_run.h"
#include "sampler.h"
#include "vrpd/sizing.h"
#include "../plan.h"
#include "../vulkan/field_engine.h"

namespace vrpd::detail {

namespace field {

namespace {
using Clock = std::chrono::steady_clock;

constexpr std::uint32_t kMaxRounds = 1000000;  // a bug guard, far above any run
constexpr int kExpBias = kExponentBias;        // exp_neg_'s index: the weighted area's exponent + 64
constexpr std::size_t kExponents = std::tuple_size_v<ExponentCounts>;
// A cell's fate in got_ (balance, refine): shared/field_run.h's, as the field kernels write it.
constexpr std::uint8_t kKeep = shared::FIELD_KEEP, kSplit = shared::FIELD_SPLIT;
// The cells a fate leaves in the next list.
std::uint64_t cells_of(std::uint8_t fate) { return fate == kKeep ? 1 : std::uint64_t(std::popcount(fate & 0xFu)); }
// The chunks' counts of cells per exponent, added.
ExponentCounts summed(const std::vector<ExponentCounts>& counts) {
    ExponentCounts total{};
    for (const auto& count : counts)
        for (std::size_t e = 0; e < kExponents; ++e) total[e] += count[e];
    return total;
}

}  // namespace

Cell FieldSampler::make_cell(uvec2 corner, std::uint32_t bits) const {
    Cell c{corner, std::uint8_t(bits), 0};
    if (density_) c.weight = std::uint8_t(shared::field_cell_weight(t_.r_lo, t_.min_over(corner, far_corner(c))));
    return c;
}

double FieldSampler::weighted_area() {
    // The cells per exponent (as the last list written counted them, else counted on the
    // threads); their exact sum is the serial sum's value.
    if (!exponents_) {
        std::vector<ExponentCounts> counts(cell_chunks());
        for_cells([&](std::size_t begin, std::size_t end, unsigned w) {
            ExponentCounts count{};
            for (std::size_t i = begin; i < end; ++i) ++count[std::size_t(exponent(i) + kExpBias)];
            counts[w] = count;
        });
        exponents_ = summed(counts);
    }
    if (const auto sum = exact_power_sum(*exponents_, kExpBias)) return *sum;
    double area = 0;
    for (std::size_t i = 0; i < cells_.size(); ++i) area += pow2(exponent(i));
    return area;
}

template <typename Fate>
void FieldSampler::write_fates(Cells& next, const std::vector<std::uint64_t>& first, Fate&& fate) {
    std::vector<ExponentCounts> counts(first.size() - 1);
    for_cells([&](std::size_t begin, std::size_t end, unsigned w) {
        std::size_t at = first[w];
        ExponentCounts& count = counts[w];
        for (std::size_t i = begin; i < end; ++i) {
            const std::uint8_t f = fate(i);
            if (f == kKeep) {
                next.copy(at++, cells_, i);
                ++count[std::size_t(exponent(i) + kExpBias)];
            }
            if (f & kSplit)
                for (std::uint32_t k = 0; k < 4; ++k)
                    if (f >> k & 1) {
                        const Cell c = *child(cells_[i], k);
                        next.set(at++, c);
                        ++count[std::size_t(exponent(c.bits, c.weight) + kExpBias)];
                    }
        }
    });
    exponents_ = summed(counts);
}

double FieldSampler::balance() {
    for (;;) {
        const double rate = kLambda * double(cells_.size()) / weighted_area();
        // No cell splits if the largest weighted area present does not.
        std::size_t top = kExponents;
        while (top > 0 && (*exponents_)[top - 1] == 0) --top;
        if (top == 0 || rate * pow2(int(top - 1) - kExpBias) <= kSplitAbove) return rate;
        auto splits = [&](std::size_t i) { return cells_.bits(i) > 0 && rate * pow2(exponent(i)) > kSplitAbove; };
        // A cell's fate: kept, or split with the mask of its children not covered by a sample.
        // Before the first sample it costs a few instructions and is found again when written;
        // after, it is kept in got_ (one search a split cell).
        const bool store = !lattice_.empty();
        auto fate_of = [&](std::size_t i, std::vector<std::uint32_t>& near) {
            if (!splits(i)) return kKeep;
            const Cell c = cells_[i];
            if (store)
                gather(c, near);
            else
                near.clear();
            return std::uint8_t(kSplit | open_children(near, c));
        };
        if (store) got_.resize(cells_.size());
        std::vector<std::uint64_t> first(cell_chunks() + 1, 0);
        std::vector<char> split(first.size() - 1, 0);
        for_cells([&](std::size_t begin, std::size_t end, unsigned w) {
            std::vector<std::uint32_t> near;
            std::uint64_t count = 0;
            for (std::size_t i = begin; i < end; ++i) {
                const std::uint8_t fate = fate_of(i, near);
                if (store) got_[i] = fate;
                split[w] |= fate != kKeep;
                count += cells_of(fate);
            }
            first[w + 1] = count;
        });
        if (std::find(split.begin(), split.end(), 1) == split.end()) return rate;
        Cells next(density_, chunk_offsets(first));
        note_bytes(next.bytes());
        std::vector<std::uint32_t> unused;  // before the first sample fate_of reads no list
        write_fates(next, first, [&](std::size_t i) { return store ? got_[i] : fate_of(i, unused); });
        std::swap(cells_, next);
    }
}

void FieldSampler::throw_darts(std::uint32_t round) {
    const double rate = balance();
    exp_neg_table(rate, exp_neg_);
    const std::uint32_t key = shared::round_key(seed_, round);
    // First each cell's count of darts, kept in got_ (kRecount: count again) and summed per chunk.
    // The dart list is then allocated once, at the darts thrown, and each chunk writes the darts
    // its conflict tests leave from its chunk's offset; the chunks' runs are then moved together.
    // A list per chunk would hold the round's darts twice while they are joined.
    constexpr std::uint8_t kRecount = 255;
    got_.resize(cells_.size());
    std::vector<std::uint64_t> first(cell_chunks() + 1, 0);
    auto count_of = [&](std::size_t i, std::uint32_t stream) {
        return shared::dart_count(stream, exp_neg_[exponent(i) + kExpBias]);
    };
    for_cells([&](std::size_t begin, std::size_t end, unsigned w) {
        std::uint64_t count = 0;
        for (std::size_t i = begin; i < end; ++i) {
            const std::uint32_t n = count_of(i, shared::cell_stream(key, cells_.corner(i)));
            got_[i] = std::uint8_t(std::min<std::uint32_t>(n, kRecount));
            count += n;
        }
        first[w + 1] = count;
    });
    const std::uint64_t thrown = chunk_offsets(first);
    darts_.resize(thrown);
    note_bytes(0);
    std::vector<std::uint64_t> kept(first.size() - 1, 0);
    for_cells([&](std::size_t begin, std::size_t end, unsigned w) {
        Dart* const start = darts_.data() + first[w];
        Dart* out = start;
        for (std::size_t i = begin; i < end; ++i) {
            if (got_[i] == 0) continue;
            const Cell c = cells_[i];
            const std::uint32_t stream = shared::cell_stream(key, c.corner);
            const std::uint32_t n = got_[i] == kRecount ? count_of(i, stream) : got_[i];
            got_[i] = 1;
            const std::uint32_t leaf = tree_.leaf_of(c.corner);
            const std::uint32_t bound =
                std::uint32_t(std::min<std::uint64_t>(std::uint64_t(t_.r_lo) << c.weight, UINT32_MAX));
            for (std::uint32_t j = 0; j < n; ++j) {
                const glm::uvec4 d = shared::make_dart(stream, j, c.corner, 1u << c.bits);
                const uvec2 p(d.x, d.y);
                if (!shared::in_lattice(t_.lattice, p)) continue;
                const std::uint32_t r = t_.radius(p);
                if (density_ &&
                    !shared::keep_weighted(shared::hash_mix(shared::hash_mix(stream, 0xD1B54A35u), j), bound, r))
                    continue;
                if (tree_.sample(leaf) != FieldQuadtree::kNone) continue;
                // A sample in conflict with a point of the leaf has stamped it: none has if it is
                // unstamped. Else the one sample that last stamped it or last rejected a dart in
                // it (an earlier round's, near it), if there is one, is the likeliest conflict:
                // tested before the search, and replaced by the sample a search finds.
                std::atomic_ref<std::uint32_t> hint(touched_[leaf]);
                const std::uint32_t near = hint.load(std::memory_order_relaxed);
                if ((near | kWholeCell) != kUnstamped) {
                    if (!(near & kStampedMany) && conflicts_with(near & kStampValue, p, r)) continue;
                    if (const std::uint32_t s = conflicting(p, r); s != FieldQuadtree::kNone) {
                        hint.store(s | (near & kWholeCell), std::memory_order_relaxed);
                        continue;
                    }
                }
                *out++ = {p, d.z, leaf};
            }
        }
        kept[w] = std::uint64_t(out - start);
    });
    // Chunk c precedes chunk c + 1 (thread_pool.h): in chunk order is cell order.
    std::uint64_t size = 0;
    for (std::size_t w = 0; w < kept.size(); ++w) {
        if (size != first[w])  // a run moves down, so a forward copy never reads what it wrote
            std::copy_n(darts_.begin() + std::ptrdiff_t(first[w]), kept[w], darts_.begin() + std::ptrdiff_t(size));
        size += kept[w];
    }
    darts_.resize(size);
    darts_thrown_ += thrown;
}

std::uint32_t FieldSampler::refine() {
    // First each cell's fate, written over its got_ entry once read. Then each chunk writes its
    // cells to the next list from its offset: every cell is copied once, and no third list is held.
    std::vector<std::uint64_t> first(cell_chunks() + 1, 0);
    std::vector<std::uint32_t> least(first.size() - 1, UINT32_MAX);  // per chunk, the next list's least bits
    const bool every = splits_every_cell(cells_.size(), tree_.leaves());
    for_cells([&](std::size_t begin, std::size_t end, unsigned w) {
        std::vector<std::uint32_t> near;
        std::uint64_t count = 0;
        std::uint32_t least_bits = UINT32_MAX;
        FieldQuadtree::Leaf at{};  // the last cell's leaf: a leaf's cells are consecutive
        for (std::size_t i = begin; i < end; ++i) {
            const uvec2 corner = cells_.corner(i);
            if (i == begin || !at.holds(corner)) at = tree_.leaf_at(corner);
            const std::uint32_t leaf = at.index;
            // Whether it splits if it stays open: it took darts, or every cell does (field_splits).
            const bool splits = got_[i] != 0 || every;
            if (!splits && !stamped(leaf)) {  // no dart and no sample of this round near: kept
                got_[i] = kKeep;
                ++count;
                least_bits = std::min(least_bits, cells_.bits(i));
                continue;
            }
            const Cell c = cells_[i];
            const bool whole = c.bits == at.bits;
            std::uint8_t fate = 0;
            if (tree_.sample(leaf) != FieldQuadtree::kNone || covered_by_fresh(c.corner, far_corner(c), leaf, whole)) {
                fate = 0;
            } else if (!splits || c.bits == 0) {
                fate = kKeep;
            } else {
                // Split: the children are tested against every sample that may cover part of the
                // cell, found by one search (an earlier round's sample may cover a child).
                gather(c, near);
                fate = std::uint8_t(kSplit | open_children(near, c));
            }
            // The leaf's one cell, dropped or split: none of the leaf's cells is ever whole again.
            if (whole && fate != kKeep) touched_[leaf] &= ~kWholeCell;
            got_[i] = fate;
            count += cells_of(fate);
            if (cells_of(fate) > 0)
                least_bits = std::min<std::uint32_t>(least_bits, fate == kKeep ? c.bits : c.bits - 1);
        }
        first[w + 1] = count;
        least[w] = least_bits;
    });
    Cells next(density_, chunk_offsets(first));
    note_bytes(next.bytes());
    write_fates(next, first, [&](std::size_t i) { return got_[i]; });
    std::swap(cells_, next);
    return *std::min_element(least.begin(), least.end());
}

void FieldSampler::add_given(const std::vector<uvec2>& given, bool checked) {
    // A sample from the options is named as given; a hierarchy's earlier levels' samples, which
    // never conflict (r only shrinks), by their point.
    auto name = [&](std::size_t i) {
        const glm::dvec2 q = i < initial_.size() ? initial_[i] : glm::dvec2(given[i]) * t_.quantum;
        return fmt::format("{} ({}, {})", i + 1, q.x, q.y);
    };
    for (std::size_t i = 0; i < given.size(); ++i) {
        const uvec2 p = given[i];
        const std::uint32_t r = t_.radius(p), leaf = tree_.leaf_of(p);
        // Two points of one leaf conflict under every rule (its diagonal is below r anywhere in it).
        std::uint32_t s = tree_.sample(leaf);
        if (s == FieldQuadtree::kNone && !checked) s = conflicting(p, r);
        if (s != FieldQuadtree::kNone)
            throw Error(fmt::format("given samples {} and {} conflict under the {} rule on the run's lattice", name(s),
                                    name(i), sizing_rule_name(SizingRule(rule_))));
        tree_.set_sample(leaf, p, add_sample(p, r));
    }
}

void FieldSampler::place_given(const std::vector<uvec2>& given, bool checked) {
    add_given(given, checked);
    // Stamped as one round's samples, they drop the leaves they cover; the rest stay, each tested
    // against every sample of its time, as the rounds' refinement keeps its cells.
    for_fresh([&](std::uint32_t s) { touch(s); });
    got_.assign(cells_.size(), 0);
    refine();
    for_fresh([&](std::uint32_t s) { tree_.settle(lattice_[s]); });
}

Sampling FieldSampler::run(const std::vector<uvec2>& given, bool checked, std::uint32_t first_round) {
    // Every leaf an active cell, unstamped; a run of tiles is a run of leaves, written by one thread.
    cells_.resize(tree_.leaves());
    touched_.resize(tree_.leaves());
    pool_.parallel_for(
        tree_.tiles(),
        [&](std::size_t begin, std::size_t end, unsigned) {
            tree_.each_leaf(begin, end, [&](std::uint32_t leaf, uvec2 corner, std::uint32_t bits) {
                cells_.set(leaf, make_cell(corner, bits));
                touched_[leaf] = kUnstamped;
            });
        },
        FieldQuadtree::kTileGrain);
    // Runs one phase, timed when the run is profiled.
    auto phase = [&](const char* name, auto&& body) {
        const auto t0 = Clock::now();
        body();
        if (profile_) phases_.add(name, std::chrono::duration<double>(Clock::now() - t0).count());
    };
    if (!given.empty()) phase("given", [&] { place_given(given, checked); });
    std::uint32_t round = 0;
    std::uint32_t deepest = 0;
    while (!cells_.empty()) {
        if (round == kMaxRounds) throw Error("internal: the sizing-field sampler did not converge");
        round_ = round + 1;
        round_first_ = std::uint32_t(lattice_.size());  // this round's samples are fresh until refined
        phase("throw", [&] { throw_darts(first_round + round); });
        phase("resolve", [&] { resolve(); });
        decltype(darts_)().swap(darts_);
        std::uint32_t least_bits = UINT32_MAX;
        phase("refine", [&] { least_bits = refine(); });
        ++round;
        if (!cells_.empty()) deepest = std::max(deepest, t_.tile_bits - least_bits);
        for_fresh([&](std::uint32_t s) { tree_.settle(lattice_[s]); });
    }
    Sampling s;
    s.lattice.assign(lattice_.begin(), lattice_.end());
    s.stats.levels = deepest;
    s.stats.rounds = round;
    s.stats.darts = darts_thrown_;
    s.stats.peak_bytes = bytes_ + t_.bytes();
    s.stats.profile = phases_.phases();
    return s;
}

}  // namespace field

Sampling sample_field(const SampleOptions& o, const FieldTable& t) {
    // tabulate() refused a field whose expected samples exceed memory; the leaves stay within a
    // 64th of it besides.
    const MemoryLimit limit = host_memory_limit();
    const std::uint64_t max_leaves = std::uint64_t(double(limit.bytes) / 64);
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    Sampling out;
    std::vector<glm::uvec2> samples = given_on_lattice(o, t.quantum, t.lattice);
    // A hierarchy's levels (a direct run is one): the field scaled by S t_k on t's lattice, each
    // level completing the last one's samples, its darts from the rounds after the last one's.
    // r only shrinks from level to level, so the earlier samples stay conflict-free.
    PhaseTimes phases;
    auto since = [](Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); };
    const std::vector<HierarchyStep> steps = hierarchy_steps(o);
    // The levels' tables are scaled on threads of their own (the samplers' come and go).
    std::optional<ThreadPool> pool;
    if (steps.size() > 1) pool.emplace(o.backend == Backend::Serial ? 1 : o.threads);
    // On a Vulkan device, one context and its kernels serve every level.
    std::optional<FieldDevice> device;
    if (o.backend == Backend::Gpu) device.emplace(o, t);
    std::string host;  // the host sampler's name, without a device
    for (std::size_t k = 0; k < steps.size(); ++k) {
        const auto [birth, scale] = steps[k];
        std::optional<FieldTable> own;
        const auto scaling = Clock::now();
        if (scale != 1) {
            own = scaled(t, scale, *pool);
            phases.add("scale", since(scaling));
        }
        const FieldTable& level = own ? *own : t;
        const auto built = Clock::now();
        Sampling s;
        if (device) {
            // The options' given samples are checked on the host, as the host backends check them
            // (one by one, in their order); a level's given samples, the earlier levels', need not be.
            if (k == 0 && !samples.empty()) field::FieldSampler(level, o, max_leaves).check_given(samples);
            s = device->run(level, max_leaves, samples, out.stats.rounds);
        } else {
            field::FieldSampler sampler(level, o, max_leaves);
            phases.add("leaves", since(built));
            // Given samples from the options are checked against each other; a level's given
            // samples, the earlier levels', are conflict-free by the scales' order.
            s = sampler.run(samples, k > 0, out.stats.rounds);
            host = sampler.device_name();
        }
        out.stats.rounds += s.stats.rounds;
        out.stats.darts += s.stats.darts;
        out.stats.levels = std::max(out.stats.levels, s.stats.levels);
        // Beside the level's arrays: the given samples, and the final table under a scaled one.
        out.stats.peak_bytes = std::max(
            out.stats.peak_bytes, s.stats.peak_bytes + samples.capacity() * sizeof(glm::uvec2) + (own ? t.bytes() : 0));
        for (const PhaseTime& p : s.stats.profile) phases.add(p);
        samples = std::move(s.lattice);
        if (o.hierarchy.steps != 0) out.birth.resize(samples.size(), birth);
    }
    if (o.hierarchy.continuous) {
        // The final field holds about S^2 times the first level's samples.
        const double scale = hierarchy_start(o);
        require_memory("the continuous hierarchy", double(samples.size()) * scale * scale, kContinuousBytesPerSample);
        const auto events = Clock::now();
        const std::uint64_t bytes = continue_hierarchy(t, o, max_leaves, samples, out.birth);
        out.stats.peak_bytes = std::max(out.stats.peak_bytes, bytes + t.bytes());
        phases.add("events", since(events));
    }
    out.lattice = std::move(samples);
    out.quantum = t.quantum;
    out.radius = out.coverage = t.r_lo * t.quantum;
    out.local_radius.reserve(out.size());
    for (const glm::uvec2 p : out.lattice) out.local_radius.push_back(t.radius(p) * t.quantum);
    out.field = t.stats();
    out.hierarchy_start = o.hierarchy.steps != 0 || o.hierarchy.continuous ? hierarchy_start(o) : 1.0;
    out.stats.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    out.box = o.box;
    out.backend = o.backend == Backend::Serial || o.backend == Backend::Gpu ? o.backend : Backend::Cpu;
    out.device = host;
    if (device) {
        out.device = device->device_name();
        out.stats.round_trips = device->round_trips();
        if (o.profile)
            for (const PhaseTime& p : device->profile()) phases.add(p);
    }
    if (o.profile) out.stats.profile = phases.phases();
    return out;
}

}  // namespace vrpd::detail
