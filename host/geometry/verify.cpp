// verify(): conflicts by a bucket grid, maximality by the largest empty circle of the Delaunay
// triangulation (CGAL, exact predicates), quality from the same triangles. A periodic box is
// handled by adding the images of points near its sides; triangles are then taken once each,
// as the image whose circumcentre lies in the box.
#include "vrpd/verify.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <fmt/format.h>

namespace vrpd {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb>;
using Delaunay = CGAL::Delaunay_triangulation_2<K, Tds>;
using P2 = K::Point_2;

void validate_input(const std::vector<glm::dvec2>& pts, Radii radii, const Box& box) {
    if (!(std::isfinite(radii.inhibition) && radii.inhibition > 0 && std::isfinite(radii.coverage) &&
          radii.coverage >= radii.inhibition))
        throw Error(
            fmt::format("radii must satisfy 0 < Rf <= Rc (got Rf = {}, Rc = {})", radii.inhibition, radii.coverage));
    if (!(radii.tolerance >= 0 && radii.tolerance < radii.inhibition))
        throw Error(fmt::format("the tolerance must satisfy 0 <= tolerance < Rf (got {})", radii.tolerance));
    if (!(std::isfinite(box.width) && box.width > 0 && std::isfinite(box.height) && box.height > 0))
        throw Error("extent must be two finite numbers > 0");
    for (const auto& [name, v] : {std::pair{"width", box.width}, {"height", box.height}, {"Rf", radii.inhibition},
                                  {"Rc", radii.coverage}})
        if (!(v >= kSmallestLength && v <= kLargestLength))
            throw Error(fmt::format("{} {} is outside the lengths vrpd judges, {} to {}", name, v, kSmallestLength,
                                    kLargestLength));
    if (pts.empty()) throw Error("no points: an empty set covers nothing");
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const glm::dvec2 p = pts[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw Error(fmt::format("point {} is not finite", i + 1));
        if (p.x < 0 || p.y < 0 || p.x >= box.width || p.y >= box.height)
            throw Error(fmt::format("point {} ({}, {}) is outside the box [0,{}) x [0,{})", i + 1, p.x, p.y, box.width,
                                    box.height));
    }
    std::vector<std::uint32_t> order(pts.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](auto a, auto b) { return std::tie(pts[a].x, pts[a].y) < std::tie(pts[b].x, pts[b].y); });
    for (std::size_t i = 1; i < order.size(); ++i)
        if (pts[order[i]] == pts[order[i - 1]])
            throw Error(fmt::format("points {} and {} are the same point ({}, {})",
                                    std::min(order[i], order[i - 1]) + 1, std::max(order[i], order[i - 1]) + 1,
                                    pts[order[i]].x, pts[order[i]].y));
}

double axis_gap(double a, double b, double extent, bool periodic) {
    double d = std::abs(a - b);
    return periodic ? std::min(d, extent - d) : d;
}

// Pairs closer than Rf, by buckets of side >= Rf (exact: every such pair is in adjacent buckets).
// Only occupied buckets exist: the points sorted by bucket, so memory is linear in the points
// whatever the radius.
std::uint64_t count_conflicts(const std::vector<glm::dvec2>& pts, double rf, const Box& box) {
    const bool periodic = box.boundary == Boundary::Periodic;
    // Buckets per side, clamped as doubles first (a huge ratio does not fit an integer).
    auto buckets = [&](double extent) { return std::int64_t(std::clamp(std::floor(extent / rf), 1.0, 1e9)); };
    const std::int64_t nx = buckets(box.width), ny = buckets(box.height);
    auto cell_of = [&](glm::dvec2 p) {
        return std::pair{std::clamp(std::int64_t(p.x / box.width * double(nx)), std::int64_t(0), nx - 1),
                         std::clamp(std::int64_t(p.y / box.height * double(ny)), std::int64_t(0), ny - 1)};
    };
    std::vector<std::pair<std::int64_t, std::uint32_t>> by_bucket(pts.size());
    for (std::uint32_t i = 0; i < pts.size(); ++i) {
        auto [cx, cy] = cell_of(pts[i]);
        by_bucket[i] = {cy * nx + cx, i};
    }
    std::sort(by_bucket.begin(), by_bucket.end());
    // A neighbourhood's buckets as runs of consecutive ids within a row: columns cx - 1 to
    // cx + 1, split where they wrap on a torus (every column once where there are fewer than 3),
    // and likewise the rows.
    auto axis_runs = [&](std::int64_t c, std::int64_t n, std::int64_t out[2][2]) {
        if (periodic && n < 3) {
            out[0][0] = 0, out[0][1] = n - 1;
            return 1;
        }
        const std::int64_t lo = c - 1, hi = c + 1;
        if (!periodic) {
            out[0][0] = std::max<std::int64_t>(lo, 0), out[0][1] = std::min(hi, n - 1);
            return 1;
        }
        if (lo < 0) {
            out[0][0] = 0, out[0][1] = hi, out[1][0] = lo + n, out[1][1] = n - 1;
            return 2;
        }
        if (hi >= n) {
            out[0][0] = lo, out[0][1] = n - 1, out[1][0] = 0, out[1][1] = hi - n;
            return 2;
        }
        out[0][0] = lo, out[0][1] = hi;
        return 1;
    };
    std::uint64_t conflicts = 0;
    const double rf2 = rf * rf;
    // Points in bucket order: a bucket's points search the same runs, near in memory.
    for (const auto& [id, i] : by_bucket) {
        const std::int64_t cx = id % nx, cy = id / nx;
        std::int64_t xs[2][2], ys[2][2];
        const int nxr = axis_runs(cx, nx, xs), nyr = axis_runs(cy, ny, ys);
        for (int a = 0; a < nyr; ++a)
            for (std::int64_t y = ys[a][0]; y <= ys[a][1]; ++y)
                for (int b = 0; b < nxr; ++b) {
                    const std::int64_t last = y * nx + xs[b][1];
                    auto it = std::lower_bound(by_bucket.begin(), by_bucket.end(),
                                               std::pair{y * nx + xs[b][0], std::uint32_t(0)});
                    for (; it != by_bucket.end() && it->first <= last; ++it) {
                        const std::uint32_t j = it->second;
                        if (j <= i) continue;
                        const double gx = axis_gap(pts[i].x, pts[j].x, box.width, periodic);
                        const double gy = axis_gap(pts[i].y, pts[j].y, box.height, periodic);
                        if (gx * gx + gy * gy < rf2) ++conflicts;
                    }
                }
    }
    return conflicts;
}

bool inside(const P2& c, const Box& box) { return c.x() >= 0 && c.y() >= 0 && c.x() < box.width && c.y() < box.height; }

// The points and, on a torus, their images within `margin` of the box.
Delaunay triangulate(const std::vector<glm::dvec2>& pts, const Box& box, double margin) {
    std::vector<std::pair<P2, std::uint32_t>> all;
    all.reserve(pts.size() + pts.size() / 8);
    for (std::uint32_t i = 0; i < pts.size(); ++i) {
        for (int sy = -1; sy <= 1; ++sy) {
            for (int sx = -1; sx <= 1; ++sx) {
                if ((sx || sy) && box.boundary != Boundary::Periodic) continue;
                const double x = pts[i].x + sx * box.width, y = pts[i].y + sy * box.height;
                if (x < -margin || y < -margin || x > box.width + margin || y > box.height + margin) continue;
                all.emplace_back(P2(x, y), i);
            }
        }
    }
    // Points all on one line make a one-dimensional triangulation, where CGAL locates a point by
    // walking every edge (quadratic in all); inserted in order along the line, each new point lies
    // beyond an end of the hull, which is found at once.
    const auto distinct = std::find_if(all.begin(), all.end(), [&](const auto& v) { return v.first != all[0].first; });
    const bool on_one_line =
        distinct == all.end() || std::all_of(all.begin(), all.end(), [&](const auto& v) {
            return CGAL::orientation(all[0].first, distinct->first, v.first) == CGAL::COLLINEAR;
        });
    if (!on_one_line) return Delaunay(all.begin(), all.end());
    std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    Delaunay dt;
    for (const auto& [p, i] : all) dt.insert(p)->info() = i;
    return dt;
}

double angle_at(const P2& a, const P2& b, const P2& c) {
    const double ux = b.x() - a.x(), uy = b.y() - a.y(), vx = c.x() - a.x(), vy = c.y() - a.y();
    return std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180.0 / std::numbers::pi;
}

void add(Histogram& h, double v) {
    const double bin = std::min(std::max(0.0, v) / h.bin_width, double(h.bins - 1));
    if (h.counts.empty()) h.counts.assign(h.bins, 0);
    ++h.counts[std::size_t(bin)];
}

// The largest circle centred on the box's sides or corners that is empty (free boundary): on a
// Voronoi edge crossing a side, or at a corner.
void boundary_circles(const Delaunay& dt, const Box& box, Report& r) {
    auto consider = [&](const P2& c, const P2& site) {
        const double rad = std::sqrt(CGAL::squared_distance(c, site));
        if (rad > r.largest_empty_radius) {
            r.largest_empty_radius = rad;
            r.largest_empty_centre = {c.x(), c.y()};
        }
    };
    for (double x : {0.0, box.width})
        for (double y : {0.0, box.height}) {
            const P2 corner(std::min(x, std::nextafter(box.width, 0.0)), std::min(y, std::nextafter(box.height, 0.0)));
            consider(corner, dt.nearest_vertex(corner)->point());
        }
    for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
        const P2& site = e->first->vertex(Delaunay::cw(e->second))->point();
        CGAL::Object dual = dt.dual(*e);
        P2 origin;
        K::Vector_2 dir;
        double t_lo = -INFINITY, t_hi = INFINITY;
        if (const K::Segment_2* s = CGAL::object_cast<K::Segment_2>(&dual)) {
            origin = s->source();
            dir = s->to_vector();
            t_lo = 0;
            t_hi = 1;
        } else if (const K::Ray_2* ray = CGAL::object_cast<K::Ray_2>(&dual)) {
            origin = ray->source();
            dir = ray->to_vector();
            t_lo = 0;
        } else if (const K::Line_2* line = CGAL::object_cast<K::Line_2>(&dual)) {
            origin = line->point();
            dir = line->to_vector();
        } else {
            continue;
        }
        for (int axis = 0; axis < 2; ++axis) {
            const double o = axis == 0 ? origin.x() : origin.y();
            const double d = axis == 0 ? dir.x() : dir.y();
            if (d == 0) continue;
            for (double side : {0.0, axis == 0 ? box.width : box.height}) {
                const double t = (side - o) / d;
                if (t < t_lo || t > t_hi) continue;
                const double other = axis == 0 ? origin.y() + t * dir.y() : origin.x() + t * dir.x();
                const double other_max = axis == 0 ? box.height : box.width;
                if (other < 0 || other > other_max) continue;
                consider(axis == 0 ? P2(side, other) : P2(other, side), site);
            }
        }
    }
}

}  // namespace

Report verify(const std::vector<glm::dvec2>& pts, Radii radii, const Box& box) {
    validate_input(pts, radii, box);
    const bool periodic = box.boundary == Boundary::Periodic;
    Report r;
    r.points = pts.size();
    r.density = double(pts.size()) * radii.inhibition * radii.inhibition / (box.width * box.height);
    r.conflicts = count_conflicts(pts, radii.inhibition - radii.tolerance, box);

    // A margin of 3 Rc holds every empty circle of radius < 1.5 Rc whose centre is in the box;
    // if a larger one shows up (a far from maximal set), triangulate again with all 8 images.
    // So do images that leave the triangulation without a triangle (fewer than 3 points, or on
    // one line): all 8 images of a point span the plane.
    const double whole = std::max(box.width, box.height);
    double margin = periodic ? std::min(3.0 * radii.coverage, whole) : 0.0;
    Delaunay dt = triangulate(pts, box, margin);
    for (;;) {
        if (periodic && dt.dimension() < 2 && margin < whole) {
            margin = whole;
            dt = triangulate(pts, box, margin);
            continue;
        }
        r.largest_empty_radius = 0;
        r.triangles = 0;
        for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
            const P2 c = dt.circumcenter(f);
            if (!inside(c, box)) continue;
            const double rad = std::sqrt(CGAL::squared_distance(c, f->vertex(0)->point()));
            if (rad > r.largest_empty_radius) {
                r.largest_empty_radius = rad;
                r.largest_empty_centre = {c.x(), c.y()};
            }
        }
        if (!periodic || r.largest_empty_radius * 2 < margin || margin >= whole) break;
        margin = whole;
        dt = triangulate(pts, box, margin);
    }
    if (!periodic) boundary_circles(dt, box, r);
    r.maximal = r.largest_empty_radius < radii.coverage + radii.tolerance;

    r.min_distance = INFINITY;
    for (auto e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
        const auto a = e->first->vertex(Delaunay::cw(e->second)), b = e->first->vertex(Delaunay::ccw(e->second));
        if (a->info() == b->info()) continue;
        // hypot: two points closer than 1e-154 have a squared distance that underflows.
        const P2 &p = a->point(), &q = b->point();
        r.min_distance = std::min(r.min_distance, std::hypot(p.x() - q.x(), p.y() - q.y()));
    }
    r.min_angle_degrees = 180;
    r.min_edge = INFINITY;
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
        if (!inside(dt.circumcenter(f), box)) continue;
        ++r.triangles;
        for (int i = 0; i < 3; ++i) {
            const P2& a = f->vertex(i)->point();
            const P2& b = f->vertex((i + 1) % 3)->point();
            const P2& c = f->vertex((i + 2) % 3)->point();
            const double angle = angle_at(a, b, c);
            r.min_angle_degrees = std::min(r.min_angle_degrees, angle);
            r.max_angle_degrees = std::max(r.max_angle_degrees, angle);
            add(r.angles, angle);
            // An interior edge bounds two triangles and is counted once for each.
            const double len = std::sqrt(CGAL::squared_distance(a, b));
            r.min_edge = std::min(r.min_edge, len);
            r.max_edge = std::max(r.max_edge, len);
            add(r.edges, len / radii.inhibition);
        }
    }
    // A free box may have no triangle to count: fewer than 3 points, points on one line, or
    // no circumcentre in the box. Its Voronoi edges and the corners (boundary_circles) still
    // hold the largest empty circle; the quality figures are then 0.
    if (r.triangles == 0) r.min_angle_degrees = r.min_edge = 0;
    return r;
}

SizingQuality sizing_quality(const std::vector<glm::dvec2>& pts, const std::vector<double>& radius,
                             const Box& box) {
    if (pts.size() != radius.size()) throw Error("sizing_quality: one radius per point");
    const double r_max = radius.empty() ? 0 : *std::max_element(radius.begin(), radius.end());
    const bool periodic = box.boundary == Boundary::Periodic;
    const Delaunay dt = triangulate(pts, box, periodic ? std::min(3 * r_max, std::max(box.width, box.height)) : 0.0);
    SizingQuality q;
    q.edge_min = INFINITY;
    q.sin_min = 1;
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
        if (!inside(dt.circumcenter(f), box)) continue;
        ++q.triangles;
        for (int i = 0; i < 3; ++i) {
            const auto va = f->vertex(i), vb = f->vertex((i + 1) % 3), vc = f->vertex((i + 2) % 3);
            const double angle = angle_at(va->point(), vb->point(), vc->point());
            q.sin_min = std::min(q.sin_min, std::sin(angle * std::numbers::pi / 180.0));
            add(q.angles, angle);
            const double len = std::sqrt(CGAL::squared_distance(va->point(), vb->point()));
            for (const double r : {radius[va->info()], radius[vb->info()]}) {
                q.edge_min = std::min(q.edge_min, len / r);
                q.edge_max = std::max(q.edge_max, len / r);
            }
        }
    }
    if (q.triangles == 0) q.edge_min = q.sin_min = 0;
    return q;
}

}  // namespace vrpd
