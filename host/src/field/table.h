// A sizing field tabulated for a run (vrpd.h, Sizing): the lattice it runs on, the table of node
// radii in lattice units (shared/field.h), and min/max pyramids that bound r over any block.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include "shared/field_table.h"
#include "../cpu/thread_pool.h"
#include "shared/lattice.h"
#include "vrpd/vrpd.h"

namespace vrpd::detail {

// A sizing field's source over points of the box: out[i] = r(x[i], y[i]) for i < n; throws nothing.
using FieldSource = std::function<void(const double* x, const double* y, double* out, std::size_t n)>;
// A source with kinks at points of the box (SizingExpression::kinked): its values and the branch
// mask each takes (SizingExpression::taken), and the branch a mask gives (SizingExpression::forced).
struct FieldBranches {
    std::function<void(const double* x, const double* y, double* out, std::uint8_t* mask, std::size_t n)> taken;
    std::function<void(const double* x, const double* y, double* out, const std::uint8_t* mask, std::size_t n)> forced;
    explicit operator bool() const { return bool(taken); }
};

// The source a Sizing names: its expression, or its image (loaded, checked greyscale), over the box.
FieldSource field_source(const Sizing& sizing, const Box& box);
// Its branches where it is an expression with kinks (SizingExpression::kinked), else empty.
FieldBranches field_branches(const Sizing& sizing, const Box& box);

// A table's data; FieldTable adds the view of its vectors that the lookups read.
struct FieldTableData {
    shared::Lattice lattice;
    double quantum = 0;           // lattice spacing in box units
    std::uint32_t tile_bits = 0;  // quadtree roots (tiles) span 2^tile_bits lattice units
    std::uint32_t tiles_x = 0, tiles_y = 0;
    std::uint32_t cell_bits = 0;             // table cells span 2^cell_bits lattice units
    std::uint32_t cells_x = 0, cells_y = 0;  // table cells over the tiles
    std::vector<std::uint32_t> nodes;        // (cells_x + 1) x (cells_y + 1), row by row
    // The min/max pyramids, level k >= 1 from pyramid_start[k] (shared/field_table.h).
    std::vector<std::uint32_t> pyramid_lo, pyramid_hi, pyramid_start;
    std::uint32_t r_lo = 0, r_hi = 0;      // over all nodes (a free box's outer ones too)
    std::uint32_t box_lo = 0, box_hi = 0;  // r's least and greatest over the box's lattice points
    double lipschitz = 0;                  // of the interpolant, exact
    double tabulation_error = 0;
    double constant = 0;  // the source's value where it is one constant, else 0

    // A table cell refined where its interpolant strays from the source (a kink, such as abs()'s):
    // a patch, a quadtree of splits over it whose leaves interpolate as the table's cells do
    // (shared/field_table.h). A split's node on an edge whose other side is a leaf of its size (a
    // table cell without a patch is one) lies on that leaf's edge, halfway between its corners, and
    // neighbouring leaves differ by at most one level, so the interpolant stays continuous (to its
    // rounding).
    struct Split {
        std::uint32_t children;  // the first child split's index << 4, and a bit per split child
        std::uint32_t mid[5];    // bottom, left, centre, right and top midpoints
        std::uint32_t lo, hi;    // its least and greatest node, its corners included
        bool operator==(const Split&) const = default;
    };
    std::vector<std::uint64_t> patched;     // a bit per table cell, row by row; empty without patches
    std::vector<std::uint32_t> patch_rank;  // per word of `patched`: the patches of the cells before it
    std::uint32_t patch_count = 0;
    std::vector<Split> splits;  // patch q's root is splits[q]; the other splits follow the roots

    // The table cells that the source's one kink crosses (its branches taken differently at their
    // corners): each the least or the greatest of its two branches' bilinear interpolants, as the
    // source is at every corner. A kinked cell's edge that the kink does not cross has one branch
    // at both ends, which is the source there, so r stays continuous with the cell beside it.
    std::vector<std::uint64_t> kinked;     // a bit per table cell, row by row; empty without kinks
    std::vector<std::uint32_t> kink_rank;  // per word of `kinked`: the kinked cells before it
    std::uint32_t kink_count = 0;
    std::vector<std::uint32_t> kinks;  // FIELD_KINK_WORDS a kinked cell, in cell order
};

struct FieldTable : FieldTableData {
    FieldTable() = default;
    // A copy or a move views its own vectors (and a table moved from, its emptied ones).
    FieldTable(const FieldTable& o) : FieldTableData(o) { refresh_view(); }
    FieldTable(FieldTable&& o) noexcept : FieldTableData(std::move(o)) {
        refresh_view();
        o.refresh_view();
    }
    FieldTable& operator=(const FieldTable& o) {
        FieldTableData::operator=(o);
        refresh_view();
        return *this;
    }
    FieldTable& operator=(FieldTable&& o) noexcept {
        FieldTableData::operator=(std::move(o));
        refresh_view();
        o.refresh_view();
        return *this;
    }

    std::uint32_t node(std::uint32_t i, std::uint32_t j) const { return nodes[std::size_t(j) * (cells_x + 1) + i]; }
    // The table as the shared lookups read it (shared/field_table.h): pointers into its vectors,
    // set again by refresh_view whenever they change (complete_bounds does, and every copy).
    const shared::FieldTableView& view() const { return view_; }
    void refresh_view() {
        static_assert(sizeof(Split) == 4 * shared::FIELD_SPLIT_WORDS && offsetof(Split, mid) == 4 &&
                      offsetof(Split, lo) == 24 && offsetof(Split, hi) == 28);
        view_ = {cell_bits,
                 cells_x,
                 cells_y,
                 patch_count,
                 {nodes.data()},
                 {patched.data()},
                 {patch_rank.data()},
                 {reinterpret_cast<const std::uint32_t*>(splits.data())},
                 {pyramid_lo.data()},
                 {pyramid_hi.data()},
                 {pyramid_start.data()},
                 kink_count,
                 0,
                 {kinked.data()},
                 {kink_rank.data()},
                 {kinks.data()}};
    }
    // The four nodes of table cell (i, j), in field_interpolate's order.
    glm::uvec4 cell_nodes(std::uint32_t i, std::uint32_t j) const { return shared::field_cell_nodes(view(), i, j); }
    // Whether table cell (i, j) has a patch; whether it is kinked.
    bool patch(std::uint32_t i, std::uint32_t j) const { return shared::field_patch(view(), i, j) >= 0; }
    bool kink(std::uint32_t i, std::uint32_t j) const { return shared::field_kink(view(), i, j) >= 0; }
    // r at lattice point p (inside the lattice).
    std::uint32_t radius(glm::uvec2 p) const { return shared::field_radius(view(), p); }
    // Starts fetching the nodes radius(p) reads.
    void prefetch(glm::uvec2 p) const {
        const std::uint32_t* v = &nodes[std::size_t(p.y >> cell_bits) * (cells_x + 1) + (p.x >> cell_bits)];
        __builtin_prefetch(v);
        __builtin_prefetch(v + cells_x + 1);
    }
    // The least and greatest r over the lattice points of [x0, x1] x [y0, y1] (inclusive, inside
    // the lattice): exact inside one table cell, else a bound from the pyramid.
    std::uint32_t min_over(glm::uvec2 a, glm::uvec2 b) const;
    std::uint32_t max_over(glm::uvec2 a, glm::uvec2 b) const;
    // min_over for the children of a block [a, b] split at m along each axis: child k spans
    // [a.x, e.x] or [m.x, b.x] by bit 0 of k, [a.y, e.y] or [m.y, b.y] by bit 1 (e = min(m - 1, b)).
    // Asked only for the children in `open` (bit k: child k, inside [a, b]); inside one table cell
    // the 16 corners share their reads and their interpolation along x.
    std::array<std::uint32_t, 4> children_min(glm::uvec2 a, glm::uvec2 e, glm::uvec2 m, glm::uvec2 b,
                                              std::uint32_t open) const;
    // Both, {min_over, max_over}, with one read of the table inside one table cell.
    std::pair<std::uint32_t, std::uint32_t> extremes_over(glm::uvec2 a, glm::uvec2 b) const;
    // The same over a square of half-width `reach` around p (wrapping on a torus, clipped to a free box).
    std::uint32_t max_near(glm::uvec2 p, std::uint64_t reach) const;
    // The lattice coordinates within `reach` of c along an axis of `extent` points, as one or (on
    // a torus, wrapped) two inclusive ranges [lo[k], hi[k]]; returns how many.
    int axis_ranges(std::uint32_t c, std::uint64_t reach, std::uint32_t extent, std::uint64_t lo[2],
                    std::uint64_t hi[2]) const;
    // A bound on f = max(r(z), r_hi) over the points z within `scale` f of [a, b], where r_hi >= r
    // over [a, b]: r_hi grown by the Lipschitz bound (r(z) <= r_hi + L |z - [a, b]| + 1, the 1 for
    // the floor; where scale L < 1) or the field's largest r, then shrunk to the largest r over
    // the square around [a, b] that reaches while it shrinks, at most `steps` times.
    std::uint64_t grown_reach(glm::uvec2 a, glm::uvec2 b, std::uint32_t r_hi, int steps, double scale = 1) const;
    FieldStats stats() const;
    // The bytes the nodes, the kinked cells, the patches' splits and the pyramids hold.
    std::uint64_t bytes() const {
        std::uint64_t n =
            nodes.capacity() + patch_rank.capacity() + 2 * patched.capacity() + splits.capacity() * sizeof(Split) / 4;
        n += kink_rank.capacity() + 2 * kinked.capacity() + kinks.capacity();
        n += pyramid_lo.capacity() + pyramid_hi.capacity() + pyramid_start.capacity();
        return 4 * n;
    }

private:
    shared::FieldTableView view_{};
};

// The words shared::field_ranked reads for a table of `cells` cells: in `bits`, a bit for each
// cell of `set`, and in `rank`, per word, the set bits before it.
inline void rank_cells(std::size_t cells, std::span<const std::uint32_t> set, std::vector<std::uint64_t>& bits,
                       std::vector<std::uint32_t>& rank) {
    bits.assign((cells + 63) / 64, 0);
    rank.assign(bits.size(), 0);
    for (const std::uint32_t c : set) bits[c >> 6] |= std::uint64_t(1) << (c & 63);
    std::uint32_t before = 0;
    for (std::size_t w = 0; w < bits.size(); ++w) {
        rank[w] = before;
        before += std::uint32_t(std::popcount(bits[w]));
    }
}

// The leaves per unit area that quadtree roots (tiles) of a side give, estimated from r at the
// centres of a survey's n x n cells of the box, row by row: a leaf is the largest part tile / 2^k
// of a tile whose diagonal is below the least r over it (field/quadtree.cpp), about r - g s
// (4 / pi) / 2 for a leaf of side s about the point, where r's slope is g (the mean over
// directions of a square's half-width). So 2^k > tile (sqrt(2) + 0.64 g) / r: with
// l = log2((sqrt(2) + 0.64 g) / r), k = floor(log2 tile + l) + 1 for tiles of side over r / 2.
// The points' 4^floor(l), binned by l's fraction (1/1024), give the sum for any side at once.
class LeafDensity {
public:
    LeafDensity(const std::vector<double>& survey, std::uint32_t n, const Box& box);
    double operator()(double tile) const;

private:
    static constexpr std::size_t kBins = 1024;
    static constexpr double kSlope = 2 / 3.141592653589793;
    std::array<double, kBins> above_{};  // the points' 4^floor(l) from each bin of l's fraction up
    double points_;
};

// The bytes per unit area that the leaves and the table at its coarsest (cells of side
// side / 2^a at most 8 `least` wide) take at a run's peak, with tiles of a side.
double tile_bytes(const LeafDensity& leaves, double side, double least);

// The tiles (quadtree roots) of a side in (largest / 2, largest] whose leaves and table take the
// fewest bytes: the leaves (LeafDensity over the survey of n x n cells; 5 or 6 a sample, which set
// much of a run's time too) and the table at its coarsest (cells of side tile / 2^a at most 8
// `least` wide). Both are powers of two below the tile, so each side falls differently against r;
// past half the side, halved tiles give the same again. On a torus the candidates are tilings of
// the box, from tx x ty (in: the largest tiles' counts) to twice as many a side; a free box takes
// any side. kTileCandidates at most, spread evenly in log2 of the side. Returns the side, with its
// counts in tx, ty.
double lightest_tiles(const Box& box, double largest, double least, std::uint64_t& tx, std::uint64_t& ty,
                      const std::vector<double>& survey, std::uint32_t n);

// Sets t's bounds from its nodes and patches, on the pool's threads: r_lo, r_hi, box_lo, box_hi,
// the interpolant's L and the min/max pyramids.
void complete_bounds(FieldTable& t, ThreadPool& pool);

// t with every node (patches' too) times `scale`, rounded: on the same lattice, the field
// scale r, each level of a hierarchy of the field (r at a point is non-decreasing in the scale).
// Throws Error where a node passes 32 bits.
FieldTable scaled(const FieldTable& t, double scale, ThreadPool& pool);

// Replaces the nodes of `cells_x` x `cells_y` table cells of side h (row by row; on a torus the
// last row and column repeat the first) by the largest L-Lipschitz function at or below them:
// each node's least v(y) + L |x - y| over the nodes y (on a torus, the nearest image of y).
// Runs on `threads` threads (0: one per hardware thread).
void limit_lipschitz(std::span<double> values, std::uint32_t cells_x, std::uint32_t cells_y, double h, double L,
                     bool periodic, unsigned threads = 0);

// Tabulates the field of `sizing` over `box`. Throws Error with the reason for a field that is
// not a finite number > 0 somewhere, an image that cannot be read, or radii the lattice cannot hold.
// The source is evaluated on `threads` threads (0: one per hardware thread).
FieldTable tabulate(const Sizing& sizing, const Box& box, unsigned threads = 0);

}  // namespace vrpd::detail
