// `vrpd figures`, spatially varying radii (paper section 5): Figure 11 (the ramp under the four
// rules, and their Delaunay angles on a rectified sine), Figure 12 (an image stippled through
// its grey levels) and Figure 16 (bigger disks on the rectified sine).
#include <cmath>
#include <fstream>
#include <iostream>
#include <numbers>

#include <fmt/format.h>

#include "cli_common.h"
#include "report.h"
#include "vrpd/figures.h"
#include "vrpd/sizing.h"
#include "vrpd/verify.h"

namespace vrpd::cli {
namespace {

constexpr const char* kRamp = "0.001 + 0.3*x";
constexpr SizingRule kRules[] = {SizingRule::Prior, SizingRule::Current, SizingRule::Bigger, SizingRule::Smaller};

// The rectified sine's smallest radius on the page (about 25 000 samples; the source's L 0.30); --full draws
// Figure 16 at the paper's 0.00015 (about 2.2 M samples, L 0.37).
constexpr double kSineSmall = 0.003;

std::string sine(double r_small) { return fmt::format("0.015 + ({} - 0.015)*abs(sin(8*pi*d))", r_small); }

// A run of `sizing` on the unit square, from `field` when it was tabulated before.
Sampling run(const Sizing& sizing, Boundary boundary, Backend backend, const SizingField* field = nullptr) {
    SampleOptions o;
    o.box.boundary = boundary;
    o.seed = 1;
    o.backend = backend;
    o.sizing = sizing;
    return field ? sample(o, *field) : sample(o);
}

std::vector<glm::dvec2> points(const Sampling& s) {
    std::vector<glm::dvec2> p(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) p[i] = s.point(i);
    return p;
}

std::string img(const std::string& stem) {
    return fmt::format("<a href=\"{0}.svg\"><img src=\"{0}.png\" width=\"320\"></a>\n", stem);
}

// A greyscale test picture for Figure 12: two dark blobs and a dark ring on white, as a binary PGM.
std::string write_picture(const std::string& path) {
    constexpr int n = 256;
    std::ofstream out(path, std::ios::binary);
    out << "P5\n" << n << " " << n << "\n255\n";
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double u = (i + 0.5) / n, v = 1 - (j + 0.5) / n;
            const double blob = 0.9 * std::exp(-(std::pow(u - 0.33, 2) + std::pow(v - 0.62, 2)) / 0.012) +
                                0.8 * std::exp(-(std::pow(u - 0.7, 2) + std::pow(v - 0.3, 2)) / 0.006);
            const double ring = 0.7 * std::exp(-std::pow(std::hypot(u - 0.68, v - 0.72) - 0.15, 2) / 0.0008);
            out.put(char(std::lround(255 * std::clamp(1 - blob - ring, 0.0, 1.0))));
        }
    if (!out) throw Error("cannot write " + path);
    return path;
}

}  // namespace

std::string sizing_figures(const ReportDir& dir, Backend backend, bool full, Json& all) {
    std::string html;
    // Figure 11: the ramp under each rule, with one seed.
    html += fmt::format(
        "<h2>Figure 11: spatially varying radii under the four rules</h2>\n<p>Left: r = {}, free "
        "boundary, seed 1, coloured by r. Right: Delaunay angles on the rectified sine r = {} "
        "(periodic).</p>\n<table>\n<tr><th>rule</th><th>ramp samples</th><th>sine samples</th>"
        "<th>smallest angle on the sine</th><th>Table 1's bound</th></tr>\n",
        kRamp, sine(kSineSmall));
    std::string panels;
    Sampling bigger_sine;
    // Each field is tabulated once for the four rules.
    Sizing ramp, wave;
    ramp.expression = kRamp;
    wave.expression = sine(kSineSmall);
    const SizingField ramp_field(ramp, {1, 1, Boundary::Free}), wave_field(wave, {1, 1, Boundary::Periodic});
    for (SizingRule rule : kRules) {
        const std::string name = sizing_rule_name(rule);
        ramp.rule = wave.rule = rule;
        const Sampling r = run(ramp, Boundary::Free, backend, &ramp_field);
        figures::PointStyle style;
        style.colour_by = r.local_radius;
        style.colour_name = "r";
        const std::string ramp_stem = "figure11-ramp-" + name;
        figures::plot_points(dir.path(ramp_stem), points(r), r.box, style,
                             fmt::format("{}: {} samples", name, r.size()));
        Sampling w = run(wave, Boundary::Periodic, backend, &wave_field);
        const SizingQuality q = sizing_quality(points(w), w.local_radius, w.box);
        const double L = w.field.lipschitz;
        const double half = rule == SizingRule::Prior || rule == SizingRule::Bigger ? 2 : 1;
        const double bound = std::asin(std::max(0.0, (1 - half * L) / 2)) * 180 / std::numbers::pi;
        const double min_angle = std::asin(q.sin_min) * 180 / std::numbers::pi;
        const std::string angle_stem = "figure11-angles-" + name;
        figures::plot_histogram(dir.path(angle_stem), q.angles.counts, 1.0, 0, 180,
                                {{bound, fmt::format("Table 1 bound {:.1f}", bound)}}, "Delaunay angle (degrees)",
                                fmt::format("{}: angles on the sine, L {:.3f}", name, L));
        html += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{:.2f} deg</td><td>{:.2f} deg</td></tr>\n", name,
                            r.size(), w.size(), min_angle, bound);
        panels += img(ramp_stem) + img(angle_stem);
        all["11"][name] = {{"ramp_samples", r.size()},   {"sine_samples", w.size()}, {"sine_lipschitz", L},
                           {"min_angle_deg", min_angle}, {"angle_bound_deg", bound}, {"edge_min_r", q.edge_min},
                           {"edge_max_r", q.edge_max}};
        std::cerr << fmt::format("vrpd: figure 11 {}: {} ramp samples, {} on the sine, smallest angle {:.2f} deg\n",
                                 name, r.size(), w.size(), min_angle);
        if (rule == SizingRule::Bigger) bigger_sine = std::move(w);
    }
    html += "</table>\n" + panels;

    // Figure 12: a picture's grey levels as radii, smoothed to L = 0.3.
    Sizing picture;
    picture.image = write_picture(dir.path("figure12-picture.pgm"));
    picture.r_min = 0.002;
    picture.r_max = 0.02;
    picture.lipschitz = 0.3;
    picture.rule = SizingRule::Current;
    const Sampling st = run(picture, Boundary::Free, backend);
    figures::plot_points(dir.path("figure12-stipple"), points(st), st.box, {}, fmt::format("{} samples", st.size()));
    html += fmt::format(
        "<h2>Figure 12: a picture stippled</h2>\n<p>The grey levels of <a href=\"figure12-picture.pgm\">"
        "a test picture</a> (vrpd's own: two blobs and a ring) as r from 0.002 (black) to 0.02 "
        "(white), smoothed to L = 0.3, current rule: {} samples.</p>\n{}",
        st.size(), img("figure12-stipple"));
    all["12"] = {{"samples", st.size()}, {"lipschitz", st.field.lipschitz}};

    // Figure 16: bigger disks on the rectified sine; the paper's r_M = 0.00015 with --full.
    const double r_small = full ? 0.00015 : kSineSmall;
    Sampling f16 = std::move(bigger_sine);
    if (full) {
        Sizing wave;
        wave.expression = sine(r_small);
        wave.rule = SizingRule::Bigger;
        f16 = run(wave, Boundary::Periodic, backend);
    }
    figures::plot_points(dir.path("figure16-sine"), points(f16), f16.box, {},
                         fmt::format("{} samples, {:.1f} s", f16.size(), f16.stats.seconds));
    html += fmt::format(
        "<h2>Figure 16: bigger disks on a rectified sine</h2>\n<p>r = {} (periodic), L {:.3f}: {} "
        "samples in {:.2f} s, {:.0f} MiB of arrays{}.</p>\n{}",
        sine(r_small), f16.field.lipschitz, f16.size(), f16.stats.seconds, double(f16.stats.peak_bytes) / (1 << 20),
        full ? "" : " (the paper's r_M = 0.00015, about 2.2 M samples, with --full)", img("figure16-sine"));
    all["16"] = {{"r_small", r_small},
                 {"samples", f16.size()},
                 {"seconds", f16.stats.seconds},
                 {"peak_bytes", f16.stats.peak_bytes}};
    return html;
}

}  // namespace vrpd::cli
