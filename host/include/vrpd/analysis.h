// Point-set analysis in the conventions of Schlömer and Deussen's PSA, which the paper's section 6
// uses: the periodogram over integer frequencies, its radial mean and anisotropy, and the
// normalised spacing measures. Part of the MIT core: no triangulation is needed here (the
// Delaunay histograms are vrpd_geometry's, vrpd/verify.h).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "vrpd/vrpd.h"

namespace vrpd {

struct SpectrumOptions {
    int half_width = 64;               // frequencies k in [-half_width, half_width]^2, in cycles per box side
    Backend backend = Backend::Auto;   // Gpu: a compute kernel; Cpu and Serial: the host in double
    std::string device;                // as SampleOptions::device
    unsigned threads = 0;              // host threads; 0: one per core
};

// P(k) = |sum_j exp(-2 pi i (kx x_j / W + ky y_j / H))|^2 / n, averaged over the sets (white
// noise reads 1), the DC term P(0) set to 0. Each coordinate is first rounded to a 32-bit fixed
// point fraction of its side, so every phase k . x is an exact integer modulo 2^32 on every
// backend; the host then sums in double, the kernel in float (docs/design.md gives its error).
struct Spectrum {
    int half_width = 0;
    std::size_t sets = 0;
    double mean_points = 0;
    std::vector<double> power;  // (2 half_width + 1)^2 values: rows ky, columns kx, each from -half_width
    Backend backend = Backend::Cpu;  // the backend that computed it (never Auto)
    std::string device;              // with Gpu, the Vulkan device; else "host"

    std::size_t width() const { return std::size_t(2 * half_width + 1); }
    double at(int kx, int ky) const {
        return power[std::size_t(ky + half_width) * width() + std::size_t(kx + half_width)];
    }
};

// Throws Error for no sets, an empty set, a point outside the box, or half_width outside [1, 1024].
Spectrum periodogram(const std::vector<std::vector<glm::dvec2>>& sets, const Box& box,
                     const SpectrumOptions& options);

// The spectrum over annuli of width 1 centred on the integer radii f = 1..half_width (|k| rounded to
// the nearest integer): the mean power, and the anisotropy 10 log10(variance / mean^2) in dB.
struct RadialPower {
    std::vector<double> frequency;  // f, in cycles per box side
    std::vector<double> power;
    std::vector<double> anisotropy_db;
};
RadialPower radial_power(const Spectrum& spectrum);

// Nearest-neighbour distances relative to d_max = sqrt(2 A / (sqrt(3) n)), the spacing of the
// hexagonal packing of n points in the box's area A: delta_x is the smallest (PSA's normalised
// minimum distance), mean_min_distance the mean of every point's nearest-neighbour distance.
// Periodic boxes measure the shortest way round. Throws Error for fewer than 2 points.
struct Spacing {
    double d_max = 0;
    double delta_x = 0;
    double mean_min_distance = 0;
};
Spacing spacing(const std::vector<glm::dvec2>& points, const Box& box);

}  // namespace vrpd
