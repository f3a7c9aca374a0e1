// Pictures of point sets and their analysis, drawn with cairo. Each call writes STEM.png and
// STEM.svg and throws Error naming the file if either cannot be written.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "vrpd/analysis.h"
#include "vrpd/vrpd.h"

namespace vrpd::figures {

struct PointStyle {
    double disk_radius = 0;          // in box units: disks of this radius; 0: dots
    std::vector<double> disk_radii;  // or one radius per point (box units), when not empty
    std::vector<double> colour_by;   // one value per point, coloured from blue (least) to yellow; or empty
    std::string colour_name;         // what colour_by holds, for the legend
};
void plot_points(const std::string& stem, const std::vector<glm::dvec2>& points, const Box& box,
                 const PointStyle& style, const std::string& title);

// The periodogram as an image, grey by log power from 0.1 (black) to 4 (white), DC at the centre.
void plot_spectrum(const std::string& stem, const Spectrum& spectrum, const std::string& title);

// Radial mean power against frequency, with the white-noise level 1 dashed.
void plot_radial(const std::string& stem, const RadialPower& radial, const std::string& title);

// A vertical line at `at` on a histogram, labelled (a bound of the paper's, say).
struct Marker {
    double at;
    std::string label;
};
// counts[i] is the number of values in [i w, (i + 1) w); drawn over [lo, hi) of the values.
void plot_histogram(const std::string& stem, const std::vector<std::uint64_t>& counts, double bin_width, double lo,
                    double hi, const std::vector<Marker>& markers, const std::string& x_label,
                    const std::string& title);

}  // namespace vrpd::figures
