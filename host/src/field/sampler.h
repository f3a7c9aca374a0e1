// The sizing-field sampler's state and steps (field/engine.cpp; resolution in field/resolve.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "quadtree.h"
#include "rate.h"
#include "../cpu/thread_pool.h"
#include "../cpu/uninitialised.h"
#include "../phase_times.h"
#include "shared/darts.h"
#include "vrpd/vrpd.h"

namespace vrpd::detail::field {

using shared::uvec2;

// An active cell: a block of one leaf (found from its corner, FieldQuadtree::leaf_of).
struct Cell {
    uvec2 corner;
    std::uint8_t bits;
    std::uint8_t weight;  // Eq. 12: darts at the rate of radius r_lo 2^weight (<= r over the cell)
};

// The active list, 8 bytes a cell, and under Eq. 12 a byte of weight beside it: the corner's y,
// and its x with the side as 2 x + 2^bits, whose lowest set bit is bit `bits` (x is a multiple of
// 2^bits below 2^31, so the sum fits the word). Filled by the pool's threads, which make the
// first touch of its pages.
class Cells {
public:
    explicit Cells(bool weighted, std::size_t n = 0) : weighted_(weighted) { resize(n); }
    std::size_t size() const { return words_.size(); }
    bool empty() const { return words_.empty(); }
    void resize(std::size_t n) {
        words_.resize(n);
        if (weighted_) weights_.resize(n);
    }
    Cell operator[](std::size_t i) const { return {corner(i), std::uint8_t(bits(i)), weight(i)}; }
    // Cell i's corner, its side exponent and its weight, each alone (the corner's x: the word
    // without its lowest set bit, halved).
    uvec2 corner(std::size_t i) const { return {(words_[i].x & (words_[i].x - 1)) >> 1, words_[i].y}; }
    std::uint32_t bits(std::size_t i) const { return std::uint32_t(std::countr_zero(words_[i].x)); }
    std::uint8_t weight(std::size_t i) const { return weighted_ ? weights_[i] : std::uint8_t(0); }
    // Cell i of `from` as cell `at`, copied as stored.
    void copy(std::size_t at, const Cells& from, std::size_t i) {
        words_[at] = from.words_[i];
        if (weighted_) weights_[at] = from.weights_[i];
    }
    void set(std::size_t i, const Cell& c) {
        words_[i] = {2 * c.corner.x + (1u << c.bits), c.corner.y};
        if (weighted_) weights_[i] = c.weight;
    }
    std::uint64_t bytes() const { return words_.capacity() * sizeof(uvec2) + weights_.capacity(); }

private:
    bool weighted_;
    std::vector<uvec2, Uninitialised<uvec2, true>> words_;
    std::vector<std::uint8_t, Uninitialised<std::uint8_t, true>> weights_;
};

// A dart still undecided after its throw, in throwing order (cell order, then index in the cell):
// the tie-break of equal keys. It carries its cell's leaf: the textbook resolution reads it in
// arrival order (one random read fewer than through the cell), the parallel one finds a leaf's
// darts through it.
struct Dart {
    uvec2 p;
    std::uint32_t key, leaf;
};

class FieldSampler {
public:
    FieldSampler(const FieldTable& t, const SampleOptions& o, std::uint64_t max_leaves)
        : t_(t),
          pool_(o.backend == Backend::Serial ? 1 : o.threads),
          tree_(t, max_leaves, pool_),
          rule_(std::uint32_t(o.sizing->rule)),
          density_(o.sizing->weighting == Weighting::Density),
          seed_(o.seed),
          serial_(o.backend == Backend::Serial),
          cells_(density_),
          profile_(o.profile),
          initial_(o.initial) {
        bytes_ = tree_.build_bytes();
    }

    // Samples until maximal from `given` (lattice points, first in the output, in their order),
    // with the darts of rounds first_round on (a hierarchy's levels go on counting); gives the
    // samples and the stats, and sample_field the rest. Unless the caller knows the given samples
    // conflict-free (`checked`), throws Error if one conflicts with an earlier one under the rule.
    Sampling run(const std::vector<uvec2>& given, bool checked, std::uint32_t first_round);
    // Only the check of run's given samples (for a Vulkan run, which takes them checked): throws
    // the same Error if one conflicts with an earlier one under the rule.
    void check_given(const std::vector<uvec2>& given) { add_given(given, false); }
    // The host as the one-radius engines name theirs.
    std::string device_name() const { return serial_ ? "serial (host, one thread)" : pool_.device_name(); }

private:
    // The farthest an earlier sample conflicting with some point of [a, b] can be, given the
    // largest r over [a, b] (docs/design.md derives each rule's bound).
    std::uint64_t reach(uvec2 a, uvec2 b, std::uint32_t r_hi) const;
    // The farthest a point sample x (radius r) may cover under the rule.
    std::uint64_t cover_reach(uvec2 x, std::uint32_t r) const;
    // Both grow f = max(r(z), r_hi) by FieldTable::grown_reach: a search takes one tightening
    // step (a second costs more than its narrower square saves); a sample's stamps take up to
    // four (each leaf stamped costs a re-test of its cells).
    // Is the reach of a search for point p (radius r) so much wider than r (a steep field) that
    // subtrees are worth testing before they are entered (within)?
    static bool steep(std::uint64_t reach, std::uint32_t r) { return reach > 4 * std::uint64_t(r) + 4; }
    // The test a steep search asks before it enters a subtree: may a point of the block lie
    // within f of [a, b]? f is the rule's f between the largest r over the block and r, the
    // block's taken as the earlier point's where `block_earlier`, else as the later one's. On a
    // torus the nearest image of the block counts.
    auto within(uvec2 a, uvec2 b, std::uint32_t r, bool block_earlier) const {
        return [this, a, b, r, block_earlier](glm::i64vec2 image, uvec2 corner, std::uint32_t bits) {
            const glm::u64vec2 g = tree_.image_gaps(image, bits, a, b);
            const std::uint64_t gx = g.x, gy = g.y;
            const std::uint32_t hi = t_.max_over(corner, far_corner(corner, bits));
            // A gap of f or more is out along one axis (and the squares below stay below 2^63).
            const std::uint32_t f = block_earlier ? shared::rule_f(rule_, hi, r) : shared::rule_f(rule_, r, hi);
            return gx < f && gy < f && shared::field_conflict(f, gx * gx + gy * gy);
        };
    }
    // search(enter) with within(a, b, r, block_earlier) as `enter` where `steep`, else the plain
    // search (FieldQuadtree::EnterAll).
    template <typename Search>
    auto search_within(bool steep, uvec2 a, uvec2 b, std::uint32_t r, bool block_earlier, Search search) const {
        if (steep) [[unlikely]]
            return search(within(a, b, r, block_earlier));
        return search(FieldQuadtree::EnterAll{});
    }
    // Does sample s conflict with a later point p of radius r?
    bool conflicts_with(std::uint32_t s, uvec2 p, std::uint32_t r) const;
    // A sample in conflict with point p of radius r, or kNone. (steep_conflicting: the search of a
    // steep reach f, kept out of line.)
    std::uint32_t conflicting(uvec2 p, std::uint32_t r) const;
    std::uint32_t steep_conflicting(uvec2 p, std::uint32_t r, std::uint64_t f) const;
    // Does one of this round's samples conflict with point p (radius r) of leaf `leaf`?
    bool conflicts_fresh(uvec2 p, std::uint32_t r, std::uint32_t leaf) const;
    // The samples that may cover one of the children of cell c wholly (c.bits >= 1).
    void gather(const Cell& c, std::vector<std::uint32_t>& out) const;
    // Does a search of reach f around [a, b] pass half the torus? Then a cover search keeps the
    // block's square rather than going around its middle (covered_by_fresh).
    bool wraps(uvec2 a, uvec2 b, std::uint64_t f) const {
        const shared::Lattice& l = t_.lattice;
        return l.periodic && (2 * (f + b.x - a.x) >= l.extent_x || 2 * (f + b.y - a.y) >= l.extent_y);
    }
    // The middle lattice points of [lo, hi] along one axis, [lo + floor(w / 2), lo + ceil(w / 2)],
    // and ceil(w / 2): how far beyond a sample's gap to them the axis's farther end lies.
    struct Middle {
        std::uint32_t from, to, half;
    };
    static Middle middle(std::uint32_t lo, std::uint32_t hi) {
        const std::uint32_t w = hi - lo;
        return {lo + w / 2, lo + (w + 1) / 2, (w + 1) / 2};
    }
    // The mask of cell c's children (bit k: child k) that lie in the lattice and that none of
    // `near` covers wholly under the rule.
    std::uint8_t open_children(const std::vector<std::uint32_t>& near, const Cell& c) const;
    // Does one of this round's samples (fresh in the tree) cover every point of [a, b], a block
    // of leaf `leaf` (the whole leaf where `whole`)? For a cell of the active list this is whether
    // any sample does: each cell was made, or last kept, by a test against every sample of its
    // time, so none of the earlier rounds' covers it.
    bool covered_by_fresh(uvec2 a, uvec2 b, std::uint32_t leaf, bool whole) const;
    // Does sample s cover [a, b], given r's least value `lo` over it: is the farthest corner
    // within f(r(s), lo), f's least value over the block?
    bool covers(std::uint32_t s, std::uint32_t lo, uvec2 a, uvec2 b) const;
    // The same, reading lo only where the rule needs it.
    bool covers(std::uint32_t s, uvec2 a, uvec2 b) const;
    // The same for a sample of radius r whose squared distance to the block's farthest point is
    // d2, calling least() for lo only where the rule needs it (f is min(r, lo) under smaller,
    // max(r, lo) under bigger: the test with r alone decides one way first; under prior lo goes
    // unread). A least() that gives 0 says no lo covers.
    template <typename Least>
    bool covers_far(std::uint32_t r, std::uint64_t d2, Least&& least) const {
        const bool own = shared::field_conflict(r, d2);
        if (rule_ == shared::RULE_PRIOR || (rule_ == shared::RULE_SMALLER && !own) ||
            (rule_ == shared::RULE_BIGGER && own))
            return own;
        return shared::field_conflict(least(), d2);
    }
    // The squared distance from sample s to the farthest point of [a, b] (shared::far_distance2).
    std::uint64_t far_distance2(std::uint32_t s, uvec2 a, uvec2 b) const;
    Cell make_cell(uvec2 corner, std::uint32_t bits) const;
    // The corner of child k of c (x, then y, low first), unless it lies outside the lattice.
    std::optional<uvec2> child_corner(const Cell& c, std::uint32_t k) const {
        const std::uint32_t half = 1u << (c.bits - 1);
        const uvec2 corner(c.corner.x + (k & 1) * half, c.corner.y + (k >> 1) * half);
        if (corner.x >= t_.lattice.extent_x || corner.y >= t_.lattice.extent_y) return std::nullopt;
        return corner;
    }
    std::optional<Cell> child(const Cell& c, std::uint32_t k) const {
        if (const auto corner = child_corner(c, k)) return make_cell(*corner, c.bits - 1);
        return std::nullopt;
    }
    // The last lattice point of the block of side 2^bits at `corner` (clipped to the lattice).
    uvec2 far_corner(uvec2 corner, std::uint32_t bits) const {
        const std::uint64_t s = (std::uint64_t(1) << bits) - 1;
        return {std::uint32_t(std::min<std::uint64_t>(corner.x + s, t_.lattice.extent_x - 1)),
                std::uint32_t(std::min<std::uint64_t>(corner.y + s, t_.lattice.extent_y - 1))};
    }
    uvec2 far_corner(const Cell& c) const { return far_corner(c.corner, c.bits); }
    // The chunks of the loops over the active cells, and such a loop: body(begin, end, chunk).
    // Cells (and darts) go to the threads from kCellGrain on: a search costs thousands of
    // instructions, and the late rounds hold a few hundred cells.
    static constexpr std::size_t kCellGrain = 128;
    std::size_t cell_chunks() const { return pool_.chunks(cells_.size(), kCellGrain); }
    template <typename Body>
    void for_cells(Body&& body) {
        pool_.parallel_for(cells_.size(), body, kCellGrain);
    }
    // The exponent of a cell's weighted area (of cell i's): 2 bits, less 2 weight under Eq. 12.
    int exponent(std::uint32_t bits, std::uint8_t weight) const {
        return 2 * int(bits) - (density_ ? 2 * int(weight) : 0);
    }
    int exponent(std::size_t i) const { return exponent(cells_.bits(i), cells_.weight(i)); }
    // Splits cells expecting more than kSplitAbove darts at this round's rate; returns the rate.
    double balance();
    // The cells' weighted area: the sum of 2^exponent over the list, in list order.
    double weighted_area();
    // Writes each cell's fate, fate(i) (engine.cpp's kKeep, or kSplit with its surviving
    // children's mask), to `next`: itself, or those children; chunk c of the pool from
    // next[first[c]]. Counts the written cells per exponent into exponents_.
    template <typename Fate>
    void write_fates(Cells& next, const std::vector<std::uint64_t>& first, Fate&& fate);
    // The active list's cells per exponent of their weighted area (+ kExponentBias), when counted.
    std::optional<ExponentCounts> exponents_;
    void throw_darts(std::uint32_t round);
    // Decides the round's darts (field/resolve.cpp): as the textbook does, one dart at a time in
    // arrival order, or (cpu backend on several threads) in parallel, with the same outcome.
    void resolve();
    void resolve_in_arrival_order();
    void resolve_in_parallel();
    // Dart j's state given the states decided so far (darts.h's DART_*): rejected if an earlier
    // dart in conflict is accepted, accepted if every earlier one in conflict is rejected, else
    // undecided, with `wait` set to an undecided earlier dart in conflict. Each leaf marked fresh
    // holds its first dart (FieldQuadtree::first_dart), and its darts are in arrival order.
    std::uint32_t decide(std::uint32_t j, std::uint8_t* state, std::uint32_t& wait) const;
    // Appends point p (radius r) to the samples; returns its index.
    std::uint32_t add_sample(uvec2 p, std::uint32_t r) {
        lattice_.push_back(p);
        radii_.push_back(r);
        return std::uint32_t(lattice_.size() - 1);
    }
    // Adds dart d (radius r) as the next sample, in the tree too.
    void accept(const Dart& d, std::uint32_t r) { tree_.set_sample(d.leaf, d.p, add_sample(d.p, r)); }
    // Stamps sample s (one of this round's) on the leaves it may cover: those meeting the square
    // of its cover reach. Safe from several threads.
    void touch(std::uint32_t s);
    // Is a stamp of touched_ one of this round's?
    bool this_round(std::uint32_t stamp) const {
        const std::uint32_t v = stamp & kStampValue;
        return stamp & kStampedMany ? v == round_ : v >= round_first_;
    }
    // Is the leaf stamped this round: may one of this round's samples cover part of it?
    bool stamped(std::uint32_t leaf) const { return this_round(touched_[leaf]); }
    // The one sample of this round that may cover part of the leaf; kNone if none or several may.
    std::uint32_t stamp(std::uint32_t leaf) const {
        const std::uint32_t v = touched_[leaf];
        return (v & kStampedMany) || (v & kStampValue) < round_first_ ? FieldQuadtree::kNone : v & kStampValue;
    }
    // Does one of this round's samples cover the whole leaf (a stamped leaf's answer)?
    bool covered_whole(std::uint32_t leaf) const { return (touched_[leaf] & kCoveredWhole) && stamped(leaf); }
    // Drops, keeps or splits each active cell (the next list); returns the least side exponent
    // in it (UINT32_MAX when it is empty).
    std::uint32_t refine();
    // Makes the given samples the first ones, in their order, each tested exactly against those
    // before it under the rule (the test a dart takes) unless `checked`; then drops the leaves
    // they cover, as a round's refinement does.
    void place_given(const std::vector<uvec2>& given, bool checked);
    // place_given's first part: each given sample checked (unless `checked`) and set in its leaf.
    void add_given(const std::vector<uvec2>& given, bool checked);
    // Calls body(s) for each of this round's samples s (from round_first_ on), on the pool's threads.
    template <typename Body>
    void for_fresh(Body&& body) {
        pool_.parallel_for(
            lattice_.size() - round_first_,
            [&](std::size_t begin, std::size_t end, unsigned) {
                for (std::size_t s = begin; s < end; ++s) body(std::uint32_t(round_first_ + s));
            },
            kCellGrain);
    }
    // Notes the arrays' bytes now, with `extra` held outside them, for the peak.
    void note_bytes(std::uint64_t extra) {
        bytes_ = std::max<std::uint64_t>(bytes_, tree_.bytes() + cells_.bytes() + darts_.capacity() * sizeof(Dart) +
                                                     lattice_.capacity() * 12 + got_.capacity() +
                                                     touched_.capacity() * 4 + extra);
    }
    BlocksReleased released_;  // first, so that it goes last
    const FieldTable& t_;
    ThreadPool pool_;
    FieldQuadtree tree_;
    std::uint32_t rule_;
    bool density_;
    std::uint32_t seed_;
    bool serial_;
    Cells cells_;
    std::vector<std::uint8_t> got_;  // per cell: its fate (balance, refine); in between, it took darts
    // Per leaf, the samples that may cover part of it (touch): the one sample of this round, or
    // kStampedMany | round when several of this round may; older stamps are stale, and a throw
    // may replace one by an earlier sample that rejected a dart in the leaf (a hint for the next
    // dart there; kUnstamped, no sample near, stays). Only cells of a stamped leaf (and cells
    // that took darts) can have become covered, and with one stamp only that sample can cover or
    // conflict with a point of the leaf. While the leaf may still be an active cell whole
    // (kWholeCell, cleared once such a cell is split or dropped), a stamp of this round carries
    // kCoveredWhole where one of the round's samples covers the whole leaf, so that the cell
    // needs no search (refine). Sample indices stay below 2^29 (one per leaf, kIndex), and so do
    // rounds, so they never carry the flags.
    static constexpr std::uint32_t kStampedMany = 0x80000000u;
    static constexpr std::uint32_t kCoveredWhole = 0x40000000u;
    static constexpr std::uint32_t kWholeCell = 0x20000000u;
    static constexpr std::uint32_t kStampValue = 0x1FFFFFFFu;  // the sample, or the round
    static constexpr std::uint32_t kUnstamped = 0xFFFFFFFFu;   // many in a round that never comes
    std::vector<std::uint32_t, Uninitialised<std::uint32_t, true>> touched_;
    // The stamps' round (0 for the given samples, dart round k stamps as k + 1) and its first sample.
    std::uint32_t round_ = 0, round_first_ = 0;
    std::vector<Dart, Uninitialised<Dart, true>> darts_;
    std::vector<uvec2> lattice_;
    std::vector<std::uint32_t> radii_;
    std::uint32_t exp_neg_[128] = {};
    std::uint64_t darts_thrown_ = 0, bytes_ = 0;
    bool profile_;
    PhaseTimes phases_;
    const std::vector<glm::dvec2>& initial_;  // names the given samples that came from the options
};

}  // namespace vrpd::detail::field
