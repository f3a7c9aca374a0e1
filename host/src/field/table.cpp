// Tabulating a sizing field (field/table.h). The lattice: quadtree roots (tiles) from r_max / 2
// to r_max wide, of the side whose leaves and table are lightest (field/tiles.cpp), and table
// cells of 2^15 lattice units at most 8 r_min wide, so r_min spans at least 4096 lattice units
// and the interpolant's rounding costs under 0.025 %. The table is refined (table cells and
// lattice halved together) while its interpolant is further than 0.075 % from the source at some
// table cell's centre or edge midpoint, within the 31-bit lattice and a budget of 8 nodes per
// expected sample. A kink, such as abs()'s, converges only linearly, so the cells still past
// 0.075 % then get patches (field/patches.cpp), quadtrees of their own, within a budget of 8
// table words per expected sample (at least 2^18; a split takes 8); where they cannot reach
// 0.075 % within it, they reach the least target they can, up by factors of sqrt(2).
#include "table.h"

#include "patches.h"

#include "field.h"
#include "../cpu/thread_pool.h"
#include "../cpu/uninitialised.h"
#include "../plan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include <fmt/format.h>

namespace vrpd::detail {
namespace {

constexpr std::uint64_t kLatticeLimit = 0x7FFFFFFFu;
constexpr std::uint64_t kMaxTableNodes = std::uint64_t(16) << 20;
constexpr double kTargetError = 0.00075;
constexpr double kNodesPerSample = 8;
constexpr std::uint64_t kMinTableNodes = std::uint64_t(1) << 16;
constexpr std::uint32_t kMinLatticeRadius = 4096;
constexpr std::uint32_t kSurvey = 256;
constexpr double kMinPatchWords = 1 << 18;

// The double-valued table at a resolution: its nodes, the source at the points halfway between
// them (which are the next resolution's nodes), and its largest relative error against the
// source at those of them inside the box.
// Its arrays are first touched by the row threads that fill them, on huge pages where granted.
using Doubles = std::vector<double, Uninitialised<double, true>>;
struct Draft {
    std::uint32_t cells_x = 0, cells_y = 0;
    double h = 0;
    Doubles values;
    Doubles fine;  // (2 cells_x + 1) x (2 cells_y + 1), at spacing h / 2
    double error = 0;
    std::uint64_t over = 0;  // the points where the error is past the target
};

// Calls row(j) for j in [0, n) on the pool's threads, from two rows on (a row holds hundreds of
// nodes or more); an Error stops the run as each_reporting says.
void for_rows(ThreadPool& pool, std::size_t n, const std::function<void(std::size_t)>& row) {
    constexpr std::size_t kRowGrain = 2;
    each_reporting(pool, n, kRowGrain, row);
}

// Fills entries first, first + step, ... of row j of the nodes of n_x x n_y cells of side h. On a
// torus the last row and column are the first: the field wraps. Inside the box a node is the
// source there, checked; past a free box's edge, the source there if it is a radius, else its
// value at the edge.
void fill_nodes(const FieldSource& f, const Box& box, bool periodic, std::uint32_t n_x, std::uint32_t n_y, double h,
                std::size_t j, std::uint32_t first, std::uint32_t step, double* row) {
    const std::size_t sj = periodic && j == n_y ? 0 : j;
    const double y = double(sj) * h;
    std::vector<double> xs, ys, vs;
    for (std::uint32_t i = first; i <= n_x; i += step) xs.push_back((periodic && i == n_x ? 0 : i) * h);
    ys.assign(xs.size(), y);
    vs.resize(xs.size());
    f(xs.data(), ys.data(), vs.data(), xs.size());
    for (std::size_t k = 0; k < xs.size(); ++k) row[first + k * step] = node_value(f, box, xs[k], y, vs[k]);
}

// The bilinear interpolant of a cell with nodes n[0], n[1] (row 0) and n[row], n[row + 1] at a
// halfway point (tx, ty): (0.5, 0.5), (0.5, 0) or (0, 0.5). There it is the mean of the four
// nodes around the point (the centre) or of the two beside it (an edge's midpoint).
[[gnu::always_inline]] inline double midpoint_mean(const double* n, std::size_t row, double tx, double ty) {
    return ty == 0   ? (n[0] + n[1]) * 0.5
           : tx == 0 ? (n[0] + n[row]) * 0.5
                     : ((n[0] + n[1]) + (n[row] + n[row + 1])) * 0.25;
}

// The relative error of a draft's interpolant at point (tx, ty) of cell (i, j), a halfway point
// (its value in d.fine). A point past a free box's edge is judged at the edge, inside the cell.
[[gnu::always_inline]] inline double point_error(const FieldSource& f, const Box& box, const Draft& d, std::uint32_t i,
                                                 std::uint32_t j, double tx, double ty) {
    const std::size_t row = std::size_t(d.cells_x) + 1;
    const double* n = &d.values[std::size_t(j) * row + i];
    const double fx = (i + tx) * d.h, fy = (double(j) + ty) * d.h;
    if (fx <= box.width && fy <= box.height) [[likely]] {
        const double v =
            d.fine[(2 * std::size_t(j) + std::size_t(2 * ty)) * (2 * row - 1) + 2 * i + std::size_t(2 * tx)];
        const double mean = midpoint_mean(n, row, tx, ty);
        return std::abs(mean - v) / v;
    }
    const double x = std::min(fx, box.width), y = std::min(fy, box.height);
    const double v = source_at(f, x, y);
    tx = x / d.h - i;
    ty = y / d.h - double(j);
    const double at = (n[0] * (1 - tx) + n[1] * tx) * (1 - ty) + (n[row] * (1 - tx) + n[row + 1] * tx) * ty;
    return std::abs(at - v) / v;
}

// The errors at cell (i, j)'s centre, bottom midpoint and left midpoint (point_error's). A cell
// wholly inside the box reads its points' values from d.fine directly.
[[gnu::always_inline]] inline std::array<double, 3> cell_point_errors(const FieldSource& f, const Box& box,
                                                                      const Draft& d, std::uint32_t i,
                                                                      std::uint32_t j) {
    if ((i + 1.0) * d.h > box.width || (j + 1.0) * d.h > box.height) [[unlikely]]
        return {point_error(f, box, d, i, j, 0.5, 0.5), point_error(f, box, d, i, j, 0.5, 0.0),
                point_error(f, box, d, i, j, 0.0, 0.5)};
    const std::size_t row = std::size_t(d.cells_x) + 1, fine_row = 2 * row - 1;
    const double* n = &d.values[std::size_t(j) * row + i];
    const double* low = &d.fine[2 * std::size_t(j) * fine_row + 2 * std::size_t(i)];
    const double* mid = low + fine_row;
    const double centre = midpoint_mean(n, row, 0.5, 0.5), bottom = midpoint_mean(n, row, 0.5, 0),
                 left = midpoint_mean(n, row, 0, 0.5);
    return {std::abs(centre - mid[1]) / mid[1], std::abs(bottom - low[1]) / low[1], std::abs(left - mid[0]) / mid[0]};
}

// Per cell of the draft, the largest error at its centre and edge midpoints (those past a free
// box's far edges excepted, as the draft's own error does).
std::vector<double> cell_errors(ThreadPool& pool, const FieldSource& f, const Box& box, const Draft& d) {
    const bool periodic = box.boundary == Boundary::Periodic;
    std::vector<double> out(std::size_t(d.cells_x) * d.cells_y, 0.0);
    auto measured = [&](std::uint32_t i, std::uint32_t j) { return i * d.h < box.width && j * d.h < box.height; };
    for_rows(pool, d.cells_y, [&](std::size_t jj) {
        const std::uint32_t j = std::uint32_t(jj);
        for (std::uint32_t i = 0; i < d.cells_x; ++i) {
            if (!measured(i, j)) continue;
            const std::array<double, 3> own = cell_point_errors(f, box, d, i, j);
            double e = std::max({own[0], own[1], own[2]});
            // The top and right midpoints, as the cells above and to the right measure them.
            const std::uint32_t up = j + 1 < d.cells_y ? j + 1 : 0, right = i + 1 < d.cells_x ? i + 1 : 0;
            if ((j + 1 < d.cells_y || periodic) && measured(i, up))
                e = std::max(e, point_error(f, box, d, i, up, 0.5, 0.0));
            if ((i + 1 < d.cells_x || periodic) && measured(right, j))
                e = std::max(e, point_error(f, box, d, right, j, 0.0, 0.5));
            out[std::size_t(j) * d.cells_x + i] = e;
        }
    });
    return out;
}

// The draft of n_x x n_y cells of side h, from its nodes if the last draft's `fine` holds them.
Draft draft(ThreadPool& pool, const FieldSource& f, const Box& box, std::uint32_t cells_x, std::uint32_t cells_y,
            double h, Doubles nodes) {
    Draft d{cells_x, cells_y, h, std::move(nodes), {}, 0};
    const bool periodic = box.boundary == Boundary::Periodic;
    const std::size_t row = std::size_t(cells_x) + 1;
    if (d.values.empty()) {
        d.values.resize(row * (std::size_t(cells_y) + 1));
        for_rows(pool, std::size_t(cells_y) + 1, [&](std::size_t j) {
            fill_nodes(f, box, periodic, cells_x, cells_y, h, j, 0, 1, &d.values[j * row]);
        });
    }
    // The halfway points: the nodes' rows with every other entry new, and the rows between them.
    const std::size_t fine_row = 2 * row - 1;
    d.fine.resize(fine_row * (2 * std::size_t(cells_y) + 1));
    for_rows(pool, 2 * std::size_t(cells_y) + 1, [&](std::size_t j) {
        double* out = &d.fine[j * fine_row];
        const bool even = j % 2 == 0;
        if (even)
            for (std::size_t i = 0; i < row; ++i) out[2 * i] = d.values[j / 2 * row + i];
        fill_nodes(f, box, periodic, 2 * cells_x, 2 * cells_y, h / 2, j, even ? 1 : 0, even ? 2 : 1, out);
    });
    std::vector<double> error(cells_y, 0.0);  // per row, so that threads never share one
    std::vector<std::uint64_t> over(cells_y, 0);
    for_rows(pool, cells_y, [&](std::size_t j) {
        if (double(j) * h >= box.height) return;
        for (std::uint32_t i = 0; i < cells_x && i * h < box.width; ++i)
            for (const double e : cell_point_errors(f, box, d, i, std::uint32_t(j))) {
                error[j] = std::max(error[j], e);
                over[j] += e > kTargetError;
            }
    });
    for (std::uint64_t n : over) d.over += n;
    for (double e : error) d.error = std::max(d.error, e);
    return d;
}

}  // namespace

FieldStats FieldTable::stats() const {
    return {box_lo * quantum, box_hi * quantum, lipschitz, tabulation_error,
            std::uint64_t(nodes.size() + 5 * splits.size())};
}

void require_memory(const char* what, double expected, double bytes_per_sample) {
    const MemoryLimit limit = host_memory_limit();
    if (!(expected * bytes_per_sample <= double(limit.bytes)))
        throw Error(fmt::format("{} needs about {:.3g} samples and {:.0f} MiB, more than the {} ({:.0f} MiB)", what,
                                expected, expected * bytes_per_sample / (1 << 20), limit.what,
                                double(limit.bytes) / (1 << 20)));
}

FieldTable tabulate(const Sizing& s, const Box& box, unsigned threads) {
    const BlocksReleased released;  // the drafts' blocks, once the drafts are gone
    if (s.lipschitz != -1 && !(std::isfinite(s.lipschitz) && s.lipschitz >= 0))
        throw Error(fmt::format("the Lipschitz bound must be a finite number >= 0 (got {})", s.lipschitz));
    if (!(s.table_budget >= 1 && s.table_budget <= 1024))
        throw Error(fmt::format("the table budget must be 1 to 1024 words a sample (got {})", s.table_budget));
    const FieldSource f = field_source(s, box);
    const bool periodic = box.boundary == Boundary::Periodic;
    double lo = INFINITY, hi = 0;
    std::vector<double> xs(kSurvey + 1), ys(kSurvey + 1), vs(kSurvey + 1);
    for (std::uint32_t j = 0; j <= kSurvey; ++j) {
        for (std::uint32_t i = 0; i <= kSurvey; ++i) {
            xs[i] = box.width * i / kSurvey * (1 - 1e-12);
            ys[i] = box.height * j / kSurvey * (1 - 1e-12);
        }
        f(xs.data(), ys.data(), vs.data(), kSurvey + 1);
        for (std::uint32_t i = 0; i <= kSurvey; ++i) {
            const double v = checked_radius(vs[i], xs[i], ys[i]);
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    // The samples to expect, 0.70 per r^2 of area (as for one radius), refused past memory.
    double expected = 0;
    std::vector<double> centres(std::size_t(kSurvey) * kSurvey);  // r at the survey cells' centres
    for (std::uint32_t j = 0; j < kSurvey; ++j) {
        for (std::uint32_t i = 0; i < kSurvey; ++i) {
            xs[i] = box.width * (i + 0.5) / kSurvey;
            ys[i] = box.height * (j + 0.5) / kSurvey;
        }
        f(xs.data(), ys.data(), &centres[std::size_t(j) * kSurvey], kSurvey);
        for (std::uint32_t i = 0; i < kSurvey; ++i) {
            const double v = checked_radius(centres[std::size_t(j) * kSurvey + i], xs[i], ys[i]);
            expected += 0.70 * box.width * box.height / (kSurvey * kSurvey) / (v * v);
        }
    }
    // A budget past the default adds its words to each sample's bytes.
    require_memory("the field", expected, kFieldBytesPerSample + 4 * std::max(0.0, s.table_budget - 8));
    const double short_side = std::min(box.width, box.height);
    if (periodic && hi >= short_side / 2)
        throw Error(
            fmt::format("the field's largest radius {:.6g} is too large for a periodic box of {} x {}: it must "
                        "be < {} (half the shorter side)",
                        hi, box.width, box.height, short_side / 2));

    FieldTable t;
    std::uint64_t tx = 0, ty = 0;
    double tile = std::min(hi, std::max(box.width, box.height));
    if (periodic && !periodic_tiling(box.width, box.height, tile, 1, tx, ty))
        throw Error(
            fmt::format("periodic box {} x {}: width/height must be a ratio of small integers so that "
                        "square tiles fit it",
                        box.width, box.height));
    tile = lightest_tiles(box, tile, lo, tx, ty, centres, kSurvey);
    auto fits = [&](std::uint32_t a) {
        return (std::max(tx, ty) << (a + shared::MAX_FIELD_CELL_BITS)) <= kLatticeLimit &&
               ((tx * ty) << (2 * a)) <= kMaxTableNodes;
    };
    std::uint32_t a = 0;
    while (tile / double(1u << a) > 8 * lo && a < 30) ++a;
    if (!fits(a))
        throw Error(
            fmt::format("the field's radii ({:.6g} to {:.6g}) span more of the box than the 31-bit lattice and "
                        "the table's {} nodes hold",
                        lo, hi, kMaxTableNodes));
    Draft d;
    Doubles nodes;
    double samples = 0;
    ThreadPool pool(threads);
    for (;;) {
        d = draft(pool, f, box, std::uint32_t(tx << a), std::uint32_t(ty << a), tile / double(1u << a),
                  std::move(nodes));
        const double quantum = d.h / double(1u << shared::MAX_FIELD_CELL_BITS);
        const double least = *std::min_element(d.values.begin(), d.values.end());
        const bool fine = d.error <= kTargetError && least / quantum >= kMinLatticeRadius;
        // The table stays within a few nodes per expected sample (0.70 per r^2 of area).
        samples = 0;
        for (double v : d.values) samples += 0.70 * d.h * d.h / (v * v);
        const double next_nodes = double(tx << (a + 1)) * double(ty << (a + 1));
        const bool affordable = next_nodes <= std::max(kNodesPerSample * samples, double(kMinTableNodes));
        if (fine || !fits(a + 1) || (least / quantum >= kMinLatticeRadius && !affordable)) break;
        nodes = std::move(d.fine);
        ++a;
    }
    // Patches where the table strays from the source past the target (a kink), within their own
    // budget of table words; none under --lipschitz, whose field is the table's nodes themselves.
    // Where they cannot reach the target within it, the least target they reach, from the target up
    // by factors of sqrt(2).
    double error = d.error;
    std::vector<PatchDraft> patches;
    const double budget = std::max(s.table_budget * samples, double(kMinPatchWords));
    if (s.lipschitz < 0 && d.error > kTargetError) {
        const TableDraft view{d.values.data(), d.fine.data(), d.cells_x, d.cells_y, d.h};
        const std::vector<double> cell_error = cell_errors(pool, f, box, d);
        for (double target = kTargetError; patches.empty() && target < d.error; target *= std::sqrt(2.0))
            patches = draft_patches(pool, f, box, view, cell_error, target, std::uint64_t(budget), error);
    }
    Doubles().swap(d.fine);
    if (lo == hi && std::all_of(d.values.begin(), d.values.end(), [&](double v) { return v == lo; })) t.constant = lo;
    if (s.lipschitz >= 0) limit_lipschitz(d.values, d.cells_x, d.cells_y, d.h, s.lipschitz, periodic, threads);

    t.cell_bits = shared::MAX_FIELD_CELL_BITS;
    t.quantum = d.h / double(1u << t.cell_bits);
    t.tile_bits = a + t.cell_bits;
    t.tiles_x = std::uint32_t(tx);
    t.tiles_y = std::uint32_t(ty);
    t.cells_x = d.cells_x;
    t.cells_y = d.cells_y;
    t.lattice.periodic = periodic ? 1u : 0u;
    const std::uint64_t ex = tx << t.tile_bits, ey = ty << t.tile_bits;
    t.lattice.extent_x =
        periodic ? std::uint32_t(ex) : std::uint32_t(std::min<double>(std::ceil(box.width / t.quantum), double(ex)));
    t.lattice.extent_y =
        periodic ? std::uint32_t(ey) : std::uint32_t(std::min<double>(std::ceil(box.height / t.quantum), double(ey)));
    t.tabulation_error = error;
    // The largest node decides whether every node fits 32 bits (rounding is monotone).
    const double largest = *std::max_element(d.values.begin(), d.values.end());
    if (std::round(largest / t.quantum) >= 4294967295.0)
        throw Error(fmt::format("the field's radius {:.6g} is too large for the lattice of this box", largest));
    t.nodes.resize(d.values.size());
    pool.parallel_for(d.values.size(), [&](std::size_t begin, std::size_t end, unsigned) {
        for (std::size_t i = begin; i < end; ++i)
            t.nodes[i] = std::max<std::uint32_t>(1, std::uint32_t(std::round(d.values[i] / t.quantum)));
    });
    install_patches(t, patches, pool);
    // The drafts are many small blocks of the heap, freed before the bounds are made: their pages
    // stay with the heap, whose later small arrays reuse them without a page fault.
    std::vector<PatchDraft>().swap(patches);
    complete_bounds(t, pool);
    return t;
}

FieldTable scaled(const FieldTable& t, double scale, ThreadPool& pool) {
    // The largest node decides whether every scaled node fits 32 bits (rounding is monotone).
    if (std::round(double(t.r_hi) * scale) >= 4294967295.0)
        throw Error(fmt::format("the field's radius {:.6g} at {} times is too large for the lattice of this box",
                                double(t.r_hi) * t.quantum, scale));
    auto times = [&](std::uint32_t v) {
        return std::max<std::uint32_t>(1, std::uint32_t(std::round(double(v) * scale)));
    };
    FieldTable out = t;
    auto scale_nodes = [&](std::vector<std::uint32_t>& nodes) {
        pool.parallel_for(nodes.size(), [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t i = begin; i < end; ++i) nodes[i] = times(nodes[i]);
        });
    };
    scale_nodes(out.nodes);
    // A split's least and greatest node scale with it: `times` is non-decreasing.
    pool.parallel_for(out.splits.size(), [&](std::size_t begin, std::size_t end, unsigned) {
        for (std::size_t i = begin; i < end; ++i) {
            FieldTable::Split& s = out.splits[i];
            for (std::uint32_t& m : s.mid) m = times(m);
            s.lo = times(s.lo);
            s.hi = times(s.hi);
        }
    });
    out.constant = t.constant * scale;
    complete_bounds(out, pool);
    return out;
}

void limit_lipschitz(std::span<double> values, std::uint32_t cells_x, std::uint32_t cells_y, double h, double L,
                     bool periodic, unsigned threads) {
    // The distinct nodes (on a torus the last row and column repeat the first), and min pyramids
    // over blocks of 2^k x 2^k of them.
    const std::size_t nx = std::size_t(cells_x) + 1, ny = std::size_t(cells_y) + 1;
    const std::size_t w = periodic ? nx - 1 : nx, hgt = periodic ? ny - 1 : ny;
    std::vector<std::vector<double>> mins(1, std::vector<double>(w * hgt));
    std::vector<std::size_t> widths(1, w), heights(1, hgt);
    for (std::size_t j = 0; j < hgt; ++j)
        for (std::size_t i = 0; i < w; ++i) mins[0][j * w + i] = values[j * nx + i];
    while (widths.back() > 1 || heights.back() > 1) {
        const std::size_t pw = widths.back(), ph = heights.back(), cw = (pw + 1) / 2, ch = (ph + 1) / 2;
        std::vector<double> next(cw * ch, INFINITY);
        const std::vector<double>& prev = mins.back();
        for (std::size_t j = 0; j < ph; ++j)
            for (std::size_t i = 0; i < pw; ++i)
                next[j / 2 * cw + i / 2] = std::min(next[j / 2 * cw + i / 2], prev[j * pw + i]);
        mins.push_back(std::move(next));
        widths.push_back(cw);
        heights.push_back(ch);
    }
    // The nodes' gap to [lo, hi] along an axis of n distinct nodes: on a torus, the shorter way.
    auto gap = [&](std::size_t c, std::size_t lo, std::size_t hi, std::size_t n) -> double {
        if (c >= lo && c <= hi) return 0;
        const std::size_t before = c < lo ? lo - c : lo + n - c, after = c > hi ? c - hi : c + n - hi;
        if (!periodic) return double(c < lo ? before : after);
        return double(std::min(before, after));
    };
    const double slope = L * h;
    std::vector<double> out(w * hgt);
    ThreadPool pool(threads);
    for_rows(pool, hgt, [&](std::size_t j) {
        struct Block {
            std::size_t level, bx, by;
            double bound;  // its least node raised by L times its distance
        };
        auto block = [&](std::size_t i, std::size_t level, std::size_t bx, std::size_t by) {
            const std::size_t lo_x = bx << level, lo_y = by << level;
            const std::size_t hi_x = std::min(w, (bx + 1) << level) - 1, hi_y = std::min(hgt, (by + 1) << level) - 1;
            // Inner blocks' bounds only order and prune the search, with a margin far wider than
            // sqrt's rounding; a node's is its value, as the cone's formula gives it.
            const double gx = gap(i, lo_x, hi_x, w), gy = gap(j, lo_y, hi_y, hgt);
            return Block{level, bx, by,
                         mins[level][by * widths[level] + bx] +
                             slope * (level == 0 ? std::hypot(gx, gy) : std::sqrt(gx * gx + gy * gy))};
        };
        std::vector<Block> stack;
        for (std::size_t i = 0; i < w; ++i) {
            // Branch and bound, nearest bound first: a block whose bound is not below the best
            // so far holds no better node. Blocks within 1e-12 of it are not entered either:
            // along a cone's rays every node ties with the best, and the nodes' values are
            // rounded to lattice units far coarser than that.
            double best = mins[0][j * w + i];
            if (mins.size() > 1) stack.push_back(block(i, mins.size() - 1, 0, 0));  // else one node
            while (!stack.empty()) {
                const Block b = stack.back();
                stack.pop_back();
                if (b.bound >= best * (1 - 1e-12)) continue;
                Block kids[4];
                int n = 0;
                for (std::size_t c = 0; c < 4; ++c) {
                    const std::size_t cx = 2 * b.bx + (c & 1), cy = 2 * b.by + (c >> 1);
                    if (cx < widths[b.level - 1] && cy < heights[b.level - 1])
                        kids[n++] = block(i, b.level - 1, cx, cy);
                }
                if (b.level == 1) {  // the kids are nodes
                    for (int k = 0; k < n; ++k) best = std::min(best, kids[k].bound);
                    continue;
                }
                for (int k = 1; k < n; ++k)  // largest bound first, so the smallest is popped first
                    for (int m = k; m > 0 && kids[m - 1].bound < kids[m].bound; --m) std::swap(kids[m - 1], kids[m]);
                for (int k = 0; k < n; ++k)
                    if (kids[k].bound < best * (1 - 1e-12)) stack.push_back(kids[k]);
            }
            out[j * w + i] = best;
        }
    });
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) values[j * nx + i] = out[(j % hgt) * w + i % w];
}

}  // namespace vrpd::detail
