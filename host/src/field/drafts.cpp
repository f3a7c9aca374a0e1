// The drafts of a sizing field's table (field/drafts.h): the source evaluated a row of points at
// a time on the pool's threads, each halving's nodes the last draft's halfway points, and the
// interpolant's error at every cell's centre and edge midpoints.
#include "drafts.h"

#include "patches.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vrpd::detail {
namespace {

// The coordinate of node i of n cells of side h along an axis: on a torus node n is node 0.
double node_coordinate(std::int64_t i, std::int64_t n, bool periodic, double h) {
    return double(periodic && i == n ? 0 : i) * h;
}

// The kinks that cross the cell whose lower left node is `at` in rows of `row` nodes: the bits in
// which the branch masks at its corners differ (0: the source takes one branch at all four).
std::uint8_t crossing(const Bytes& mask, std::size_t at, std::size_t row) {
    const std::uint8_t m0 = mask[at];
    return std::uint8_t((mask[at + 1] ^ m0) | (mask[at + row] ^ m0) | (mask[at + row + 1] ^ m0));
}
// Whether more than one bit of a crossing is set: more than one kink.
bool several(std::uint8_t kinks) { return (kinks & (kinks - 1)) != 0; }

// Fills entries first, first + step, ... of row j of the nodes of n_x x n_y cells of side h. On a
// torus the last row and column are the first: the field wraps. Inside the box a node is the
// source there, checked; past a free box's edge, the source there if it is a radius, else its
// value at the edge. With branches g, `mask` (as `row`) gets the branch the source takes; a node
// that takes the source at the edge takes none (mask 0, its value on every branch).
void fill_nodes(const FieldSource& f, const FieldBranches& g, const Box& box, bool periodic, std::uint32_t n_x,
                std::uint32_t n_y, double h, std::size_t j, std::uint32_t first, std::uint32_t step, double* row,
                std::uint8_t* mask) {
    const double y = node_coordinate(std::int64_t(j), n_y, periodic, h);
    std::vector<double> xs, ys, vs;
    std::vector<std::uint8_t> takes;
    for (std::uint32_t i = first; i <= n_x; i += step) xs.push_back(node_coordinate(i, n_x, periodic, h));
    ys.assign(xs.size(), y);
    vs.resize(xs.size());
    if (g) {
        takes.resize(xs.size());
        g.taken(xs.data(), ys.data(), vs.data(), takes.data(), xs.size());
    } else {
        f(xs.data(), ys.data(), vs.data(), xs.size());
    }
    for (std::size_t k = 0; k < xs.size(); ++k) {
        const double node = node_value(f, box, xs[k], y, vs[k]);
        row[first + k * step] = node;
        if (g) mask[first + k * step] = node == vs[k] ? takes[k] : 0;
    }
}

// Sets `other` at the nodes of a draft's cells that a kink crosses (the source's branch masks
// differ at their corners): the source with that kink's branch flipped, or the node's own value
// where it takes the source at a free box's edge (fill_nodes); NaN, which cell_model takes for a
// broken cell, where the cells around the node are crossed by more than one kink. By rows of
// nodes on the pool's threads.
void fill_others(ThreadPool& pool, const FieldBranches& g, bool periodic, std::uint32_t cells_x, std::uint32_t cells_y,
                 double h, const Doubles& values, const Bytes& mask, Doubles& other) {
    const std::size_t row = std::size_t(cells_x) + 1;
    auto crossed = [&](std::int64_t i, std::int64_t j) -> std::uint8_t {
        if (i < 0 || j < 0 || i >= std::int64_t(cells_x) || j >= std::int64_t(cells_y)) return 0;
        return crossing(mask, std::size_t(j) * row + std::size_t(i), row);
    };
    for_rows(pool, std::size_t(cells_y) + 1, [&](std::size_t jj) {
        const std::int64_t j = std::int64_t(jj);
        std::vector<std::size_t> at;
        std::vector<double> xs, ys;
        std::vector<std::uint8_t> own, flipped;
        for (std::int64_t i = 0; i <= std::int64_t(cells_x); ++i) {
            const std::uint8_t around[4] = {crossed(i - 1, j - 1), crossed(i, j - 1), crossed(i - 1, j), crossed(i, j)};
            std::uint8_t kink = 0;  // the one kink crossing the cells around, or 0xff for more
            for (const std::uint8_t c : around)
                if (c != 0) kink = several(c) || (kink != 0 && kink != c) ? 0xff : c;
            if (kink == 0) continue;
            const std::size_t node = jj * row + std::size_t(i);
            if (kink == 0xff) {
                other[node] = NAN;
                continue;
            }
            at.push_back(node);
            xs.push_back(node_coordinate(i, cells_x, periodic, h));
            ys.push_back(node_coordinate(j, cells_y, periodic, h));
            own.push_back(mask[node]);
            flipped.push_back(std::uint8_t(mask[node] ^ kink));
        }
        if (at.empty()) return;
        std::vector<double> vs(at.size()), os(at.size());
        g.forced(xs.data(), ys.data(), vs.data(), own.data(), at.size());
        g.forced(xs.data(), ys.data(), os.data(), flipped.data(), at.size());
        for (std::size_t k = 0; k < at.size(); ++k) other[at[k]] = values[at[k]] == vs[k] ? os[k] : values[at[k]];
    });
}

// The bilinear interpolant of a cell with nodes n[0], n[1] (row 0) and n[row], n[row + 1] at a
// halfway point (tx, ty): (0.5, 0.5), (0.5, 0) or (0, 0.5). There it is the mean of the four
// nodes around the point (the centre) or of the two beside it (an edge's midpoint).
[[gnu::always_inline]] inline double midpoint_mean(const double* n, std::size_t row, double tx, double ty) {
    return ty == 0   ? (n[0] + n[1]) * 0.5
           : tx == 0 ? (n[0] + n[row]) * 0.5
                     : ((n[0] + n[1]) + (n[row] + n[row + 1])) * 0.25;
}
// The same for a cell as cell_model takes it: a kinked cell joins its branches' means.
[[gnu::always_inline]] inline double model_mean(const CellModel& m, const double* n, std::size_t row, double tx,
                                                double ty) {
    if (m.join != kMin && m.join != kMax) return midpoint_mean(n, row, tx, ty);
    const double a = midpoint_mean(m.a, 2, tx, ty), b = midpoint_mean(m.b, 2, tx, ty);
    return m.join == kMin ? std::min(a, b) : std::max(a, b);
}
// The interpolant of a cell as cell_model takes it at (tx, ty), in cell sides.
inline double model_at(const CellModel& m, const double* n, std::size_t row, double tx, double ty) {
    auto bilinear = [&](double v00, double v10, double v01, double v11) {
        return (v00 * (1 - tx) + v10 * tx) * (1 - ty) + (v01 * (1 - tx) + v11 * tx) * ty;
    };
    if (m.join != kMin && m.join != kMax) return bilinear(n[0], n[1], n[row], n[row + 1]);
    const double a = bilinear(m.a[0], m.a[1], m.a[2], m.a[3]), b = bilinear(m.b[0], m.b[1], m.b[2], m.b[3]);
    return m.join == kMin ? std::min(a, b) : std::max(a, b);
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
        const double mean = model_mean(cell_model(d, i, j), n, row, tx, ty);
        return std::abs(mean - v) / v;
    }
    const double x = std::min(fx, box.width), y = std::min(fy, box.height);
    const double v = source_at(f, x, y);
    const double at = model_at(cell_model(d, i, j), n, row, x / d.h - i, y / d.h - double(j));
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
    const CellModel m = cell_model(d, i, j);
    const double centre = model_mean(m, n, row, 0.5, 0.5), bottom = model_mean(m, n, row, 0.5, 0),
                 left = model_mean(m, n, row, 0, 0.5);
    return {std::abs(centre - mid[1]) / mid[1], std::abs(bottom - low[1]) / low[1], std::abs(left - mid[0]) / mid[0]};
}

}  // namespace

CellModel cell_model(const Draft& d, std::uint32_t i, std::uint32_t j) {
    CellModel m;
    if (d.mask.empty()) return m;
    const std::size_t row = std::size_t(d.cells_x) + 1, at = std::size_t(j) * row + i;
    const std::size_t corner[4] = {at, at + 1, at + row, at + row + 1};
    const std::uint8_t kink = crossing(d.mask, at, row);
    if (kink == 0) return m;
    if (several(kink)) {
        m.join = kBroken;
        return m;
    }
    bool least = true, greatest = true;
    for (int c = 0; c < 4; ++c) {
        const double v = d.values[corner[c]], o = d.other[corner[c]];
        if (!(std::isfinite(o) && o > 0)) {
            m.join = kBroken;
            return m;
        }
        least = least && v <= o;
        greatest = greatest && v >= o;
        const bool second = (d.mask[corner[c]] & kink) != 0;
        m.a[c] = second ? o : v;
        m.b[c] = second ? v : o;
    }
    m.join = least ? kMin : greatest ? kMax : kBroken;
    return m;
}

void for_rows(ThreadPool& pool, std::size_t n, const std::function<void(std::size_t)>& row) {
    constexpr std::size_t kRowGrain = 2;
    each_reporting(pool, n, kRowGrain, row);
}

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

Draft draft(ThreadPool& pool, const FieldSource& f, const FieldBranches& g, const Box& box, std::uint32_t cells_x,
            std::uint32_t cells_y, double h, Draft last) {
    Draft d;
    d.cells_x = cells_x;
    d.cells_y = cells_y;
    d.h = h;
    d.values = std::move(last.fine);
    d.mask = std::move(last.mask_fine);
    const bool periodic = box.boundary == Boundary::Periodic;
    const std::size_t row = std::size_t(cells_x) + 1;
    if (d.values.empty()) {
        d.values.resize(row * (std::size_t(cells_y) + 1));
        if (g) d.mask.resize(d.values.size());
        for_rows(pool, std::size_t(cells_y) + 1, [&](std::size_t j) {
            fill_nodes(f, g, box, periodic, cells_x, cells_y, h, j, 0, 1, &d.values[j * row],
                       g ? &d.mask[j * row] : nullptr);
        });
    }
    if (g) {
        d.other.resize(d.values.size());
        fill_others(pool, g, periodic, cells_x, cells_y, h, d.values, d.mask, d.other);
    }
    // The halfway points: the nodes' rows with every other entry new, and the rows between them.
    const std::size_t fine_row = 2 * row - 1;
    d.fine.resize(fine_row * (2 * std::size_t(cells_y) + 1));
    if (g) d.mask_fine.resize(d.fine.size());
    for_rows(pool, 2 * std::size_t(cells_y) + 1, [&](std::size_t j) {
        double* out = &d.fine[j * fine_row];
        std::uint8_t* mask = g ? &d.mask_fine[j * fine_row] : nullptr;
        const bool even = j % 2 == 0;
        if (even)
            for (std::size_t i = 0; i < row; ++i) {
                out[2 * i] = d.values[j / 2 * row + i];
                if (g) mask[2 * i] = d.mask[j / 2 * row + i];
            }
        fill_nodes(f, g, box, periodic, 2 * cells_x, 2 * cells_y, h / 2, j, even ? 1 : 0, even ? 2 : 1, out, mask);
    });
    std::vector<double> error(cells_y, 0.0);  // per row, so that threads never share one
    std::vector<std::uint64_t> over(cells_y, 0);
    std::vector<std::uint8_t> broken(cells_y, 0);
    for_rows(pool, cells_y, [&](std::size_t j) {
        if (g)
            for (std::uint32_t i = 0; i < cells_x; ++i) broken[j] |= cell_model(d, i, std::uint32_t(j)).join == kBroken;
        if (double(j) * h >= box.height) return;
        for (std::uint32_t i = 0; i < cells_x && i * h < box.width; ++i)
            for (const double e : cell_point_errors(f, box, d, i, std::uint32_t(j))) {
                error[j] = std::max(error[j], e);
                over[j] += e > kTargetError;
            }
    });
    for (std::uint64_t n : over) d.over += n;
    for (double e : error) d.error = std::max(d.error, e);
    d.broken = std::find(broken.begin(), broken.end(), 1) != broken.end();
    return d;
}

}  // namespace vrpd::detail
