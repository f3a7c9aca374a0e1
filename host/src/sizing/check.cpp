// Judging a point set under a sizing field and rule (vrpd/sizing.h). Conflicts: each point scans
// the buckets within its own radius; since f <= max(r(x), r(y)) under every rule, each
// conflicting pair is found from its larger-radius side. Coverage: each sample marks the grid
// nodes it covers, within r(x) / (1 - L) of it, the farthest a node it covers can be when r is
// L-Lipschitz with L < 1 (else within the field's largest radius).
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "vrpd/sizing.h"

namespace vrpd {
namespace {

constexpr double kMaxGridPoints = 16.0 * 1024 * 1024;  // coverage nodes, so memory stays near 64 MiB
constexpr double kMaxBuckets = 4.0 * 1024 * 1024;

// The shortest way from a to b along one axis.
double gap(double a, double b, double extent, bool periodic) {
    const double d = std::abs(a - b);
    return periodic ? std::min(d, extent - d) : d;
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

SizingReport check_sizing(const std::vector<glm::dvec2>& pts, const SizingFunction& r, SizingRule rule,
                          const Box& box, double tolerance, const FieldSummary& field) {
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

    // Coverage on a grid of nodes at cell centres.
    rep.resolution = std::max(rep.field.r_min / 4, std::sqrt(box.width * box.height / kMaxGridPoints));
    const auto gx = std::size_t(std::ceil(box.width / rep.resolution)),
               gy = std::size_t(std::ceil(box.height / rep.resolution));
    rep.grid_points = gx * gy;
    std::vector<float> best(rep.grid_points, std::numeric_limits<float>::infinity());
    const double L = rep.field.lipschitz * 1.01;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const double reach = L < 1 ? radius[i] / (1 - L) + tolerance : rep.field.r_max + tolerance;
        const auto lo_x = std::int64_t(std::floor((pts[i].x - reach) / rep.resolution - 0.5)),
                   hi_x = std::int64_t(std::ceil((pts[i].x + reach) / rep.resolution - 0.5));
        const auto lo_y = std::int64_t(std::floor((pts[i].y - reach) / rep.resolution - 0.5)),
                   hi_y = std::int64_t(std::ceil((pts[i].y + reach) / rep.resolution - 0.5));
        for (std::int64_t y = lo_y; y <= hi_y; ++y)
            for (std::int64_t x = lo_x; x <= hi_x; ++x) {
                std::int64_t ux = x, uy = y;
                if (periodic) {
                    ux = (x % std::int64_t(gx) + std::int64_t(gx)) % std::int64_t(gx);
                    uy = (y % std::int64_t(gy) + std::int64_t(gy)) % std::int64_t(gy);
                } else if (x < 0 || y < 0 || x >= std::int64_t(gx) || y >= std::int64_t(gy)) {
                    continue;
                }
                const glm::dvec2 node{(double(ux) + 0.5) * rep.resolution, (double(uy) + 0.5) * rep.resolution};
                if (node.x >= box.width || node.y >= box.height) continue;
                const double d = distance(pts[i], node);
                if (d > reach) continue;
                // The node is a point that came after every sample: f(r(sample), r(node)).
                const double f = rule_radius(rule, radius[i], r(node)) + tolerance;
                float& b = best[std::size_t(uy) * gx + std::size_t(ux)];
                b = std::min(b, float(d / f));
            }
    }
    rep.worst_ratio = 0;
    for (std::size_t y = 0; y < gy; ++y)
        for (std::size_t x = 0; x < gx; ++x) {
            const glm::dvec2 node{(double(x) + 0.5) * rep.resolution, (double(y) + 0.5) * rep.resolution};
            if (node.x >= box.width || node.y >= box.height) continue;
            const double b = best[y * gx + x];
            if (b >= 1) ++rep.uncovered;
            if (b > rep.worst_ratio) {
                rep.worst_ratio = b;
                rep.worst_point = node;
            }
        }
    return rep;
}

}  // namespace vrpd
