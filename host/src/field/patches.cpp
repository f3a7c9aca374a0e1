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
#include <optional>
#include <utility>

namespace vrpd::detail {
namespace {

using namespace patch;

// How many times the budget's splits the settling passes may visit, in all.
constexpr std::uint64_t kSettleVisits = 32;

// The halvings that take an error e past target t within it: ceil(log2(e / t)), for e > t, read
// exactly from the quotient's exponent (frexp: q = m 2^p, m in [0.5, 1)), at a fraction of
// log2's cost; the draft tries several targets over every cell past the least of them.
int halvings(double e, double t) {
    int p = 0;
    const double m = std::frexp(e / t, &p);
    return m == 0.5 ? p - 1 : p;
}

}  // namespace

std::vector<PatchDraft> draft_patches(ThreadPool& pool, const FieldSource& f, const Box& box, const TableDraft& d,
                                      const std::vector<double>& cell_error, double target, std::uint64_t budget,
                                      const std::vector<std::uint32_t>& fixed, double& error, bool& met_fixed) {
    const std::size_t cells = cell_error.size();
    // A kink's error halves with each level: a cell past the target by more than kMaxLevel halvings
    // (a jump, or a kink too sharp) is not patched, nor is the table.
    const std::uint64_t limit = budget / shared::FIELD_SPLIT_WORDS;
    // Growth past two thirds of the budget stops: balance and continuity add about half as many
    // again. Nor is it begun where a line of kink across each cell past the target (by a factor
    // e) would take more: about e / 2 leaves of the size at which it is within it, and as many
    // splits.
    const std::uint64_t grown_limit = limit / 3 * 2;
    std::vector<std::uint32_t> over;
    std::uint64_t estimate = 0;
    for (std::uint32_t c = 0; c < cells; ++c) {
        if (cell_error[c] <= target) continue;
        const int k = halvings(cell_error[c], target);
        if (k > int(kMaxLevel)) return {};
        estimate += std::uint64_t(1) << (k - 1);
        over.push_back(c);
    }
    if (over.empty() || estimate > grown_limit) return {};
    Forest forest(f, box, d);
    {
        // Grown a level at a time over all patches: the children of the last level's splits are
        // judged on the threads in batches (their midpoints in one call of the source each), and
        // those past the target split in order. A child left a leaf keeps its error.
        if (over.size() > grown_limit) return {};
        struct Parent {
            std::uint32_t patch;
            std::int32_t split;
            Corners v;
        };
        struct Past {
            std::uint32_t child;  // in the level's children: 4 a parent
            double node[5];
        };
        std::vector<PatchDraft> grown(over.size());
        std::vector<Parent> parents(over.size()), next;
        pool.parallel_for(over.size(), [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t k = begin; k < end; ++k) {
                grown[k] = forest.root(over[k]);
                parents[k] = {std::uint32_t(k), 0, forest.corners(over[k])};
            }
        });
        std::uint64_t total = over.size();
        while (!parents.empty()) {
            const std::size_t children = 4 * parents.size(), batches = (children + kBatch - 1) / kBatch;
            std::vector<std::vector<Past>> past(batches);
            // Past the budget, the level's other batches are not judged.
            std::atomic<std::uint64_t> splits = total;
            each_reporting(pool, batches, 1, [&](std::size_t b) {
                if (splits.load(std::memory_order_relaxed) > grown_limit) return;
                const std::size_t first = b * kBatch, n = std::min(kBatch, children - first);
                std::array<Square, kBatch> squares{};  // the first n are this batch's
                std::array<Midpoints, kBatch> m;
                for (std::size_t i = 0; i < n; ++i) {
                    const Parent& p = parents[(first + i) / 4];
                    const PatchDraft::Split& s = grown[p.patch].splits[std::size_t(p.split)];
                    squares[i] = Square{over[p.patch], s.level, s.x, s.y}.child(int((first + i) % 4));
                }
                forest.midpoints(squares.data(), n, m.data());
                for (std::size_t i = 0; i < n; ++i) {
                    const Parent& p = parents[(first + i) / 4];
                    const int c = int((first + i) % 4);
                    PatchDraft::Split& s = grown[p.patch].splits[std::size_t(p.split)];
                    const double e = forest.error(m[i], child_corners(p.v, s.source, c));
                    if (e <= target) {
                        s.error[c] = float(e);
                        continue;
                    }
                    Past& q = past[b].emplace_back();
                    q.child = std::uint32_t(first + i);
                    std::copy(std::begin(m[i].node), std::end(m[i].node), q.node);
                }
                splits.fetch_add(past[b].size(), std::memory_order_relaxed);
            });
            if (splits > grown_limit) return {};
            next.clear();
            for (const std::vector<Past>& batch : past)
                for (const Past& q : batch) {
                    const Parent& p = parents[q.child / 4];
                    const int c = int(q.child % 4);
                    PatchDraft& patch = grown[p.patch];
                    const PatchDraft::Split parent = patch.splits[std::size_t(p.split)];
                    const Square square = Square{patch.cell, parent.level, parent.x, parent.y}.child(c);
                    if (square.level >= kMaxLevel) return {};
                    const std::int32_t s = std::int32_t(patch.splits.size());
                    patch.splits[std::size_t(p.split)].child[c] = s;
                    patch.splits.push_back(Forest::made(square, q.node));
                    next.push_back({p.patch, s, child_corners(p.v, parent.source, c)});
                }
            total = splits;
            std::swap(parents, next);
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
    std::vector<double> chunk_steepest(pool.chunks(cells), 0.0);  // a maximum per chunk: exact in any order
    pool.parallel_for(cells, [&](std::size_t begin, std::size_t end, unsigned chunk) {
        for (std::size_t c = begin; c < end; ++c) {
            const Corners v = forest.corners(std::uint32_t(c));
            raise_steepest(chunk_steepest[chunk], v[0], v[1], v[2], v[3], 1);
        }
    });
    double steepest = *std::max_element(chunk_steepest.begin(), chunk_steepest.end());
    // Balanced, then settled: where continuity takes a leaf past the target, or makes it steeper
    // than any leaf or cell with the source's nodes, the leaves of a larger size across its edges
    // (whose edges set its corners there) are split; a leaf past the target with none is split
    // itself. Until every leaf is within the target and, while the splits stay within two thirds
    // of the budget, the reference's slope: where a kink line's leaves change level (r, and with
    // it the relative error, varies along the line), each change moves a node by up to the kink's
    // jump in slope times a quarter of the coarser side, and splitting the coarser leaf moves the
    // change one leaf along the line, so the slope's fixes take every leaf of the line to its
    // deepest level. Past that share the table keeps the steeper leaves, whose L is measured.
    // Each patch's settling is kept until a split in it or in a table cell beside it (whose edge
    // nodes its own depend on) calls for it again.
    std::vector<Forest::Settled> settled;
    std::vector<std::uint8_t> dirty;
    std::vector<std::uint32_t> again;  // the patches to settle again
    // Each pass settles its patches whole, so a chain of fixes a leaf at a time (a cusp, whose
    // leaves along it pass the target split after split) costs its length times a patch. The
    // passes stop once they have settled kSettleVisits times the budget's splits: the leaves
    // still past the target stay, and the error reported is theirs (every patch is settled as
    // it stands).
    std::uint64_t visited = 0;
    for (;;) {
        forest.balance(work);
        if (forest.split_count > limit) return {};
        const std::size_t before = settled.size();
        for (std::size_t p = before; p < forest.patches.size(); ++p)
            if (std::binary_search(fixed.begin(), fixed.end(), forest.patches[p].cell)) {
                met_fixed = true;
                return {};
            }
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
                       [&](std::size_t k) { settled[again[k]] = forest.settle(again[k], target, steepest); });
        for (const std::uint32_t p : again) {
            steepest = std::max(steepest, settled[p].steepest);
            visited += forest.patches[p].splits.size();
        }
        std::vector<Leaf> fix;
        for (const std::uint32_t p : again) {
            fix.insert(fix.end(), settled[p].past.begin(), settled[p].past.end());
            if (forest.split_count <= grown_limit)
                for (const auto& [leaf, g] : settled[p].moved)
                    if (g > steepest * 1.01) fix.push_back(leaf);
        }
        if (fix.empty() || visited > kSettleVisits * limit) break;
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
