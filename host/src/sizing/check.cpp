// Judging a point set under a sizing field and rule (vrpd/sizing.h). Conflicts: each point scans
// the buckets within its own radius; since f <= max(r(x), r(y)) under every rule, each
// conflicting pair is found from its larger-radius side. Coverage: each sample marks the grid
// nodes it covers, within r(x) / (1 - L) of it, the farthest a node it covers can be when r is
// L-Lipschitz with L < 1 (else within the field's largest radius), one band of grid rows at a
// time on each thread, r read once per node.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "vrpd/sizing.h"
#include "../cpu/thread_pool.h"

namespace vrpd {
namespace {

constexpr double kMaxGridPoints = 16.0 * 1024 * 1024;  // coverage nodes, which bound the work
constexpr double kMaxBuckets = 4.0 * 1024 * 1024;

// The shortest way from a to b along one axis.
double gap(double a, double b, double extent, bool periodic) {
    const double d = std::abs(a - b);
    return periodic ? std::min(d, extent - d) : d;
}

// Coverage on a grid of nodes at cell centres: rep's resolution, grid_points, uncovered and worst
// node, for samples `pts` of radii `radius` (at rep.field's r_min, r_max and L).
void cover(const std::vector<glm::dvec2>& pts, const std::vector<double>& radius, const SizingFunction& r,
           SizingRule rule, const Box& box, double tolerance, unsigned threads, SizingReport& rep) {
    const bool periodic = box.boundary == Boundary::Periodic;
    // Bands of rows go to the threads: a band holds its nodes' radii and the least ratio d / f
    // found at each, and meets every sample whose reach crosses its rows; the bands' counts and
    // worst nodes are joined in row order.
    rep.resolution = std::max(rep.field.r_min / 4, std::sqrt(box.width * box.height / kMaxGridPoints));
    const double res = rep.resolution;
    const auto gx = std::int64_t(std::ceil(box.width / res)), gy = std::int64_t(std::ceil(box.height / res));
    rep.grid_points = std::uint64_t(gx * gy);
    auto centre = [&](std::int64_t i) { return (double(i) + 0.5) * res; };  // node i's coordinate
    const double L = rep.field.lipschitz * 1.01;
    auto reach_of = [&](std::size_t i) {
        return L < 1 ? radius[i] / (1 - L) + tolerance : rep.field.r_max + tolerance;
    };
    // The node indices [lo, hi] within `reach` of coordinate v along an axis of n nodes; on a
    // torus unwrapped, at most n of them (each node once) from lo in [0, n). Their runs
    // [first, last] inside [from, to]: one, or on a torus two (the second past the axis's end).
    auto span = [&](double v, double reach, std::int64_t n) {
        const std::int64_t lo = std::int64_t(std::floor((v - reach) / res - 0.5)),
                           hi = std::int64_t(std::ceil((v + reach) / res - 0.5));
        if (!periodic) return std::pair{lo, hi};
        const std::int64_t from = (lo % n + n) % n;
        return std::pair{from, from + std::min(hi - lo, n - 1)};
    };
    auto runs = [&](std::pair<std::int64_t, std::int64_t> s, std::int64_t n, std::int64_t from, std::int64_t to,
                    std::int64_t out[2][2]) {
        int count = 0;
        for (const std::int64_t shift : {std::int64_t(0), -n}) {
            if (shift != 0 && !periodic) break;
            const std::int64_t first = std::max(s.first + shift, from), last = std::min(s.second + shift, to);
            if (first <= last) out[count][0] = first, out[count][1] = last, ++count;
        }
        return count;
    };
    std::vector<std::pair<std::int64_t, std::int64_t>> rows(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) rows[i] = span(pts[i].y, reach_of(i), gy);
    const bool reads_node = rule != SizingRule::Prior;  // under prior f is the sample's own radius
    constexpr std::int64_t kBandRows = 64;
    const std::int64_t bands = (gy + kBandRows - 1) / kBandRows;
    struct Band {
        std::uint64_t uncovered = 0;
        double worst = 0;
        glm::dvec2 at{0, 0};
    };
    std::vector<Band> found(static_cast<std::size_t>(bands));
    detail::ThreadPool pool(threads);
    pool.parallel_for(
        std::size_t(bands),
        [&](std::size_t begin, std::size_t end, unsigned) {
            std::vector<float> best;
            std::vector<double> node_r;
            for (std::size_t band = begin; band < end; ++band) {
                const std::int64_t y0 = std::int64_t(band) * kBandRows, y1 = std::min(gy, y0 + kBandRows);
                const std::size_t cells = std::size_t((y1 - y0) * gx);
                best.assign(cells, std::numeric_limits<float>::infinity());
                if (reads_node) {
                    node_r.assign(cells, 0.0);
                    for (std::int64_t y = y0; y < y1; ++y)
                        for (std::int64_t x = 0; x < gx; ++x) {
                            const glm::dvec2 node{centre(x), centre(y)};
                            if (node.x < box.width && node.y < box.height)
                                node_r[std::size_t((y - y0) * gx + x)] = r(node);
                        }
                }
                for (std::size_t i = 0; i < pts.size(); ++i) {
                    std::int64_t ys[2][2], xs[2][2];
                    const int ny = runs(rows[i], gy, y0, y1 - 1, ys);
                    if (ny == 0) continue;
                    const double reach = reach_of(i);
                    const int nx = runs(span(pts[i].x, reach, gx), gx, 0, gx - 1, xs);
                    for (int a = 0; a < ny; ++a)
                        for (std::int64_t y = ys[a][0]; y <= ys[a][1]; ++y) {
                            const double node_y = centre(y);
                            if (node_y >= box.height) continue;
                            const double dy = gap(pts[i].y, node_y, box.height, periodic);
                            for (int b = 0; b < nx; ++b)
                                for (std::int64_t x = xs[b][0]; x <= xs[b][1]; ++x) {
                                    const double node_x = centre(x);
                                    if (node_x >= box.width) continue;
                                    const double dx = gap(pts[i].x, node_x, box.width, periodic);
                                    const double d = std::sqrt(dx * dx + dy * dy);
                                    if (d > reach) continue;
                                    const std::size_t k = std::size_t((y - y0) * gx + x);
                                    // The node is a point that came after every sample: f(r(sample), r(node)).
                                    const double f =
                                        rule_radius(rule, radius[i], reads_node ? node_r[k] : radius[i]) + tolerance;
                                    best[k] = std::min(best[k], float(d / f));
                                }
                        }
                }
                Band& out = found[band];
                for (std::int64_t y = y0; y < y1; ++y)
                    for (std::int64_t x = 0; x < gx; ++x) {
                        const glm::dvec2 node{centre(x), centre(y)};
                        if (node.x >= box.width || node.y >= box.height) continue;
                        const double b = best[std::size_t((y - y0) * gx + x)];
                        if (b >= 1) ++out.uncovered;
                        if (b > out.worst) out.worst = b, out.at = node;
                    }
            }
        },
        1);
    rep.worst_ratio = 0;
    for (const Band& b : found) {
        rep.uncovered += b.uncovered;
        if (b.worst > rep.worst_ratio) rep.worst_ratio = b.worst, rep.worst_point = b.at;
    }
}

}  // namespace

double rule_lipschitz_bound(SizingRule rule) {
    return rule == SizingRule::Prior || rule == SizingRule::Bigger ? 0.5 : 1.0;
}

FieldSummary summarize_field(const SizingFunction& r, const Box& box, std::size_t n) {
    FieldSummary f;
    f.nodes_per_side = n + 1;
    f.r_min = INFINITY;
    std::vector<double> row(n + 1), last(n + 1);
    for (std::size_t j = 0; j <= n; ++j) {
        const double y = box.height * double(j) / double(n);
        for (std::size_t i = 0; i <= n; ++i) {
            const double x = box.width * double(i) / double(n);
            const double v = r({x, y});
            if (!(std::isfinite(v) && v > 0))
                throw Error(fmt::format("sizing field: r({}, {}) = {}; it must be a finite number > 0 everywhere in "
                                        "the box",
                                        x, y, v));
            row[i] = v;
            f.r_min = std::min(f.r_min, v);
            f.r_max = std::max(f.r_max, v);
        }
        const double hx = box.width / double(n), hy = box.height / double(n), hd = std::hypot(hx, hy);
        for (std::size_t i = 0; i <= n; ++i) {
            if (i > 0) f.lipschitz = std::max(f.lipschitz, std::abs(row[i] - row[i - 1]) / hx);
            if (j == 0) continue;
            f.lipschitz = std::max(f.lipschitz, std::abs(row[i] - last[i]) / hy);
            if (i > 0) f.lipschitz = std::max(f.lipschitz, std::abs(row[i] - last[i - 1]) / hd);
            if (i < n) f.lipschitz = std::max(f.lipschitz, std::abs(row[i] - last[i + 1]) / hd);
        }
        std::swap(row, last);
    }
    return f;
}

SizingReport check_sizing(const std::vector<glm::dvec2>& pts, const SizingFunction& r, SizingRule rule, const Box& box,
                          double tolerance, const FieldSummary& field, unsigned threads) {
    SizingReport rep;
    rep.field = field;
    rep.points = pts.size();
    if (pts.empty()) throw Error("no points: an empty set covers nothing");
    const bool periodic = box.boundary == Boundary::Periodic;
    std::vector<double> radius(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const glm::dvec2 p = pts[i];
        if (!(p.x >= 0 && p.y >= 0 && p.x < box.width && p.y < box.height))
            throw Error(fmt::format("point {} ({}, {}) is outside the box [0,{}) x [0,{})", i + 1, p.x, p.y,
                                    box.width, box.height));
        radius[i] = r(p);
        if (!(std::isfinite(radius[i]) && radius[i] > 0))
            throw Error(fmt::format("sizing field: r = {} at point {}", radius[i], i + 1));
    }

    // Buckets of side at least the smallest radius, and few enough to hold.
    const double side = std::max(rep.field.r_min, std::sqrt(box.width * box.height / kMaxBuckets));
    const auto bx = std::int64_t(std::max(1.0, std::floor(box.width / side)));
    const auto by = std::int64_t(std::max(1.0, std::floor(box.height / side)));
    const double sx = box.width / double(bx), sy = box.height / double(by);
    auto cell = [&](glm::dvec2 p) {
        return std::pair{std::min(std::int64_t(p.x / sx), bx - 1), std::min(std::int64_t(p.y / sy), by - 1)};
    };
    std::vector<std::uint32_t> start(std::size_t(bx * by) + 1, 0), order(pts.size());
    for (const glm::dvec2& p : pts) {
        const auto [cx, cy] = cell(p);
        ++start[std::size_t(cy * bx + cx) + 1];
    }
    for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t i = 0; i < pts.size(); ++i) {
        const auto [cx, cy] = cell(pts[i]);
        order[fill[std::size_t(cy * bx + cx)]++] = i;
    }
    // Calls visit(j) for every point in the buckets within `reach` of p (each bucket once).
    auto near = [&](glm::dvec2 p, double reach, auto&& visit) {
        const auto [cx, cy] = cell(p);
        const std::int64_t rx = std::int64_t(std::ceil(reach / sx)), ry = std::int64_t(std::ceil(reach / sy));
        const std::int64_t x0 = periodic ? cx - std::min(rx, (bx - 1) / 2) : std::max<std::int64_t>(0, cx - rx);
        const std::int64_t x1 = periodic ? cx + std::min(rx, bx / 2) : std::min(bx - 1, cx + rx);
        const std::int64_t y0 = periodic ? cy - std::min(ry, (by - 1) / 2) : std::max<std::int64_t>(0, cy - ry);
        const std::int64_t y1 = periodic ? cy + std::min(ry, by / 2) : std::min(by - 1, cy + ry);
        for (std::int64_t y = y0; y <= y1; ++y)
            for (std::int64_t x = x0; x <= x1; ++x) {
                const std::size_t b = std::size_t(((y % by + by) % by) * bx + ((x % bx + bx) % bx));
                for (std::uint32_t k = start[b]; k < start[b + 1]; ++k) visit(order[k]);
            }
    };
    auto distance = [&](glm::dvec2 a, glm::dvec2 b) {
        return std::hypot(gap(a.x, b.x, box.width, periodic), gap(a.y, b.y, box.height, periodic));
    };

    for (std::size_t i = 0; i < pts.size(); ++i)
        near(pts[i], radius[i], [&](std::uint32_t j) {
            // Each pair once: from the side with the larger radius (ties: the earlier).
            if (j == i || radius[j] > radius[i] || (radius[j] == radius[i] && j < i)) return;
            const std::size_t a = std::min<std::size_t>(i, j), b = std::max<std::size_t>(i, j);
            const double f = rule_radius(rule, radius[a], radius[b]);
            if (distance(pts[i], pts[j]) < f - tolerance) {
                if (rep.conflicts++ == 0) {
                    rep.first_a = a + 1;
                    rep.first_b = b + 1;
                }
            }
        });

    cover(pts, radius, r, rule, box, tolerance, threads, rep);
    return rep;
}

}  // namespace vrpd
