// Resolution of a round's darts under the field's rule (paper section 1, Eq. 4): a dart is
// accepted iff no accepted dart of the round arriving before it (by key, then throwing order)
// conflicts with it; each was tested against the earlier rounds' samples when thrown. The
// accepted darts become samples in arrival order.
#include <algorithm>
#include <atomic>

#include "sampler.h"

namespace vrpd::detail::field {

namespace {

std::uint8_t load_state(std::uint8_t* state, std::uint32_t j) {
    return std::atomic_ref<std::uint8_t>(state[j]).load(std::memory_order_relaxed);
}

}  // namespace

void FieldSampler::resolve() {
    // On one thread the parallel resolution's extra searches buy nothing.
    if (serial_ || pool_.size() == 1)
        resolve_in_arrival_order();
    else
        resolve_in_parallel();
}

void FieldSampler::touch(std::uint32_t s) {
    const uvec2 p = lattice_[s];
    const std::uint32_t r = radii_[s], many = kStampedMany | round_;
    const std::uint64_t f = cover_reach(p, r);
    const shared::Lattice& l = t_.lattice;
    // Where the square and the leaves meeting it lie within half the torus of p along each axis,
    // a leaf's image in the search's coordinates is the nearest one at every point: its gaps are
    // the lattice's (shared::far_distance2).
    const std::uint64_t span = f + (std::uint64_t(1) << t_.tile_bits);
    const bool framed = !l.periodic || (2 * span <= l.extent_x && 2 * span <= l.extent_y);
    // Whether s covers the whole leaf: covers(s, corner, its far corner), the test a cell that is
    // the leaf would take. In the frame, from the image's gaps, reading the leaf's least r only
    // where the rule needs it and r's slope lets it reach the farthest point: r there is at
    // least r at the leaf's nearest point, at most r + L |nearest - p| + 1 (floored).
    auto covers_leaf = [&](uvec2 corner, std::uint32_t bits, glm::i64vec2 image) {
        const uvec2 b = far_corner(corner, bits);
        if (!framed) return covers(s, corner, b);
        const glm::i64vec2 last = image + glm::i64vec2(b) - glm::i64vec2(corner);
        const std::int64_t px = p.x, py = p.y;
        const std::uint64_t fx = std::uint64_t(std::max(px - image.x, last.x - px)),
                            fy = std::uint64_t(std::max(py - image.y, last.y - py));
        const std::uint64_t d2 = fx * fx + fy * fy;
        return covers_far(r, d2, [&] {
            const std::int64_t nx = std::max<std::int64_t>({image.x - px, px - last.x, 0}),
                               ny = std::max<std::int64_t>({image.y - py, py - last.y, 0});
            const double reach = double(r) + t_.lipschitz * (1 + 1e-9) * std::sqrt(double(nx * nx + ny * ny)) + 2;
            return double(d2) >= reach * reach ? 0u : t_.min_over(corner, b);
        });
    };
    auto stamp = [&](std::uint32_t leaf, uvec2 corner, std::uint32_t bits, glm::i64vec2 image) {
        std::atomic_ref<std::uint32_t> word(touched_[leaf]);
        std::uint32_t old = word.load(std::memory_order_relaxed);
        // Only a leaf that may still be an active cell whole is tested whole.
        const std::uint32_t covered = (old & kWholeCell) && covers_leaf(corner, bits, image) ? kCoveredWhole : 0;
        for (;;) {
            // Stamped by s already (a leaf may be met twice by one search: two images of it on a
            // torus), or by several of the round's samples: the value stays, and so does a cover.
            const bool now = this_round(old);
            const std::uint32_t value = old & (kStampedMany | kStampValue);
            const std::uint32_t next = (!now                          ? s
                                        : value == s || value == many ? value
                                                                      : many) |
                                       (now ? old & kCoveredWhole : 0) | (old & kWholeCell) | covered;
            if (next == old || word.compare_exchange_weak(old, next, std::memory_order_relaxed)) break;
        }
        return false;
    };
    // The sample may cover a point of a block only within f(its r, r over the block).
    search_within(steep(f, radii_[s]), p, p, radii_[s], false,
                  [&](auto enter) { return tree_.near(p, p, f, stamp, enter); });
}

void FieldSampler::resolve_in_arrival_order() {
    note_bytes((darts_.size() + 1) / 2 * sizeof(Dart));  // the sort's buffer: libstdc++ merges through half the range
    std::stable_sort(darts_.begin(), darts_.end(), [](const Dart& a, const Dart& b) { return a.key < b.key; });
    // Arrival order is random in space: the words a dart reads first (its leaf's sample and stamp,
    // its table cell) are fetched a few darts ahead.
    constexpr std::size_t kAhead = 8;
    for (std::size_t j = 0; j < darts_.size(); ++j) {
        if (j + kAhead < darts_.size()) {
            const Dart& next = darts_[j + kAhead];
            tree_.prefetch(next.leaf);
            __builtin_prefetch(&touched_[next.leaf]);
            t_.prefetch(next.p);
        }
        const Dart& d = darts_[j];
        if (tree_.sample(d.leaf) != FieldQuadtree::kNone) continue;
        const std::uint32_t r = t_.radius(d.p);
        if (conflicts_fresh(d.p, r, d.leaf)) continue;
        accept(d, r);
        touch(std::uint32_t(lattice_.size() - 1));
    }
}

std::uint32_t FieldSampler::decide(std::uint32_t j, std::uint8_t* state, std::uint32_t& wait) const {
    const Dart& d = darts_[j];
    wait = FieldQuadtree::kNone;
    // Two points of one leaf conflict under every rule (its diagonal is shorter than r anywhere in
    // it), so a leaf accepts at most one dart, and the leaf's darts before j (its earlier arrivals)
    // decide first: an accepted one rejects j, an undecided one holds it.
    for (std::uint32_t k = tree_.first_dart(d.leaf); k < j; ++k) {
        const std::uint8_t s = load_state(state, k);
        if (s == shared::DART_REJECTED) continue;
        if (s == shared::DART_ACCEPTED) return shared::DART_REJECTED;
        wait = k;
        return shared::DART_UNDECIDED;
    }
    const std::uint32_t r = t_.radius(d.p);
    // An earlier dart in conflict lies within the reach: r under current and smaller (f <= r of
    // the later), under prior and bigger grown with r nearby (f may be the earlier's radius). In
    // another leaf, its darts before j in arrival order count: up to its accepted one (the rest
    // conflict with that one), or up to an undecided one in conflict, which j waits for (none
    // after it can be accepted before it is decided).
    auto test = [&](std::uint32_t leaf) {
        if (leaf == d.leaf) return false;
        for (std::uint32_t k = tree_.first_dart(leaf); k < darts_.size() && darts_[k].leaf == leaf; ++k) {
            const Dart& o = darts_[k];
            if (!shared::arrives_before(o.key, k, d.key, j)) break;
            const std::uint8_t s = load_state(state, k);
            if (s == shared::DART_REJECTED) continue;
            const bool conflict = shared::field_conflict(shared::rule_f(rule_, t_.radius(o.p), r),
                                                         shared::distance2(t_.lattice, o.p, d.p));
            if (s == shared::DART_ACCEPTED) return conflict;
            if (conflict) {
                wait = k;
                break;
            }
        }
        return false;
    };
    const std::uint64_t f = reach(d.p, d.p, r);
    const bool rejected = search_within(steep(f, r), d.p, d.p, r, true,
                                        [&](auto enter) { return tree_.near_fresh(d.p, d.p, f, test, enter); });
    if (rejected) return shared::DART_REJECTED;
    return wait == FieldQuadtree::kNone ? shared::DART_ACCEPTED : shared::DART_UNDECIDED;
}

void FieldSampler::resolve_in_parallel() {
    const std::size_t n = darts_.size();
    // Darts come in cell order, and a leaf's cells are consecutive in the list (a split cell's
    // children take its place), so a leaf's darts are too. They are put in arrival order within
    // the leaf: a stable sort by key keeps ties in throwing order, and each leaf keeps its range,
    // so every dart arrives before the same darts as it did. Each leaf with darts records its
    // first in its sample's slot and is marked fresh (it holds no sample: its darts would have
    // been rejected when thrown), so that a search meets only the leaves with darts.
    std::vector<std::uint8_t> state(n, std::uint8_t(shared::DART_UNDECIDED));
    note_bytes(n);
    // Each leaf's first dart, found by the chunks in order (reading only), then each leaf's range
    // sorted by one thread, which reads and writes nothing outside it.
    std::vector<std::vector<std::uint32_t>> found(pool_.chunks(n, kCellGrain));
    pool_.parallel_for(
        n,
        [&](std::size_t begin, std::size_t end, unsigned chunk) {
            for (std::size_t j = begin; j < end; ++j) {
                if (j > 0 && darts_[j].leaf == darts_[j - 1].leaf) continue;
                if (j > 0 && darts_[j].leaf < darts_[j - 1].leaf)
                    throw Error("internal: a leaf's darts are not consecutive");
                found[chunk].push_back(std::uint32_t(j));
            }
        },
        kCellGrain);
    std::vector<std::uint32_t> first;  // each leaf's first dart, then n
    for (const std::vector<std::uint32_t>& f : found) first.insert(first.end(), f.begin(), f.end());
    std::vector<std::vector<std::uint32_t>>().swap(found);
    first.push_back(std::uint32_t(n));
    note_bytes(first.size() * 4);
    const std::size_t leaves = first.size() - 1;
    pool_.parallel_for(
        leaves,
        [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t k = begin; k < end; ++k) {
                const auto from = darts_.begin() + std::ptrdiff_t(first[k]);
                const auto to = darts_.begin() + std::ptrdiff_t(first[k + 1]);
                if (to - from > 1)
                    std::stable_sort(from, to, [](const Dart& a, const Dart& b) { return a.key < b.key; });
                tree_.set_first_dart(from->leaf, first[k]);
                tree_.mark_fresh(from->p);
            }
        },
        kCellGrain);
    // Each thread decides the darts of its part (spatial order), one at a time: a dart left
    // undecided waits for an earlier one, decided first (depth first; each wait is for an earlier
    // arrival, so the chains end). Threads may decide the same dart near their parts' border:
    // both reach the same final state.
    pool_.parallel_for(
        n,
        [&](std::size_t begin, std::size_t end, unsigned) {
            std::vector<std::uint32_t> stack;
            for (std::size_t j = begin; j < end; ++j) {
                stack.push_back(std::uint32_t(j));
                while (!stack.empty()) {
                    const std::uint32_t t = stack.back();
                    if (load_state(state.data(), t) != shared::DART_UNDECIDED) {
                        stack.pop_back();
                        continue;
                    }
                    std::uint32_t wait = 0;
                    const std::uint32_t s = decide(t, state.data(), wait);
                    if (s == shared::DART_UNDECIDED) {
                        stack.push_back(wait);
                        continue;
                    }
                    std::atomic_ref<std::uint8_t>(state[t]).store(std::uint8_t(s), std::memory_order_relaxed);
                    stack.pop_back();
                }
            }
        },
        kCellGrain);
    // The darts' marks and first darts end before the samples' begin.
    pool_.parallel_for(
        leaves,
        [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t k = begin; k < end; ++k) {
                tree_.settle(darts_[first[k]].p);
                tree_.clear_first_dart(darts_[first[k]].leaf);
            }
        },
        kCellGrain);
    // The accepted darts become samples in arrival order; the tree's marks and the stamps are
    // then set in throwing order, which is spatial: neighbouring searches share cached nodes.
    std::vector<std::uint32_t> accepted;
    for (std::uint32_t j = 0; j < n; ++j)
        if (state[j] == shared::DART_ACCEPTED) accepted.push_back(j);
    std::vector<std::uint32_t> arrival(accepted);
    std::sort(arrival.begin(), arrival.end(), [&](std::uint32_t a, std::uint32_t b) {
        return shared::arrives_before(darts_[a].key, a, darts_[b].key, b);
    });
    std::vector<std::uint32_t> sample_of(n);  // dart j's sample, for the accepted ones
    note_bytes(n * 4 + accepted.size() * 8);
    for (std::uint32_t j : arrival) sample_of[j] = add_sample(darts_[j].p, t_.radius(darts_[j].p));
    pool_.parallel_for(
        accepted.size(),
        [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t i = begin; i < end; ++i) {
                const std::uint32_t j = accepted[i];
                tree_.set_sample(darts_[j].leaf, darts_[j].p, sample_of[j]);
            }
        },
        kCellGrain);
    pool_.parallel_for(
        accepted.size(),
        [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t i = begin; i < end; ++i) touch(sample_of[accepted[i]]);
        },
        kCellGrain);
}

}  // namespace vrpd::detail::field
