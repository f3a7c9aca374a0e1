// A continuous hierarchy of a sizing field (paper section 4.2 under section 5's rules), exact on
// the lattice. From a maximal sampling at S times the field, t falls without steps. For the
// samples X so far, a lattice point y is uncovered at scale s while |x - y| >= s f(x, y) for
// every x in X, so the next sample is due at the scale
//     s* = max over y of g(y),   g(y) = min over x in X of |x - y| / f(x, y),
// and goes at the point y where g is greatest (with one radius it has nowhere else to go), born
// at t = s* / S. The search for y is best-first over blocks of the lattice, each queued with an
// upper bound of g^2 over its points, kept as a fraction of integers: a block whose bound is
// below 1 is covered at the final field for good (samples only lower g) and is dropped; the
// queue's top is split until it is one lattice point with its exact g^2, which no other point's
// bound reaches. Design and bounds: docs/design.md, "Continuous hierarchies of a field".
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <deque>
#include <vector>

#include <fmt/format.h>

#include "field.h"
#include "quadtree.h"
#include "shared/field.h"
#include "shared/lattice.h"
#include "../plan.h"

namespace vrpd::detail {
namespace {

// num / den, a squared ratio of lattice lengths; den 0 is unbounded (num is then 1). Compared
// by their quotients in doubles where those differ by more than their rounding, else exactly.
struct Ratio {
    std::uint64_t num = 1, den = 0;
    double quotient = INFINITY;
    Ratio() = default;
    Ratio(std::uint64_t n, std::uint64_t d) : num(n), den(d), quotient(double(n) / double(d)) {}
    bool operator<(const Ratio& o) const {
        if (quotient < o.quotient * (1 - 1e-12)) return true;
        if (o.quotient < quotient * (1 - 1e-12)) return false;
        return static_cast<unsigned __int128>(num) * o.den < static_cast<unsigned __int128>(o.num) * den;
    }
    bool below_one() const { return num < den; }
};

// A block of the lattice: [x, x + 2^bits) x [y, y + 2^bits) clipped to it, with an upper bound of
// g^2 over its points (exact for one point) found against the first `seen` samples.
struct Block {
    std::uint32_t x, y, bits, seen;
    Ratio g2;
};

// The queue's order: the greater bound first; at equal bounds a larger block first (so a point
// is taken only once no block may still hold one as far from the samples), then the lower row
// and column: one total order, so the samples do not depend on how the queue keeps its items.
struct After {
    bool operator()(const Block& a, const Block& b) const {
        if (a.g2 < b.g2 || b.g2 < a.g2) return a.g2 < b.g2;
        if (a.bits != b.bits) return a.bits < b.bits;
        return a.y != b.y ? a.y > b.y : a.x > b.x;
    }
};

// The blocks in the queue's order (After): those of the greatest buckets in a heap, the others
// in buckets by their bound's quotient, 1 024 a doubling (the bits of its double, which order
// positive doubles as their values). A greater bucket holds greater bounds, so the heap's top is
// the greatest block; the queue's greatest bound only falls (a block is pushed with a bound at
// most the one just popped), so the heap stays one bucket or two of blocks, near in memory, where
// one heap of every block would take a cache miss a level. A bucket is a list of chunks of
// blocks from a shared pool, whose freed chunks are taken again first: the pool holds little
// more than the queue's most blocks at once.
class BlockQueue {
public:
    bool empty() const { return heap_.empty() && stored_ == 0; }
    // The bytes the pool and the heap hold.
    std::size_t bytes() const { return pool_.size() * sizeof(Chunk) + heap_.capacity() * sizeof(Block); }
    const Block& top() {
        fill();
        return heap_.front();
    }
    void pop() {
        fill();
        std::pop_heap(heap_.begin(), heap_.end(), After{});
        heap_.pop_back();
    }
    void push(const Block& b) {
        const std::size_t k = bucket(b.g2);
        if (!heap_.empty() && k >= current_) {
            heap_.push_back(b);
            std::push_heap(heap_.begin(), heap_.end(), After{});
            return;
        }
        if (k >= heads_.size()) heads_.resize(k + 1, kEnd);
        std::uint32_t c = heads_[k];
        if (c == kEnd || pool_[c].count == kChunk) {
            std::uint32_t fresh = free_;
            if (fresh != kEnd) {
                free_ = pool_[fresh].next;
            } else {
                fresh = std::uint32_t(pool_.size());
                pool_.emplace_back();
            }
            pool_[fresh].count = 0;
            pool_[fresh].next = c;
            heads_[k] = c = fresh;
        }
        pool_[c].blocks[pool_[c].count++] = b;
        ++stored_;
        top_ = std::max(top_, k);
    }

private:
    static constexpr std::uint32_t kEnd = UINT32_MAX;
    static constexpr std::uint32_t kChunk = 63;
    struct Chunk {
        std::array<Block, kChunk> blocks;
        std::uint32_t count, next;
    };
    // A quotient's bucket: its double's exponent and first ten bits of mantissa, from 1 up.
    // Quotients of 64-bit integers stay below 2^64; an unbounded one takes the bucket past them.
    static std::size_t bucket(const Ratio& r) {
        constexpr int kShift = 52 - 10;
        constexpr std::uint64_t kOne = std::bit_cast<std::uint64_t>(1.0) >> kShift;
        constexpr std::uint64_t kUnbounded = std::uint64_t(65) << (52 - kShift);
        const std::uint64_t bits = std::bit_cast<std::uint64_t>(r.quotient) >> kShift;
        return bits > kOne ? std::size_t(std::min(bits - kOne, kUnbounded)) : 0;
    }
    // Moves the greatest bucket into the heap where the heap is empty (and the queue is not).
    void fill() {
        if (!heap_.empty()) return;
        while (heads_[top_] == kEnd) --top_;
        for (std::uint32_t c = heads_[top_], next; c != kEnd; c = next) {
            Chunk& chunk = pool_[c];
            heap_.insert(heap_.end(), chunk.blocks.begin(), chunk.blocks.begin() + chunk.count);
            stored_ -= chunk.count;
            next = chunk.next;
            chunk.next = free_;
            free_ = c;
        }
        heads_[top_] = kEnd;
        std::make_heap(heap_.begin(), heap_.end(), After{});
        current_ = top_;
    }
    std::vector<Block> heap_;
    std::deque<Chunk> pool_;
    std::vector<std::uint32_t> heads_;  // per bucket, its first chunk
    std::uint32_t free_ = kEnd;
    std::size_t stored_ = 0, top_ = 0, current_ = 0;
};

class Events {
public:
    Events(const FieldTable& t, const SampleOptions& o, std::uint64_t max_leaves, ThreadPool& pool)
        : t_(t),
          lattice_(t.lattice),
          rule_(std::uint32_t(o.sizing->rule)),
          start_(hierarchy_start(o)),
          tree_(t, max_leaves, pool) {
        // Cells of about the least r, at most 2^22 of them.
        mark_bits_ = std::uint32_t(std::bit_width(std::max(1u, t.r_lo)) - 1);
        auto cells = [&](std::uint32_t extent) {
            return (std::uint64_t(extent) + (1u << mark_bits_) - 1) >> mark_bits_;
        };
        while (cells(lattice_.extent_x) * cells(lattice_.extent_y) > (1u << 22)) ++mark_bits_;
        marks_x_ = std::uint32_t(cells(lattice_.extent_x));
        marks_.assign(marks_x_ * cells(lattice_.extent_y), 0);
    }

    // Places the direct sampling's points (born at t = 1), then every event down to the final
    // field, appending each to `samples` and its t to `birth`.
    void run(std::vector<glm::uvec2>& samples, std::vector<double>& birth) {
        for (const glm::uvec2 p : samples) insert(p);
        birth.assign(samples.size(), 1.0);
        for (std::uint32_t j = 0; j < t_.tiles_y; ++j)
            for (std::uint32_t i = 0; i < t_.tiles_x; ++i)
                if ((i << t_.tile_bits) < lattice_.extent_x && (j << t_.tile_bits) < lattice_.extent_y) {
                    Block tile{i << t_.tile_bits, j << t_.tile_bits, t_.tile_bits, 0, {}};
                    evaluate(tile);
                    push(tile);
                }
        while (!queue_.empty()) {
            Block b = queue_.top();
            queue_.pop();
            if (b.seen != points_.size()) {
                // Stale: lowered by the samples placed near it since (else it stands), and taken
                // on now only if it still comes first.
                if (touched(b)) {
                    const std::uint32_t lo = least_r(b);
                    if (covered_by_marks(b, lo)) continue;
                    update(b, lo);
                    if (b.g2.below_one() || (!queue_.empty() && After{}(b, queue_.top()))) {
                        push(b);
                        continue;
                    }
                }
                b.seen = std::uint32_t(points_.size());
            }
            // b's bound is against every sample, and no other block's is greater: split it, and
            // go on down while its greatest child still comes before every queued block (the
            // queue would hand it back next). The samples gathered for b decide every block in it.
            if (b.bits > 0) gather({b.x, b.y}, far_corner(b), b.g2);
            bool queued = false;
            while (b.bits > 0 && !queued) {
                const Block next = split(b);
                queued = next.g2.below_one() || (!queue_.empty() && After{}(next, queue_.top()));
                if (queued) {
                    push(next);
                } else {
                    b = next;
                    narrow(b);
                }
            }
            if (queued) continue;
            // The greatest g over the lattice, exact: the next sample, at scale sqrt(g^2). The
            // direct sampling's field is S r with its nodes rounded, so points just past S are
            // still the first level's.
            samples.push_back({b.x, b.y});
            birth.push_back(std::min(1.0, std::sqrt(b.g2.quotient) / start_));
            insert(samples.back());
            mark(samples.back(), b.g2);
        }
    }
    std::uint64_t bytes() const { return tree_.bytes() + points_.capacity() * 12 + peak_queue_; }

private:
    void insert(glm::uvec2 p) {
        const std::uint32_t leaf = tree_.leaf_of(p);
        // A leaf's diagonal is below the least r over it, so a conflict-free set holds one sample a leaf.
        if (tree_.sample(leaf) != FieldQuadtree::kNone)
            throw Error(
                fmt::format("internal: two samples of a continuous hierarchy in one leaf, at ({}, {})", p.x, p.y));
        tree_.set_sample(leaf, p, std::uint32_t(points_.size()));
        points_.push_back(p);
        radius_.push_back(t_.radius(p));
    }
    // Marks the cells a sample placed at p, at scale sqrt(g2) (no queued block's bound passes
    // g2), may lower a block's bound in: those within sqrt(g2) f(p, y) of it for some y.
    void mark(glm::uvec2 p, Ratio g2) {
        const double root = std::sqrt(g2.quotient) * (1 + 1e-9);
        const std::uint32_t own = radius_.back();
        // Under prior and smaller f is at most r(p); under current and bigger r(y) counts too.
        const std::uint64_t need = rule_ == shared::RULE_PRIOR || rule_ == shared::RULE_SMALLER
                                       ? std::uint64_t(root * double(own)) + 2
                                       : spread(p, p, root, own);
        std::uint64_t xl[2], xh[2], yl[2], yh[2];
        const int nx = t_.axis_ranges(p.x, need, lattice_.extent_x, xl, xh),
                  ny = t_.axis_ranges(p.y, need, lattice_.extent_y, yl, yh);
        const std::uint32_t stamp = std::uint32_t(points_.size());  // the sample's index + 1
        for (int j = 0; j < ny; ++j)
            for (std::uint64_t cy = yl[j] >> mark_bits_; cy <= yh[j] >> mark_bits_; ++cy)
                for (int i = 0; i < nx; ++i)
                    for (std::uint64_t cx = xl[i] >> mark_bits_; cx <= xh[i] >> mark_bits_; ++cx)
                        marks_[std::size_t(cy) * marks_x_ + std::size_t(cx)] = stamp;
    }
    // Whether a sample placed since b's bound was set may lower it: one marked a cell b meets
    // (a block over many cells is taken as touched).
    bool touched(const Block& b) const {
        const glm::uvec2 a{b.x >> mark_bits_, b.y >> mark_bits_}, e = far_corner(b) >> mark_bits_;
        if (std::uint64_t(e.x - a.x + 1) * (e.y - a.y + 1) > 64) return true;
        for (std::uint32_t y = a.y; y <= e.y; ++y)
            for (std::uint32_t x = a.x; x <= e.x; ++x)
                if (marks_[std::size_t(y) * marks_x_ + x] > b.seen) return true;
        return false;
    }
    // Whether one of the samples that last marked the cells b meets covers b at the final field
    // (gives it a bound below 1), given r's least value `lo` over it: so are most stale blocks,
    // by a sample placed beside them since, found without a search.
    bool covered_by_marks(const Block& b, std::uint32_t lo) const {
        const glm::uvec2 a{b.x, b.y}, e = far_corner(b), ca = a >> mark_bits_, ce = e >> mark_bits_;
        if (std::uint64_t(ce.x - ca.x + 1) * (ce.y - ca.y + 1) > 64) return false;
        std::uint32_t tried = 0;
        for (std::uint32_t y = ca.y; y <= ce.y; ++y)
            for (std::uint32_t x = ca.x; x <= ce.x; ++x) {
                const std::uint32_t stamp = marks_[std::size_t(y) * marks_x_ + x];
                if (stamp <= b.seen || stamp == tried) continue;
                tried = stamp;
                if (bound_from(stamp - 1, a, e, lo).below_one()) return true;
            }
        return false;
    }
    // The least r over b's lattice points.
    std::uint32_t least_r(const Block& b) const { return least_r({b.x, b.y}, far_corner(b), b.bits); }
    std::uint32_t least_r(glm::uvec2 a, glm::uvec2 e, std::uint32_t bits) const {
        return bits == 0 ? t_.radius(a) : t_.min_over(a, e);
    }
    // The block's last lattice point on each axis.
    glm::uvec2 far_corner(const Block& b) const { return far_corner({b.x, b.y}, b.bits); }
    glm::uvec2 far_corner(glm::uvec2 corner, std::uint32_t bits) const {
        const std::uint64_t side = std::uint64_t(1) << bits;
        return {std::uint32_t(std::min<std::uint64_t>(corner.x + side, lattice_.extent_x) - 1),
                std::uint32_t(std::min<std::uint64_t>(corner.y + side, lattice_.extent_y) - 1)};
    }
    // The least distance along an axis from c to a point of [a, e].
    std::uint32_t nearest(std::uint32_t c, std::uint32_t a, std::uint32_t e, std::uint32_t extent) const {
        if (c >= a && c <= e) return 0;
        return std::min(shared::axis_gap(c, a, extent, lattice_.periodic),
                        shared::axis_gap(c, e, extent, lattice_.periodic));
    }
    // The bound sample k gives over [a, e], whose least r is `lo`: its farthest squared distance
    // over f with r(y) at its least (f is non-decreasing in r(y)); exact for a single point.
    Ratio bound_from(std::uint32_t k, glm::uvec2 a, glm::uvec2 e, std::uint32_t lo) const {
        const glm::uvec2 x = points_[k];
        const std::uint64_t dx = shared::axis_far_gap(x.x, a.x, e.x, lattice_.extent_x, lattice_.periodic),
                            dy = shared::axis_far_gap(x.y, a.y, e.y, lattice_.extent_y, lattice_.periodic);
        const std::uint64_t f = shared::rule_f(rule_, radius_[k], lo);
        return {dx * dx + dy * dy, f * f};
    }
    // The least bound of the samples within `reach` of [a, e]; unbounded where none is.
    Ratio search(glm::uvec2 a, glm::uvec2 e, std::uint32_t lo, std::uint64_t reach) const {
        Ratio best;
        tree_.near_samples(a, e, reach, [&](std::uint32_t leaf) {
            best = std::min(best, bound_from(tree_.sample(leaf), a, e, lo));
            return false;
        });
        return best;
    }
    // The least bound of the samples in `near_` over [a, e], whose least r is `lo`.
    Ratio least(glm::uvec2 a, glm::uvec2 e, std::uint32_t lo) const {
        Ratio best;
        for (const std::uint32_t k : near_) best = std::min(best, bound_from(k, a, e, lo));
        return best;
    }
    // How far from [a, e], where r is at most `known`, a point can be while f between it and a
    // point of [a, e] may pass their distance / root: root times the grown f (every rule's f is
    // at most max(r(x), r(y))).
    std::uint64_t spread(glm::uvec2 a, glm::uvec2 e, double root, std::uint32_t known) const {
        return std::uint64_t(std::ceil(root * double(t_.grown_reach(a, e, known, 2, root)))) + 2;
    }
    // The test a steep gather asks before it enters a subtree: may a sample in it pass within
    // for [a, e]? Its r is at most the subtree's largest, and f is non-decreasing in it.
    auto reaches(glm::uvec2 a, glm::uvec2 e) const {
        return [this, a, e](glm::i64vec2 image, glm::uvec2 corner, std::uint32_t bits) {
            const glm::u64vec2 g = tree_.image_gaps(image, bits, a, e);
            const std::uint32_t largest = t_.max_over(corner, far_corner(corner, bits));
            const double reach = near_root_ * double(shared::rule_f(rule_, largest, near_hi_)) + 2;
            const double dx = double(g.x), dy = double(g.y);
            return dx * dx + dy * dy < reach * reach;
        };
    }
    // Lists in near_ every sample that may give a block inside [a, e] a bound below g2 (bounded):
    // a sample x at distance d from [a, e] gives a block in it at least d^2 / f(x, y)^2 for some
    // y in [a, e], so nothing below g2 once d >= sqrt(g2) f. Under current and smaller f is at
    // most r(y), so at most the largest r over [a, e]; under prior and bigger r(x) counts too.
    void gather(glm::uvec2 a, glm::uvec2 e, Ratio g2) {
        const double root = std::sqrt(g2.quotient) * (1 + 1e-9);
        const std::uint32_t hi = t_.max_over(a, e);
        const std::uint64_t need = rule_ == shared::RULE_CURRENT || rule_ == shared::RULE_SMALLER
                                       ? std::uint64_t(root * double(hi)) + 2
                                       : spread(a, e, root, hi);
        near_.clear();
        near_root_ = root;
        near_hi_ = hi;
        auto keep = [&](std::uint32_t leaf) {
            if (const std::uint32_t k = tree_.sample(leaf); within(k, a, e)) near_.push_back(k);
            return false;
        };
        // Under prior and bigger a reach grown far past root r (larger r nearby) meets many
        // samples whose own r keeps them out: subtrees are tested before they are entered.
        if (need > 4 * std::uint64_t(root * double(hi)) + 4)
            tree_.near_samples(a, e, need, keep, reaches(a, e));
        else
            tree_.near_samples(a, e, need, keep);
    }
    // Whether sample k may give a block inside [a, e] (within the gathered one) a bound below the
    // gathered g2: whether it is nearer than sqrt(g2) f(r(k), the gathered block's largest r).
    bool within(std::uint32_t k, glm::uvec2 a, glm::uvec2 e) const {
        const glm::uvec2 x = points_[k];
        const double dx = double(nearest(x.x, a.x, e.x, lattice_.extent_x)),
                     dy = double(nearest(x.y, a.y, e.y, lattice_.extent_y));
        const double reach = near_root_ * double(shared::rule_f(rule_, radius_[k], near_hi_)) + 2;
        return dx * dx + dy * dy < reach * reach;
    }
    // Keeps in near_ the samples that may give a block inside b's one a bound below the gathered
    // g2 (those that may not for the larger block may not for any inside it).
    void narrow(const Block& b) {
        const glm::uvec2 a{b.x, b.y}, e = far_corner(b);
        std::erase_if(near_, [&](std::uint32_t k) { return !within(k, a, e); });
    }
    // Sets b's bound against every sample so far: from a first search within 1.5 S times its
    // largest r (the first level's samples lie about S r apart), widened till it meets one, the
    // samples gathered within that bound.
    void evaluate(Block& b) {
        const glm::uvec2 a{b.x, b.y}, e = far_corner(b);
        const std::uint32_t lo = least_r(a, e, b.bits);
        std::uint64_t reach = std::uint64_t(start_ * 1.5 * double(t_.max_over(a, e))) + 2;
        Ratio best = search(a, e, lo, reach);
        while (best.den == 0 && reach < 2 * std::uint64_t(std::max(lattice_.extent_x, lattice_.extent_y)))
            best = search(a, e, lo, reach *= 2);
        if (best.den != 0) {
            gather(a, e, best);
            best = std::min(best, least(a, e, lo));
        }
        b.g2 = best;
        b.seen = std::uint32_t(points_.size());
    }
    // The four children of b, each bound by the gathered samples (a list that decides every
    // block inside b). The least bound they give is the child's, or b's where they give more:
    // then no sample gives less than b's bound, which bounds the child. For one lattice point,
    // that is its exact g^2 either way. Queues all but the first of them in the queue's order
    // and returns that one (where no child is in the lattice, an empty block below one).
    Block split(const Block& b) {
        const std::uint32_t half = 1u << (b.bits - 1);
        Block first{0, 0, 0, 0, {0, 1}};
        for (std::uint32_t c = 0; c < 4; ++c) {
            Block child{b.x + (c & 1) * half, b.y + (c >> 1) * half, b.bits - 1, std::uint32_t(points_.size()), {}};
            if (child.x >= lattice_.extent_x || child.y >= lattice_.extent_y) continue;
            const glm::uvec2 a{child.x, child.y}, e = far_corner(child);
            child.g2 = std::min(b.g2, least(a, e, least_r(a, e, child.bits)));
            if (After{}(first, child)) std::swap(first, child);
            push(child);
        }
        return first;
    }
    // Lowers b's bound by the samples placed since it was set: by each directly where they are
    // few, else by those of them gathered near it (the others give no less than its bound).
    void update(Block& b, std::uint32_t lo) {
        constexpr std::size_t kDirect = 32;
        const glm::uvec2 a{b.x, b.y}, e = far_corner(b);
        const std::uint32_t seen = b.seen;
        if (points_.size() - seen > kDirect) {
            gather(a, e, b.g2);
            for (const std::uint32_t k : near_)
                if (k >= seen) b.g2 = std::min(b.g2, bound_from(k, a, e, lo));
        } else {
            for (std::size_t k = seen; k < points_.size(); ++k)
                b.g2 = std::min(b.g2, bound_from(std::uint32_t(k), a, e, lo));
        }
        b.seen = std::uint32_t(points_.size());
    }
    void push(const Block& b) {
        if (b.g2.below_one()) return;
        queue_.push(b);
        peak_queue_ = std::max<std::size_t>(peak_queue_, queue_.bytes());
    }

    const FieldTable& t_;
    const shared::Lattice lattice_;
    const std::uint32_t rule_;
    const double start_;
    FieldQuadtree tree_;
    std::vector<glm::uvec2> points_;
    std::vector<std::uint32_t> radius_;  // r at each sample, in lattice units
    BlockQueue queue_;
    std::vector<std::uint32_t> near_;  // gather's list
    double near_root_ = 0;             // sqrt of the gathered g2, and the gathered block's largest r
    std::uint32_t near_hi_ = 0;
    // Per cell of side 2^mark_bits_ (row by row, marks_x_ a row): 1 + the last sample that may
    // lower the bound of a block meeting it, 0 for none since the direct sampling.
    std::uint32_t mark_bits_ = 0, marks_x_ = 0;
    std::vector<std::uint32_t> marks_;
    std::size_t peak_queue_ = 0;
};

}  // namespace

std::uint64_t continue_hierarchy(const FieldTable& t, const SampleOptions& o, std::uint64_t max_leaves,
                                 std::vector<glm::uvec2>& samples, std::vector<double>& birth) {
    ThreadPool pool(o.backend == Backend::Serial ? 1 : o.threads);
    Events events(t, o, max_leaves, pool);
    events.run(samples, birth);
    return events.bytes();
}

}  // namespace vrpd::detail
