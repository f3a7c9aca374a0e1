// The continuous hierarchy (vrpd/continuous.h): a priority queue of the Delaunay triangles by
// circumradius over a triangulation of the samples and their periodic images near the box, the
// largest popped, its circumcentre's sample inserted (located from that triangle), the new
// triangles pushed. Triangles are queued once, as the image whose circumcentre lies in the box;
// a popped triangle that insertions have destroyed is skipped.
#include "vrpd/continuous.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <queue>
#include <random>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <fmt/format.h>

namespace vrpd {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Delaunay = CGAL::Delaunay_triangulation_2<K>;
using P2 = K::Point_2;
using Vertex = Delaunay::Vertex_handle;
using Face = Delaunay::Face_handle;

struct Queued {
    double r2;  // squared circumradius
    Face face;
    Vertex v[3];
    bool operator<(const Queued& o) const { return r2 < o.r2; }
};

class Events {
public:
    // `buckets` per side of a grid over the box and its margin, each remembering a vertex in it,
    // from which an image's insertion starts its walk.
    // Triangles whose circumradius is at most `last` are not queued: the run ends before them.
    Events(const Box& box, double margin, std::size_t buckets, double last)
        : box_(box), margin_(margin), last2_(last * last), side_(buckets), near_(buckets * buckets) {}

    // Inserts p (in the box) and its images within the margin, each located from a vertex near
    // it (p itself from `hint`); queues the triangles made.
    void insert(P2 p, Face hint) {
        for (int sy = -1; sy <= 1; ++sy)
            for (int sx = -1; sx <= 1; ++sx) {
                const double x = p.x() + sx * box_.width, y = p.y() + sy * box_.height;
                if (x < -margin_ || y < -margin_ || x > box_.width + margin_ || y > box_.height + margin_) continue;
                Vertex& near = near_[bucket(x, y)];
                if ((sx != 0 || sy != 0 || hint == Face()) && near != Vertex()) hint = near->face();
                const Vertex v = dt_.insert(P2(x, y), hint);
                near = v;
                if (dt_.dimension() < 2) continue;
                Delaunay::Face_circulator f = dt_.incident_faces(v), end = f;
                do {
                    if (!dt_.is_infinite(f)) push(f);
                } while (++f != end);
            }
    }
    void push_all() {
        for (auto f = dt_.finite_faces_begin(); f != dt_.finite_faces_end(); ++f) push(f);
    }
    // The largest live triangle whose circumcentre is in the box; false when none is left.
    bool pop(Queued& top) {
        while (!queue_.empty()) {
            top = queue_.top();
            queue_.pop();
            Face f;
            if (dt_.is_face(top.v[0], top.v[1], top.v[2], f)) {
                top.face = f;
                return true;
            }
        }
        return false;
    }
    const Delaunay& dt() const { return dt_; }

private:
    void push(Face f) {
        const P2 c = dt_.circumcenter(f);
        if (c.x() < 0 || c.y() < 0 || c.x() >= box_.width || c.y() >= box_.height) return;
        const double r2 = CGAL::squared_distance(c, f->vertex(0)->point());
        if (r2 > last2_) queue_.push({r2, f, {f->vertex(0), f->vertex(1), f->vertex(2)}});
    }
    std::size_t bucket(double x, double y) const {
        auto axis = [&](double v, double extent) {
            const double f = (v + margin_) / (extent + 2 * margin_) * double(side_);
            return std::size_t(std::clamp(f, 0.0, double(side_ - 1)));
        };
        return axis(y, box_.height) * side_ + axis(x, box_.width);
    }
    Box box_;
    double margin_;
    double last2_;
    std::size_t side_;
    std::vector<Vertex> near_;
    Delaunay dt_;
    std::priority_queue<Queued> queue_;
};

}  // namespace

Sampling continuous_hierarchy(const SampleOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!o.hierarchy.continuous) throw Error("continuous_hierarchy needs options.hierarchy.continuous");
    validate(o);
    if (o.box.boundary != Boundary::Periodic)
        throw Error("a continuous hierarchy needs a periodic box (its free-boundary form is not built yet)");
    const double start = o.hierarchy.start == 0 ? 10.0 : o.hierarchy.start;
    const double rf0 = o.radius * start, rc0 = (o.coverage == 0 ? o.radius : o.coverage) * start;
    const bool two = o.coverage != 0 && o.coverage != o.radius;

    SampleOptions first = o;
    first.hierarchy = {};
    first.radius = rf0;
    first.coverage = two ? rc0 : 0.0;
    Sampling s = sample(first);
    const double q = s.quantum;
    s.birth.assign(s.size(), 1.0);

    // Every empty circle met has radius <= rc0 and its centre in the box: its three samples lie
    // within rc0 of the box.
    // About one bucket per sample of the final sampling.
    const double expected = 0.7 * o.box.width * o.box.height / (o.radius * o.radius);
    Events events(o.box, 1.01 * rc0, std::size_t(std::clamp(std::sqrt(expected), 1.0, 2048.0)), rc0 / start);
    for (std::size_t i = 0; i < s.size(); ++i) {
        const glm::dvec2 p = s.point(i);
        events.insert(P2(p.x, p.y), Face());
    }
    events.push_all();
    std::mt19937_64 rng(o.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto extent_x = std::uint32_t(std::llround(o.box.width / q)),
               extent_y = std::uint32_t(std::llround(o.box.height / q));
    Queued top;
    while (events.pop(top)) {
        // Only circles larger than the final Rc are queued: when none is left, the sampling is
        // maximal at the final radii.
        const double radius = std::sqrt(top.r2), t = radius / rc0;
        const P2 u = events.dt().circumcenter(top.face);
        P2 p = u;
        if (two) {
            // A uniform point of T: of the disk of radius rc(t) around u, the points no sample is
            // closer to than rf(t) (u itself is one: its nearest samples are rc(t) away).
            const double rf = t * rf0;
            for (int tries = 0; tries < 1000000; ++tries) {
                const double rho = radius * std::sqrt(unit(rng)), angle = 2 * M_PI * unit(rng);
                const P2 c(u.x() + rho * std::cos(angle), u.y() + rho * std::sin(angle));
                const Vertex near = events.dt().nearest_vertex(c, top.face);
                if (CGAL::squared_distance(near->point(), c) >= rf * rf) {
                    p = c;
                    break;
                }
            }
        }
        // Onto the lattice, in the box.
        auto wrap = [](double v, std::uint32_t extent) {
            const auto l = std::int64_t(std::llround(v));
            return std::uint32_t(((l % extent) + extent) % extent);
        };
        const glm::uvec2 l{wrap(p.x() / q, extent_x), wrap(p.y() / q, extent_y)};
        s.lattice.push_back(l);
        s.birth.push_back(t);
        events.insert(P2(double(l.x) * q, double(l.y) * q), top.face);
    }
    s.radius = o.radius;
    s.coverage = o.coverage == 0 ? o.radius : o.coverage;
    s.hierarchy_start = start;
    s.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return s;
}

}  // namespace vrpd
