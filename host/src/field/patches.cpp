// Patches of a sizing field's table (field/patches.h). A bilinear cell across a kink is off by
// about the slope's jump times the cell's side, so it converges only linearly: refining the whole
// table to the target there would take far more nodes than samples, and so would a uniform grid
// over each cell the kink crosses. A patch is a quadtree over its cell whose leaves are split
// only where their own error asks, so its splits follow the kink's line.
#include "patches.h"

#include "forest.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

namespace vrpd::detail {
namespace {

using namespace patch;

// Runs body(k) for k in [0, n) on the pool's threads; a k that throws Error stops the run, the
// lowest such k's message given, so that it does not depend on timing.
template <typename Body>
void each_reporting(ThreadPool& pool, std::size_t n, std::size_t grain, Body&& body) {
    std::mutex mutex;
    std::size_t failed = SIZE_MAX;
    std::string message;
    pool.parallel_for(
        n,
        [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t k = begin; k < end; ++k) {
                try {
                    body(k);
                } catch (const Error& e) {
                    const std::lock_guard lock(mutex);
                    if (k < failed) failed = k, message = e.what();
                    return;
                }
            }
        },
        grain);
    if (failed != SIZE_MAX) throw Error(message);
}

}  // namespace

std::vector<PatchDraft> draft_patches(ThreadPool& pool, const FieldSource& f, const Box& box, const TableDraft& d,
                                      const std::vector<double>& cell_error, double target, std::uint64_t budget,
                                      double& error) {
    const std::size_t cells = cell_error.size();
    // A kink's error halves with each level: a cell past the target by more than kMaxLevel halvings
    // (a jump, or a kink too sharp) is not patched, nor is the table.
    std::vector<std::uint32_t> over;
    for (std::uint32_t c = 0; c < cells; ++c) {
        if (cell_error[c] <= target) continue;
        if (std::ceil(std::log2(cell_error[c] / target)) > kMaxLevel) return {};
        over.push_back(c);
    }
    if (over.empty()) return {};
    const std::uint64_t limit = budget / shared::FIELD_SPLIT_WORDS;
    // Growth past two thirds of the budget stops: balance and continuity add about half as many
    // again. Nor is it begun where a line of kink across each cell past the target (by a factor
    // e) would take more: about e / 2 leaves of the size at which it is within it, and as many
    // splits.
    const std::uint64_t grown_limit = limit / 3 * 2;
    double estimate = 0;
    for (const std::uint32_t c : over)
        estimate += std::ldexp(1.0, int(std::ceil(std::log2(cell_error[c] / target))) - 1);
    if (estimate > double(grown_limit)) return {};
    Forest forest(f, box, d);
    {
        // Grown a level at a time over all patches, the squares of a level judged on the threads,
        // their midpoints in batches.
        struct Judged {
            double node[5];
            double error;
        };
        std::vector<Square> squares(over.size());
        std::vector<Judged> judged;
        // Judges the squares (their corners from corners_of(index)); returns those past the target,
        // or more than `room` once past it, the level's other batches then left unjudged.
        auto judge = [&](std::uint64_t room, auto&& corners_of) {
            judged.resize(squares.size());
            std::atomic<std::uint64_t> splits = 0;
            each_reporting(pool, (squares.size() + kBatch - 1) / kBatch, 1, [&](std::size_t b) {
                if (splits.load(std::memory_order_relaxed) > room) return;
                const std::size_t first = b * kBatch, n = std::min(kBatch, squares.size() - first);
                std::array<Midpoints, kBatch> m;
                forest.midpoints(&squares[first], n, m.data());
                std::uint64_t past = 0;
                for (std::size_t i = 0; i < n; ++i) {
                    Judged& j = judged[first + i];
                    std::copy(std::begin(m[i].node), std::end(m[i].node), j.node);
                    j.error = forest.error(m[i], corners_of(first + i));
                    past += j.error > target;
                }
                splits.fetch_add(past, std::memory_order_relaxed);
            });
            return splits.load();
        };
        for (std::size_t k = 0; k < over.size(); ++k) squares[k] = {over[k], 0, 0, 0};
        judge(UINT64_MAX, [&](std::size_t k) { return forest.corners(over[k]); });
        std::vector<PatchDraft> grown(over.size());
        for (std::size_t k = 0; k < over.size(); ++k) grown[k] = Forest::root(squares[k], judged[k].node);
        struct Candidate {
            std::uint32_t patch;
            std::int32_t split;
            int child;
            Corners v;
        };
        std::vector<Candidate> frontier, next;
        frontier.reserve(4 * over.size());
        next.reserve(4 * over.size());
        auto open = [&](std::uint32_t p, std::int32_t s, const Corners& v) {
            for (int c = 0; c < 4; ++c)
                frontier.push_back({p, s, c, child_corners(v, grown[p].splits[std::size_t(s)].source, c)});
        };
        for (std::uint32_t k = 0; k < over.size(); ++k) open(k, 0, forest.corners(over[k]));
        std::uint64_t total = over.size();
        if (total > grown_limit) return {};
        while (!frontier.empty()) {
            squares.resize(frontier.size());
            for (std::size_t i = 0; i < frontier.size(); ++i) {
                const Candidate& c = frontier[i];
                const PatchDraft::Split& s = grown[c.patch].splits[std::size_t(c.split)];
                squares[i] = Square{grown[c.patch].cell, s.level, s.x, s.y}.child(c.child);
            }
            if (judge(grown_limit - total, [&](std::size_t i) { return frontier[i].v; }) > grown_limit - total)
                return {};
            next.clear();
            std::swap(frontier, next);  // `next` holds this level; `frontier` gathers the next
            for (std::size_t i = 0; i < next.size(); ++i) {
                if (judged[i].error <= target) {
                    grown[next[i].patch].splits[std::size_t(next[i].split)].error[next[i].child] =
                        float(judged[i].error);
                    continue;
                }
                if (squares[i].level >= kMaxLevel) return {};
                ++total;
                const Candidate& c = next[i];
                PatchDraft& p = grown[c.patch];
                const std::int32_t s = std::int32_t(p.splits.size());
                p.splits[std::size_t(c.split)].child[c.child] = s;
                p.splits.push_back(Forest::made(squares[i], judged[i].node));
                open(c.patch, s, c.v);
            }
        }
        forest.adopt(std::move(grown));
    }
    std::vector<std::pair<std::int32_t, std::int32_t>> work;
    for (std::size_t p = 0; p < forest.patches.size(); ++p)
        for (std::size_t s = 0; s < forest.patches[p].splits.size(); ++s)
            work.push_back({std::int32_t(p), std::int32_t(s)});
    std::reverse(work.begin(), work.end());
    // The table's steepest gradient, a reference for the patches' own: continuity moves a node
    // off the source by up to the target, which over a small leaf can be steeper than the field.
    double steepest = 0;
    for (std::uint32_t c = 0; c < cells; ++c) {
        const Corners v = forest.corners(c);
        raise_steepest(steepest, v[0], v[1], v[2], v[3], 1);
    }
    // Balanced, then settled: where continuity takes a leaf past the target, or makes it steeper
    // than any leaf or cell with the source's nodes, the leaves of a larger size across its edges
    // (whose edges set its corners there) are split; a leaf past the target with none is split
    // itself. Until every leaf is within the target and the reference's slope.
    // Each patch's settling is kept until a split in it or in a table cell beside it (whose edge
    // nodes its own depend on) calls for it again.
    std::vector<Forest::Settled> settled;
    std::vector<std::uint8_t> dirty;
    std::vector<std::uint32_t> again;  // the patches to settle again
    std::uint64_t splits = 0;
    for (const PatchDraft& p : forest.patches) splits += p.splits.size();
    for (;;) {
        forest.balance(work);
        splits += forest.split_count;
        forest.split_count = 0;
        if (splits > limit) return {};
        const std::size_t before = settled.size();
        settled.resize(forest.patches.size());
        dirty.assign(forest.patches.size(), 0);
        for (std::size_t p = before; p < settled.size(); ++p) dirty[p] = 1;
        for (const std::uint32_t c : forest.touched)
            forest.each_neighbour(c, [&](std::uint32_t n) {
                if (forest.slot(n) >= 0) dirty[std::size_t(forest.slot(n))] = 1;
            });
        forest.touched.clear();
        again.clear();
        for (std::size_t p = 0; p < dirty.size(); ++p)
            if (dirty[p]) again.push_back(std::uint32_t(p));
        each_reporting(pool, again.size(), 4,
                       [&](std::size_t k) { settled[again[k]] = forest.settle(again[k], target); });
        for (const std::uint32_t p : again) steepest = std::max(steepest, settled[p].steepest);
        std::vector<Leaf> fix;
        for (const std::uint32_t p : again) {
            fix.insert(fix.end(), settled[p].past.begin(), settled[p].past.end());
            for (const auto& [leaf, g] : settled[p].moved)
                if (g > steepest * 1.01) fix.push_back(leaf);
        }
        if (fix.empty()) break;
        for (const Leaf& l : fix) {
            const Square sq = forest.square(l);
            bool coarser = false;
            for (int e = 0; e < 4; ++e) {
                const auto g = forest.across(sq, e);
                if (!g) continue;
                const Leaf n = forest.locate(*g);
                if (n.level >= sq.level) continue;
                coarser = true;
                work.push_back(forest.split(n));
            }
            if (coarser || forest.patches[std::size_t(l.patch)].splits[std::size_t(l.split)].child[l.child] >= 0)
                continue;  // the leaf may have been split already, as another's coarser neighbour
            if (sq.level >= kMaxLevel) return {};
            work.push_back(forest.split(l));
        }
    }
    double worst = 0;
    for (const Forest::Settled& o : settled) worst = std::max(worst, o.error);
    // Patches in cell order; the error is the largest over the leaves and the cells left unpatched.
    std::vector<PatchDraft> ordered;
    ordered.reserve(forest.patches.size());
    error = worst;
    for (std::uint32_t c = 0; c < cells; ++c) {
        const std::int32_t s = forest.slot(c);
        if (s < 0)
            error = std::max(error, cell_error[c]);
        else
            ordered.push_back(std::move(forest.patches[std::size_t(s)]));
    }
    return ordered;
}

}  // namespace vrpd::detail
