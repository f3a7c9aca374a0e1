// The exact checker (issue: vrpd check and the geometry target) on hand-made sets with known
// answers, and on the sampler's output: maximality by the largest empty circle, Prop. 1-2.
#include <catch2/catch.hpp>

#include <cmath>

#include "support.h"
#include "vrpd/verify.h"

using namespace vrpd;
using vrpd::test::options;

namespace {
// A k x k square lattice of spacing 1/k on the unit torus, offset so that no circumcentre falls
// on the box's sides (where rounding would decide which image of a triangle is counted).
std::vector<glm::dvec2> square_lattice(int k) {
    std::vector<glm::dvec2> p;
    for (int y = 0; y < k; ++y)
        for (int x = 0; x < k; ++x) p.push_back({(x + 0.25) / k, (y + 0.25) / k});
    return p;
}
}  // namespace

TEST_CASE("square lattice: known empty circle and angles", "[verify]") {
    const int k = 10;
    const double a = 1.0 / k;
    // Neighbours are exactly a apart, which rounding may put a hair below a: Rf just under a.
    const Report r = verify(square_lattice(k), {0.999 * a, a}, Box{});
    CHECK(r.conflicts == 0);
    CHECK(r.min_distance == Approx(a));
    CHECK(r.largest_empty_radius == Approx(a / std::sqrt(2.0)));
    CHECK(r.maximal);
    CHECK(r.triangles == 2 * k * k);
    CHECK(r.min_angle_degrees == Approx(45));
    CHECK(r.max_angle_degrees == Approx(90));
}

TEST_CASE("hexagonal lattice: every angle is 60 degrees", "[verify]") {
    const int cols = 8, rows = 10;  // rows even, so the torus closes
    const double a = 1.0;
    const Box box{cols * a, rows * a * std::sqrt(3.0) / 2, Boundary::Periodic};
    std::vector<glm::dvec2> p;
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < cols; ++x)
            p.push_back({(x + 0.5 * (y % 2) + 0.25) * a, (y + 0.5) * a * std::sqrt(3.0) / 2});
    const Report r = verify(p, {a, a}, box);
    CHECK(r.min_angle_degrees == Approx(60).epsilon(1e-9));
    CHECK(r.max_angle_degrees == Approx(60).epsilon(1e-9));
    CHECK(r.largest_empty_radius == Approx(a / std::sqrt(3.0)));
    CHECK(r.maximal);
}

TEST_CASE("a planted gap is found, with its centre", "[verify]") {
    const int k = 10;
    std::vector<glm::dvec2> p = square_lattice(k);
    const glm::dvec2 removed = p[34];
    p.erase(p.begin() + 34);
    const Report r = verify(p, {0.9 / k, 0.9 / k}, Box{});
    CHECK_FALSE(r.maximal);
    CHECK(r.largest_empty_radius == Approx(1.0 / k));
    CHECK(r.largest_empty_centre.x == Approx(removed.x));
    CHECK(r.largest_empty_centre.y == Approx(removed.y));
}

TEST_CASE("a planted conflict is counted", "[verify]") {
    std::vector<glm::dvec2> p = square_lattice(10);
    p.push_back({p[5].x + 0.0007, p[5].y});  // 0.0007 from p[5], 0.0993 (> Rf) from the rest
    const Report r = verify(p, {0.099, 0.1}, Box{});
    CHECK(r.conflicts == 1);
    CHECK(r.min_distance == Approx(0.0007));
    CHECK_FALSE(r.passed());
}

// The buckets' neighbourhoods as runs of columns and rows, wrapped on a torus and taken once
// each where an axis has fewer than three buckets: every pair closer than Rf, counted once.
TEST_CASE("conflicts by buckets equal the pairs found by brute force", "[verify]") {
    std::uint32_t state = 12345;
    auto uniform = [&] {
        state = state * 1664525u + 1013904223u;
        return double(state >> 8) / double(1u << 24);
    };
    for (const Boundary boundary : {Boundary::Periodic, Boundary::Free})
        for (const glm::dvec2 extent : {glm::dvec2(1, 1), glm::dvec2(3, 1)})
            for (const double rf : {0.05, 0.3, 0.45}) {
                const Box box{extent.x, extent.y, boundary};
                std::vector<glm::dvec2> p(300);
                for (glm::dvec2& q : p) q = {uniform() * extent.x, uniform() * extent.y};
                std::uint64_t brute = 0;
                for (std::size_t i = 0; i < p.size(); ++i)
                    for (std::size_t j = i + 1; j < p.size(); ++j) {
                        double gx = std::abs(p[i].x - p[j].x), gy = std::abs(p[i].y - p[j].y);
                        if (boundary == Boundary::Periodic)
                            gx = std::min(gx, extent.x - gx), gy = std::min(gy, extent.y - gy);
                        brute += gx * gx + gy * gy < rf * rf;
                    }
                INFO("Rf " << rf << " box " << extent.x << " x " << extent.y
                           << (boundary == Boundary::Free ? " free" : " periodic"));
                CHECK(brute > 0);
                CHECK(verify(p, {rf, rf}, box).conflicts == brute);
            }
}

TEST_CASE("free boundary: empty circles centred on the sides and corners count", "[verify]") {
    // Three points near one corner of a 1 x 1 box: the far corner is the largest empty centre.
    const std::vector<glm::dvec2> p{{0.1, 0.1}, {0.2, 0.1}, {0.1, 0.2}};
    const Report r = verify(p, {0.05, 0.05}, Box{1, 1, Boundary::Free});
    CHECK(r.largest_empty_radius == Approx(std::hypot(0.8, 0.9)).epsilon(1e-6));
    CHECK_FALSE(r.maximal);
}

// Sets too small or too straight to triangulate: a large radius leaves one or two samples. The
// largest empty circle is then centred at a corner, or where a bisector meets a side (free box),
// or at the far side of the torus.
TEST_CASE("one, two or collinear points: the largest empty circle is still found", "[verify]") {
    const Box free{1, 1, Boundary::Free};
    const Box torus{};
    struct Known {
        std::vector<glm::dvec2> points;
        Box box;
        double radius;  // of the largest empty circle
    };
    const Known known[] = {
        {{{0.5, 0.5}}, free, std::sqrt(0.5)},                                // at a corner
        {{{0.3, 0.5}}, free, std::hypot(0.7, 0.5)},                          // the far corners
        {{{0.25, 0.5}, {0.75, 0.5}}, free, std::hypot(0.25, 0.5)},           // corners, and x = 0.5 on the sides
        {{{0.5, 0.2}, {0.5, 0.9}}, free, std::hypot(0.5, 0.35)},             // the bisector y = 0.55 on the sides
        {{{0.2, 0.5}, {0.5, 0.5}, {0.8, 0.5}}, free, std::hypot(0.2, 0.5)},  // on one line
        {{{0.5, 0.5}}, torus, std::sqrt(0.5)},                               // the torus's far point
        {{{0.25, 0.25}, {0.75, 0.75}}, torus, 0.5},                          // a square lattice of side sqrt(1/2)
    };
    for (const Known& k : known) {
        INFO(k.points.size() << " points, " << (k.box.boundary == Boundary::Free ? "free" : "periodic"));
        const Report below = verify(k.points, {0.1, k.radius * (1 - 1e-6)}, k.box);
        CHECK(below.largest_empty_radius == Approx(k.radius).epsilon(1e-9));
        CHECK_FALSE(below.maximal);
        CHECK(verify(k.points, {0.1, k.radius * (1 + 1e-6)}, k.box).maximal);
    }
}

TEST_CASE("bad point sets are refused with the offending point", "[verify]") {
    const Box box{};
    CHECK_THROWS_WITH(verify({}, {0.1, 0.1}, box), Catch::Contains("no points"));
    CHECK_THROWS_WITH(verify({{0.1, 0.1}, {0.2, 0.2}, {0.1, 0.1}}, {0.1, 0.1}, box), Catch::Contains("same point"));
    CHECK_THROWS_WITH(verify({{0.1, 0.1}, {0.2, 0.2}, {1.5, 0.1}}, {0.1, 0.1}, box), Catch::Contains("point 3"));
    CHECK_THROWS_WITH(verify({{0.1, 0.1}, {0.2, NAN}, {0.3, 0.1}}, {0.1, 0.1}, box), Catch::Contains("not finite"));
    CHECK_THROWS_WITH(verify(square_lattice(4), {0.2, 0.1}, box), Catch::Contains("Rf <= Rc"));
}

// The stated range (vrpd.h): extents and radii from 1e-100 to 1e100. Within it every figure is a
// plain double, at either end; outside it the set is refused, not judged wrongly.
TEST_CASE("extreme scales: judged within the lengths vrpd takes, refused outside them", "[verify]") {
    const Box tiny{1e-300, 1e-300, Boundary::Free};
    CHECK_THROWS_WITH(verify({{1e-301, 1e-301}, {5e-301, 5e-301}}, {1e-302, 1e-302}, tiny),
                      Catch::Contains("width 1e-300 is outside the lengths vrpd judges"));
    CHECK_THROWS_WITH(verify({{1, 1}}, {1e101, 1e101}, Box{2, 2, Boundary::Free}), Catch::Contains("Rf 1e+101"));
    CHECK_THROWS_WITH(verify({{1, 1}}, {1e-101, 1}, Box{2, 2, Boundary::Free}), Catch::Contains("Rf 1e-101"));

    // Two points 1.4e-160 apart: their squared distance underflows, their distance does not.
    const Report close = verify({{1e-160, 1e-160}, {2e-160, 2e-160}}, {1e-100, 1e-100}, Box{1, 1, Boundary::Free});
    CHECK(close.conflicts == 1);
    CHECK(close.min_distance == Approx(std::sqrt(2.0) * 1e-160));

    // The largest box: a 4 x 4 square lattice of spacing 2.5e99, judged at its own radii and at the
    // smallest, where every edge is 1e199 radii long and lands in the histogram's last bin.
    std::vector<glm::dvec2> grid;
    for (glm::dvec2 p : square_lattice(4)) grid.push_back(p * 1e100);
    const Box big{1e100, 1e100, Boundary::Periodic};
    const Report at_spacing = verify(grid, {1.7e99, 2.5e99 / std::sqrt(2.0) * (1 + 1e-9)}, big);
    CHECK(at_spacing.conflicts == 0);
    CHECK(at_spacing.maximal);
    CHECK(at_spacing.min_distance == Approx(2.5e99));
    const Report at_smallest = verify(grid, {1e-100, 1e-100}, big);
    CHECK_FALSE(at_smallest.maximal);
    REQUIRE(at_smallest.edges.counts.size() == at_smallest.edges.bins);
    CHECK(at_smallest.edges.counts.back() == 3 * at_smallest.triangles);
}

// Maximality of the sampler's output, judged by the largest empty circle. Samples lie on a
// lattice of spacing q, and coverage is exact on it, so the continuous largest empty circle may
// exceed r by at most q / sqrt(2) (q is about 1e-6 r here).
TEST_CASE("sampler output is conflict-free and maximal by the largest empty circle", "[verify][sampling]") {
    const struct {
        double radius;
        Box box;
        Backend backend;
    } cases[] = {
        {0.01, {1, 1, Boundary::Periodic}, Backend::Gpu},
        {0.004, {1, 1, Boundary::Periodic}, Backend::Cpu},
        {0.02, {1.5, 0.7, Boundary::Free}, Backend::Gpu},
        {5.0, {320, 180, Boundary::Free}, Backend::Cpu},
        {5.0, {320, 180, Boundary::Periodic}, Backend::Cpu},
    };
    for (const auto& c : cases) {
        for (std::uint32_t seed : {1u, 2u}) {
            const Sampling s = sample(options(c.radius, seed, c.backend, c.box));
            const Report r = verify(vrpd::test::points_of(s), {c.radius, c.radius}, c.box);
            INFO("r " << c.radius << " box " << c.box.width << "x" << c.box.height << " seed " << seed << ": LEC "
                      << r.largest_empty_radius << ", min angle " << r.min_angle_degrees);
            CHECK(r.conflicts == 0);
            CHECK(r.largest_empty_radius < c.radius + s.quantum / std::sqrt(2.0));
            // Proposition 2 with Rf = Rc: every Delaunay angle > 30 degrees; Prop. 1: edges in [r, 2r].
            CHECK(r.min_angle_degrees > 30.0);
            CHECK(r.min_edge >= c.radius * (1 - 1e-9));
            CHECK(r.max_edge <= 2 * c.radius + s.quantum);
        }
    }
}

TEST_CASE("removing any one sample from a maximal set makes it fail", "[verify][sampling]") {
    const Sampling s = sample(options(0.1, 9, Backend::Cpu));
    const std::vector<glm::dvec2> all = vrpd::test::points_of(s);
    REQUIRE(verify(all, {0.1, 0.1}, Box{}).passed());
    for (std::size_t i = 0; i < all.size(); ++i) {
        std::vector<glm::dvec2> fewer = all;
        fewer.erase(fewer.begin() + std::ptrdiff_t(i));
        const Report r = verify(fewer, {0.1, 0.1}, Box{});
        INFO("without sample " << i);
        CHECK_FALSE(r.maximal);
        CHECK(r.largest_empty_radius >= 0.1);
    }
}

// Two radii (paper section 3): conflict-free at Rf, maximal at Rc by the largest empty circle, and
// Propositions 1-2: every Delaunay edge in [Rf, 2 Rc], every angle >= asin(Rf / (2 Rc)). With two
// radii the quadtree's cells are tested exactly in the continuous plane, so on a torus the largest
// empty circle is at most Rc itself (up to rounding when points are converted to doubles); with a
// free boundary, U is the box of lattice points [0, (lattice_x - 1) q], less than q short of the
// box. Rc / Rf = 1 is the one-radius sampler reached through --rf/--rc (within q / sqrt(2)).
TEST_CASE("two radii: conflict-free at Rf, maximal at Rc, Delaunay bounds of Props. 1-2", "[verify][two-radii]") {
    const struct {
        double rf, rc;
        Box box;
        Backend backend;
    } cases[] = {
        {0.01, 0.01, {1, 1, Boundary::Periodic}, Backend::Cpu},
        {0.01, 0.015, {1, 1, Boundary::Periodic}, Backend::Gpu},
        {0.005, 0.01, {1, 1, Boundary::Periodic}, Backend::Cpu},
        {0.005, 0.02, {1, 1, Boundary::Periodic}, Backend::Cpu},
        {0.01, 0.015, {1.5, 0.7, Boundary::Free}, Backend::Cpu},
        {0.005, 0.01, {1, 1, Boundary::Free}, Backend::Gpu},
        {2.5, 10.0, {320, 180, Boundary::Free}, Backend::Cpu},
    };
    for (const auto& c : cases) {
        for (std::uint32_t seed : {1u, 2u}) {
            SampleOptions o = options(c.rf, seed, c.backend, c.box);
            o.coverage = c.rc;
            const Sampling s = sample(o);
            const Report r = verify(vrpd::test::points_of(s), {c.rf, c.rc}, c.box);
            INFO("Rf " << c.rf << " Rc " << c.rc << " box " << c.box.width << "x" << c.box.height << " seed " << seed
                       << ": LEC " << r.largest_empty_radius << ", angles " << r.min_angle_degrees << ", edges "
                       << r.min_edge << ".." << r.max_edge);
            CHECK(r.conflicts == 0);
            if (c.rf == c.rc) CHECK(r.largest_empty_radius < c.rc + s.quantum / std::sqrt(2.0));
            else if (c.box.boundary == Boundary::Periodic) CHECK(r.largest_empty_radius <= c.rc * (1 + 1e-12));
            else CHECK(r.largest_empty_radius < c.rc + s.quantum);
            CHECK(r.min_edge >= c.rf * (1 - 1e-9));
            CHECK(r.max_edge <= 2 * c.rc + s.quantum);
            CHECK(r.min_angle_degrees >= std::asin(c.rf / (2 * c.rc)) * 180 / M_PI - 1e-6);
            // The sets differ from one radius: with Rc > Rf some Delaunay edges exceed 2 Rf.
            if (c.rc >= 2 * c.rf) CHECK(r.max_edge > 2 * c.rf);
        }
    }
}
