// The patches of a sizing field's table as they are drafted (field/patches.h): a forest of
// quadtrees, one over each patched table cell, whose leaves meet their neighbours' across table
// cells, and which is graded, made continuous and judged against the source as a whole.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "patches.h"

namespace vrpd::detail::patch {

// Leaves down to 2^-12 table cells: 8 lattice units.
constexpr std::uint32_t kMaxLevel = 12;
// Squares whose midpoints the source is asked for in one call, on one thread.
constexpr std::size_t kBatch = 256;

using Corners = std::array<double, 4>;  // field_interpolate's order: v00, v10, v01, v11

// A square's midpoints in half-sides from its corner: bottom, left, centre, right, top.
constexpr std::uint32_t kMid[5][2] = {{1, 0}, {0, 1}, {1, 1}, {2, 1}, {1, 2}};
// Per edge (0 below, 1 above, 2 left, 3 right, as Forest::across numbers them): its midpoint, and
// the corners at its ends.
constexpr int kEdgeMid[4] = {0, 4, 1, 3};
constexpr int kEdgeEnds[4][2] = {{0, 1}, {2, 3}, {0, 2}, {1, 3}};

// The interpolant at midpoint k: the mean of the two corners beside it or the four around it.
inline double mean_at(const Corners& v, int k) {
    switch (k) {
        case 0:
            return (v[0] + v[1]) * 0.5;
        case 1:
            return (v[0] + v[2]) * 0.5;
        case 2:
            return ((v[0] + v[1]) + (v[2] + v[3])) * 0.25;
        case 3:
            return (v[1] + v[3]) * 0.5;
        default:
            return (v[2] + v[3]) * 0.5;
    }
}

// Child c's corners (shared/field_table.h's field_child_nodes) from its parent's corners v and the
// parent's midpoints m.
inline Corners child_corners(const Corners& v, const double* m, int c) {
    switch (c) {
        case 0:
            return {v[0], m[0], m[1], m[2]};
        case 1:
            return {m[0], v[1], m[2], m[3]};
        case 2:
            return {m[1], m[2], v[2], m[4]};
        default:
            return {m[2], m[3], m[4], v[3]};
    }
}

// A square of a patch, by level and place in its table cell.
struct Square {
    std::uint32_t cell, level, x, y;
    Square child(int c) const { return {cell, level + 1, 2 * x + (c & 1), 2 * y + (c >> 1)}; }
};

// A leaf of the patched table: in a table cell without a patch (patch -1: the cell itself, level
// 0), or child `child` of split `split` of patch `patch`.
struct Leaf {
    std::uint32_t cell;
    std::int32_t patch, split;
    int child;
    std::uint32_t level;
};

// The source at a square's five midpoints.
struct Midpoints {
    double x[5], y[5], source[5];
    double node[5];  // as nodes: node_value's
    double x0, y0, side;
};

class Forest {
public:
    Forest(const FieldSource& f, const Box& box, const TableDraft& d)
        : f_(f),
          box_(box),
          d_(d),
          periodic_(box.boundary == Boundary::Periodic),
          slot_(std::size_t(d.cells_x) * d.cells_y, -1) {}

    std::vector<PatchDraft> patches;
    std::vector<std::uint32_t> touched;  // the table cells split has split in, since last cleared
    std::uint64_t split_count = 0;       // the splits of all patches

    std::int32_t slot(std::uint32_t cell) const { return slot_[cell]; }

    // Calls visit(n) for table cell c and each cell sharing an edge with it (on a torus, around).
    template <typename Visit>
    void each_neighbour(std::uint32_t c, Visit&& visit) const {
        visit(c);
        const std::int64_t i = c % d_.cells_x, j = c / d_.cells_x;
        constexpr int kStep[4][2] = {{0, -1}, {0, 1}, {-1, 0}, {1, 0}};
        for (const auto& step : kStep) {
            std::int64_t x = i + step[0], y = j + step[1];
            if (periodic_) {
                x = (x + d_.cells_x) % d_.cells_x;
                y = (y + d_.cells_y) % d_.cells_y;
            } else if (x < 0 || y < 0 || x >= d_.cells_x || y >= d_.cells_y) {
                continue;
            }
            visit(std::uint32_t(y * d_.cells_x + x));
        }
    }

    // The table cell's corners.
    Corners corners(std::uint32_t cell) const {
        const std::size_t row = std::size_t(d_.cells_x) + 1, i = cell % d_.cells_x, j = cell / d_.cells_x;
        const double* n = &d_.values[j * row + i];
        return {n[0], n[1], n[row], n[row + 1]};
    }

    // The source at the squares' midpoints, in one call of the source.
    void midpoints(const Square* squares, std::size_t n, Midpoints* out) const {
        // Each thread's scratch, kept from call to call: neither allocated nor cleared again.
        thread_local std::vector<double> xs, ys, vs;
        xs.resize(5 * n);
        ys.resize(5 * n);
        vs.resize(5 * n);
        for (std::size_t i = 0; i < n; ++i) {
            const Square& s = squares[i];
            Midpoints& m = out[i];
            const std::uint32_t bits = s.level + 1;
            const double step = std::ldexp(d_.h, -int(bits));
            const std::uint64_t gx = (std::uint64_t(s.cell % d_.cells_x) << bits) + 2 * std::uint64_t(s.x),
                                gy = (std::uint64_t(s.cell / d_.cells_x) << bits) + 2 * std::uint64_t(s.y);
            // Grid point `at` of 2^bits a table cell: the same double as any coarser grid's for
            // the same point (the table's too); on a torus the last is the first.
            auto coordinate = [&](std::uint64_t at, std::uint32_t cells) {
                return double(periodic_ && at == std::uint64_t(cells) << bits ? 0 : at) * step;
            };
            for (int k = 0; k < 5; ++k) {
                xs[5 * i + std::size_t(k)] = m.x[k] = coordinate(gx + kMid[k][0], d_.cells_x);
                ys[5 * i + std::size_t(k)] = m.y[k] = coordinate(gy + kMid[k][1], d_.cells_y);
            }
            m.x0 = double(gx) * step;
            m.y0 = double(gy) * step;
            m.side = 2 * step;
        }
        f_(xs.data(), ys.data(), vs.data(), 5 * n);
        for (std::size_t i = 0; i < n; ++i)
            for (int k = 0; k < 5; ++k) {
                Midpoints& m = out[i];
                m.source[k] = vs[5 * i + std::size_t(k)];
                m.node[k] = node_value(f_, box_, m.x[k], m.y[k], m.source[k]);
            }
    }
    Midpoints midpoints(const Square& s) const {
        Midpoints m;
        midpoints(&s, 1, &m);
        return m;
    }

    // The largest relative distance from the source of the interpolant of corners v at the
    // square's midpoints. A point past a free box's edge is judged at the edge, where that is in
    // the square.
    double error(const Midpoints& m, const Corners& v) const {
        double e = 0;
        for (int k = 0; k < 5; ++k) {
            if (m.x[k] <= box_.width && m.y[k] <= box_.height) {
                e = std::max(e, std::abs(mean_at(v, k) - m.node[k]) / m.node[k]);
                continue;
            }
            const double ex = std::min(m.x[k], box_.width), ey = std::min(m.y[k], box_.height);
            if (ex < m.x0 || ey < m.y0) continue;
            const double s = source_at(f_, ex, ey), u = (ex - m.x0) / m.side, w = (ey - m.y0) / m.side;
            const double at = (v[0] * (1 - u) + v[1] * u) * (1 - w) + (v[2] * (1 - u) + v[3] * u) * w;
            e = std::max(e, std::abs(at - s) / s);
        }
        return e;
    }

    // Table cell c's patch of one split, its nodes the table draft's points halfway between the
    // cell's (the same doubles as the source's at those points, as nodes).
    PatchDraft root(std::uint32_t c) const {
        const std::size_t row = 2 * std::size_t(d_.cells_x) + 1, i = 2 * (c % d_.cells_x), j = 2 * (c / d_.cells_x);
        const double* low = &d_.fine[j * row + i];
        const double node[5] = {low[1], low[row], low[row + 1], low[row + 2], low[2 * row + 1]};
        PatchDraft p;
        p.cell = c;
        p.splits.push_back(made(Square{c, 0, 0, 0}, node));
        return p;
    }

    // Adds patches grown in cell order.
    void adopt(std::vector<PatchDraft>&& grown) {
        patches.reserve(patches.size() + grown.size());
        for (PatchDraft& p : grown) {
            split_count += p.splits.size();
            slot_[p.cell] = std::int32_t(patches.size());
            patches.push_back(std::move(p));
        }
    }

    // A point (in squares of kMaxLevel) inside the square of the same size across edge e of s, or
    // none past a free box's table.
    std::optional<std::array<std::uint64_t, 2>> across(const Square& s, int e) const {
        const std::uint32_t shift = kMaxLevel - s.level;
        const std::int64_t side = std::int64_t(1) << shift;
        std::int64_t gx = (std::int64_t(s.cell % d_.cells_x) << kMaxLevel) + (std::int64_t(s.x) << shift),
                     gy = (std::int64_t(s.cell / d_.cells_x) << kMaxLevel) + (std::int64_t(s.y) << shift);
        gx += e == 2 ? -1 : e == 3 ? side : 0;
        gy += e == 0 ? -1 : e == 1 ? side : 0;
        const std::int64_t wx = std::int64_t(d_.cells_x) << kMaxLevel, wy = std::int64_t(d_.cells_y) << kMaxLevel;
        if (gx < 0 || gy < 0 || gx >= wx || gy >= wy) {
            if (!periodic_) return std::nullopt;
            gx = (gx + wx) % wx;
            gy = (gy + wy) % wy;
        }
        return std::array<std::uint64_t, 2>{std::uint64_t(gx), std::uint64_t(gy)};
    }

    // The leaf that holds point g (in squares of kMaxLevel).
    Leaf locate(const std::array<std::uint64_t, 2>& g) const {
        const std::uint32_t cell = std::uint32_t(g[1] >> kMaxLevel) * d_.cells_x + std::uint32_t(g[0] >> kMaxLevel);
        Leaf l{cell, slot_[cell], -1, 0, 0};
        if (l.patch < 0) return l;
        const std::vector<PatchDraft::Split>& splits = patches[std::size_t(l.patch)].splits;
        for (std::int32_t s = 0; s >= 0; ++l.level) {
            const std::uint32_t shift = kMaxLevel - l.level - 1;
            l.split = s;
            l.child = int((g[0] >> shift) & 1) | int((g[1] >> shift) & 1) << 1;
            s = splits[std::size_t(s)].child[l.child];
        }
        return l;
    }

    // The level of the leaf across edge e of s (of s's size or larger: s's level or less; inside
    // splits of its size: more), or none.
    std::optional<std::uint32_t> level_across(const Square& s, int e) const {
        const auto g = across(s, e);
        if (!g) return std::nullopt;
        return locate(*g).level;
    }

    Square square(const Leaf& l) const {
        if (l.patch < 0) return {l.cell, 0, 0, 0};
        const PatchDraft::Split& s = patches[std::size_t(l.patch)].splits[std::size_t(l.split)];
        return Square{l.cell, s.level, s.x, s.y}.child(l.child);
    }

    // Splits leaf l (a table cell without a patch gets one); returns the new split.
    std::pair<std::int32_t, std::int32_t> split(const Leaf& l) {
        touched.push_back(l.cell);
        ++split_count;
        if (l.patch < 0) {
            slot_[l.cell] = std::int32_t(patches.size());
            patches.push_back(root(l.cell));
            return {slot_[l.cell], 0};
        }
        PatchDraft& p = patches[std::size_t(l.patch)];
        const std::int32_t s = std::int32_t(p.splits.size());
        p.splits.push_back(made(square(l)));
        p.splits[std::size_t(l.split)].child[l.child] = s;
        return {l.patch, s};
    }

    // Splits leaves until no two sharing an edge are more than one level apart: a split's square
    // has none of a larger size across its edges. `work` holds the splits to check; those made
    // are checked in turn.
    void balance(std::vector<std::pair<std::int32_t, std::int32_t>>& work) {
        while (!work.empty()) {
            const auto [p, s] = work.back();
            work.pop_back();
            const PatchDraft::Split& split = patches[std::size_t(p)].splits[std::size_t(s)];
            const Square sq{patches[std::size_t(p)].cell, split.level, split.x, split.y};
            for (int e = 0; e < 4 && sq.level > 0; ++e) {
                const auto g = across(sq, e);
                if (!g) continue;
                for (Leaf l = locate(*g); l.level < sq.level; l = locate(*g)) work.push_back(this->split(l));
            }
        }
    }

    // What settle finds over a patch's leaves.
    struct Settled {
        double error = 0;        // the largest error
        double steepest = 0;     // the largest gradient with the source's nodes at every corner
        std::vector<Leaf> past;  // those past the target
        // Those with a corner moved for continuity that are steeper than the reference, and their
        // gradient.
        std::vector<std::pair<Leaf, double>> moved;
    };

    // Sets each split's values (continuity: a midpoint whose edge has a leaf of the split's size
    // across it lies halfway between the split's corners there) and measures each leaf of patch p.
    // Gradients are in node units per table cell; `steepest` is the reference, a gradient reached
    // already (only a steeper one is measured exactly).
    Settled settle(std::size_t p, double target, double steepest) {
        PatchDraft& patch = patches[p];
        Settled out;
        out.steepest = steepest;
        struct Node {
            std::int32_t split;
            Corners v, source;  // the corners as settled, and as the source gives them
        };
        struct Open {
            Leaf leaf;
            Square square;
            Corners v, source;
        };
        // Each thread's scratch, kept from patch to patch.
        thread_local std::vector<Open> leaves;
        thread_local std::vector<Node> stack;
        thread_local std::vector<Square> squares;
        thread_local std::vector<Midpoints> m;
        leaves.clear();
        const Corners first = corners(patch.cell);
        stack.assign(1, {0, first, first});
        while (!stack.empty()) {
            const Node n = stack.back();
            stack.pop_back();
            PatchDraft::Split& split = patch.splits[std::size_t(n.split)];
            const Square sq{patch.cell, split.level, split.x, split.y};
            std::copy(std::begin(split.source), std::end(split.source), split.value);
            for (int e = 0; e < 4; ++e) {
                const std::optional<std::uint32_t> level = level_across(sq, e);
                if (level && *level <= sq.level)
                    split.value[kEdgeMid[e]] =
                        (n.v[std::size_t(kEdgeEnds[e][0])] + n.v[std::size_t(kEdgeEnds[e][1])]) * 0.5;
            }
            for (int k = 0; k < 4; ++k) {
                const Corners cv = child_corners(n.v, split.value, k), cs = child_corners(n.source, split.source, k);
                if (split.child[k] >= 0) {
                    stack.push_back({split.child[k], cv, cs});
                    continue;
                }
                const Leaf leaf{patch.cell, std::int32_t(p), n.split, k, sq.level + 1};
                // A leaf with the source's nodes at its corners keeps the error it was judged at.
                if (cv == cs && split.error[k] >= 0) {
                    out.error = std::max(out.error, double(split.error[k]));
                    if (split.error[k] > target) out.past.push_back(leaf);
                    raise_steepest(out.steepest, cs[0], cs[1], cs[2], cs[3], double(1u << leaf.level));
                    continue;
                }
                leaves.push_back({leaf, sq.child(k), cv, cs});
            }
        }
        squares.resize(leaves.size());
        for (std::size_t i = 0; i < leaves.size(); ++i) squares[i] = leaves[i].square;
        m.resize(leaves.size());
        midpoints(squares.data(), squares.size(), m.data());
        for (std::size_t i = 0; i < leaves.size(); ++i) {
            const Open& o = leaves[i];
            const double e = error(m[i], o.v);
            if (o.v == o.source) patch.splits[std::size_t(o.leaf.split)].error[o.leaf.child] = float(e);
            out.error = std::max(out.error, e);
            if (e > target) out.past.push_back(o.leaf);
            const double scale = double(1u << o.leaf.level);
            raise_steepest(out.steepest, o.source[0], o.source[1], o.source[2], o.source[3], scale);
            if (o.v != o.source) {
                double g = steepest;
                raise_steepest(g, o.v[0], o.v[1], o.v[2], o.v[3], scale);
                if (g > steepest) out.moved.push_back({o.leaf, g});
            }
        }
        return out;
    }

    PatchDraft::Split made(const Square& s) const { return made(s, midpoints(s).node); }
    static PatchDraft::Split made(const Square& s, const double* node) {
        PatchDraft::Split out;
        std::copy(node, node + 5, out.source);
        std::copy(node, node + 5, out.value);
        out.x = std::uint16_t(s.x);
        out.y = std::uint16_t(s.y);
        out.level = std::uint8_t(s.level);
        return out;
    }

private:
    const FieldSource& f_;
    const Box& box_;
    const TableDraft& d_;
    bool periodic_;
    std::vector<std::int32_t> slot_;  // each table cell's patch, or -1
};

}  // namespace vrpd::detail::patch
