// Exact verification of a sampling, independent of how it was made: conflicts (paper Eq. 1/5),
// maximality by the largest empty circle (Eqs. 3/8), and Delaunay quality (Propositions 1-2).
// Part of the optional vrpd_geometry target, built on CGAL (GPL): the sampling core never needs it.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "vrpd/vrpd.h"

namespace vrpd {

struct Radii {
    double inhibition;  // Rf: samples closer than this conflict
    double coverage;    // Rc: maximal iff every point of the box is within Rc of a sample
    double tolerance = 0;  // the points' resolution: pairs conflict if closer than Rf - tolerance,
                           // and the set is maximal if every empty circle is smaller than Rc + tolerance
};

struct Histogram {
    double bin_width;
    std::size_t bins;                   // bin i holds values in [i w, (i+1) w); the last, all above
    std::vector<std::uint64_t> counts;  // bins entries, or empty if nothing was counted
};

struct Report {
    std::size_t points = 0;
    double density = 0;                 // n Rf^2 / area
    double min_distance = 0;            // over all pairs (periodic: shortest way round)
    std::uint64_t conflicts = 0;        // pairs closer than Rf - tolerance
    double largest_empty_radius = 0;    // radius of the largest empty circle centred in the box
    glm::dvec2 largest_empty_centre{0, 0};
    bool maximal = false;               // largest_empty_radius < Rc + tolerance
    // Delaunay triangles counted: periodic, each triangle once; free boundary, only triangles
    // whose circumcentre lies in the box (the hull's slivers are outside the paper's theory).
    std::uint64_t triangles = 0;
    double min_angle_degrees = 0;
    double max_angle_degrees = 0;
    Histogram angles{1.0, 180, {}};     // degrees
    double min_edge = 0, max_edge = 0;  // over those triangles' edges
    Histogram edges{0.05, 200, {}};     // edge length / Rf, once per triangle an edge bounds; up to 10 Rf
    bool passed() const { return conflicts == 0 && maximal; }
};

// Throws Error (with the index of the offending point) for NaN or inf, points outside the box,
// duplicate points, no points, radii that are not 0 < Rf <= Rc with 0 <= tolerance < Rf, or
// lengths outside those vrpd takes (kSmallestLength to kLargestLength, vrpd.h).
// Any nonempty set is judged, down to one point; min_distance is infinite without a pair.
Report verify(const std::vector<glm::dvec2>& points, Radii radii, const Box& box);

// Table 1's Delaunay columns for a sampling under a sizing field, over the triangles verify
// counts (periodic: each once; free: circumcentre in the box): each edge's length as a factor of
// r at either endpoint (least and greatest), the least sine of an angle, and the angles.
struct SizingQuality {
    std::uint64_t triangles = 0;
    double edge_min = 0, edge_max = 0;  // |x - y| / r(x) over edges, both ends
    double sin_min = 0;
    Histogram angles{1.0, 180, {}};     // degrees
};
// radius[i] is r at points[i]; on a torus, triangles within 3 max(radius) of the box are built.
SizingQuality sizing_quality(const std::vector<glm::dvec2>& points, const std::vector<double>& radius,
                             const Box& box);

}  // namespace vrpd
