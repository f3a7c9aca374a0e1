// The figures (vrpd/figures.h): each panel is drawn once, by one function, onto a PNG surface
// and an SVG surface in turn.
#include "vrpd/figures.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

namespace vrpd::figures {
namespace {

constexpr int kWidth = 640, kHeight = 480;  // plots
constexpr int kSquare = 640;                // point sets and spectra
constexpr double kMargin = 56;              // room for tick labels and axis titles

using Draw = std::function<void(cairo_t*, double width, double height)>;

void check(cairo_status_t status, const std::string& file) {
    if (status != CAIRO_STATUS_SUCCESS)
        throw Error(fmt::format("cannot write {}: {}", file, cairo_status_to_string(status)));
}

// Draws onto a white PNG and a white SVG of the given size: STEM.png and STEM.svg.
void write(const std::string& stem, int width, int height, const Draw& draw) {
    auto paint = [&](cairo_surface_t* surface, const std::string& file) {
        cairo_t* cr = cairo_create(surface);
        cairo_set_source_rgb(cr, 1, 1, 1);
        cairo_paint(cr);
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
        cairo_set_font_size(cr, 13);
        draw(cr, width, height);
        const cairo_status_t status = cairo_status(cr);
        cairo_destroy(cr);
        check(status, file);
    };
    const std::string png = stem + ".png", svg = stem + ".svg";
    cairo_surface_t* image = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
    paint(image, png);
    const cairo_status_t written = cairo_surface_write_to_png(image, png.c_str());
    cairo_surface_destroy(image);
    check(written, png);
    cairo_surface_t* vector = cairo_svg_surface_create(svg.c_str(), width, height);
    paint(vector, svg);
    cairo_surface_finish(vector);
    const cairo_status_t finished = cairo_surface_status(vector);
    cairo_surface_destroy(vector);
    check(finished, svg);
}

void text(cairo_t* cr, double x, double y, const std::string& s, double align_x = 0.5, double align_y = 0.5) {
    cairo_text_extents_t e;
    cairo_text_extents(cr, s.c_str(), &e);
    cairo_move_to(cr, x - e.x_advance * align_x, y + e.height * (1 - align_y));
    cairo_show_text(cr, s.c_str());
}

void title(cairo_t* cr, double width, const std::string& s) {
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_font_size(cr, 15);
    text(cr, width / 2, 18, s);
    cairo_set_font_size(cr, 13);
}

// Tick spacing of 1, 2 or 5 times a power of ten, giving about five ticks over `range`.
double tick_step(double range) {
    const double rough = range / 5, power = std::pow(10.0, std::floor(std::log10(rough)));
    for (double m : {1.0, 2.0, 5.0})
        if (m * power >= rough) return m * power;
    return 10 * power;
}

// The axes of a plot over [x0, x1] x [y0, y1] in the rectangle left of the margins; returns the
// map from data to the surface.
struct Frame {
    double left, top, right, bottom, x0, x1, y0, y1;
    double x(double v) const { return left + (v - x0) / (x1 - x0) * (right - left); }
    double y(double v) const { return bottom - (v - y0) / (y1 - y0) * (bottom - top); }
};
Frame axes(cairo_t* cr, double width, double height, double x0, double x1, double y0, double y1,
           const std::string& x_label, const std::string& y_label) {
    const Frame f{kMargin + 8, 34, width - 20, height - kMargin, x0, x1, y0, y1};
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1);
    cairo_rectangle(cr, f.left, f.top, f.right - f.left, f.bottom - f.top);
    cairo_stroke(cr);
    const double sx = tick_step(x1 - x0), sy = tick_step(y1 - y0);
    for (double v = std::ceil(x0 / sx) * sx; v <= x1 + 1e-9 * sx; v += sx) {
        cairo_move_to(cr, f.x(v), f.bottom);
        cairo_line_to(cr, f.x(v), f.bottom + 5);
        cairo_stroke(cr);
        text(cr, f.x(v), f.bottom + 14, fmt::format("{:g}", v));
    }
    for (double v = std::ceil(y0 / sy) * sy; v <= y1 + 1e-9 * sy; v += sy) {
        cairo_move_to(cr, f.left - 5, f.y(v));
        cairo_line_to(cr, f.left, f.y(v));
        cairo_stroke(cr);
        text(cr, f.left - 8, f.y(v), fmt::format("{:g}", v), 1.0);
    }
    text(cr, (f.left + f.right) / 2, height - 14, x_label);
    cairo_save(cr);
    cairo_translate(cr, 16, (f.top + f.bottom) / 2);
    cairo_rotate(cr, -M_PI / 2);
    text(cr, 0, 0, y_label);
    cairo_restore(cr);
    return f;
}

void dashed_line(cairo_t* cr, double x0, double y0, double x1, double y1) {
    const double dash[] = {6, 4};
    cairo_set_dash(cr, dash, 2, 0);
    cairo_move_to(cr, x0, y0);
    cairo_line_to(cr, x1, y1);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
}

// Blue (0) to yellow (1) through green.
void colour_ramp(cairo_t* cr, double v) {
    v = std::clamp(v, 0.0, 1.0);
    cairo_set_source_rgb(cr, 0.27 + 0.72 * v * v, 0.0 + 0.9 * v, 0.33 + 0.4 * v - 0.6 * v * v);
}

}  // namespace

void plot_points(const std::string& stem, const std::vector<glm::dvec2>& points, const Box& box,
                 const PointStyle& style, const std::string& name) {
    const double longest = std::max(box.width, box.height);
    const int width = int(std::lround(kSquare * box.width / longest)) + 40;
    const int height = int(std::lround(kSquare * box.height / longest)) + 60;
    double lo = 0, hi = 1;
    if (!style.disk_radii.empty() && style.disk_radii.size() != points.size())
        throw Error(fmt::format("{} disk radii for {} points", style.disk_radii.size(), points.size()));
    if (!style.colour_by.empty()) {
        if (style.colour_by.size() != points.size())
            throw Error(fmt::format("{} values to colour {} points", style.colour_by.size(), points.size()));
        auto [a, b] = std::minmax_element(style.colour_by.begin(), style.colour_by.end());
        lo = *a;
        hi = *b > *a ? *b : *a + 1;
    }
    write(stem, width, height, [&](cairo_t* cr, double w, double h) {
        title(cr, w, style.colour_by.empty() ? name
                                             : fmt::format("{} (colour: {} from {:.4g} to {:.4g})", name,
                                                           style.colour_name, lo, hi));
        const double scale = kSquare / longest, left = 20, top = 40;
        cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
        cairo_set_line_width(cr, 1);
        cairo_rectangle(cr, left, top, box.width * scale, box.height * scale);
        cairo_stroke(cr);
        const double dot = style.disk_radius > 0 ? style.disk_radius * scale : std::min(1.6, 0.3 * w / 100);
        cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (!style.colour_by.empty()) colour_ramp(cr, (style.colour_by[i] - lo) / (hi - lo));
            const double radius = style.disk_radii.empty() ? dot : style.disk_radii[i] * scale;
            // y up, as in the paper's figures
            cairo_arc(cr, left + points[i].x * scale, top + (box.height - points[i].y) * scale, radius, 0, 2 * M_PI);
            cairo_fill(cr);
        }
        (void)h;
    });
}

void plot_spectrum(const std::string& stem, const Spectrum& spectrum, const std::string& name) {
    const int n = int(spectrum.width());
    cairo_surface_t* image = cairo_image_surface_create(CAIRO_FORMAT_RGB24, n, n);
    cairo_surface_flush(image);
    unsigned char* data = cairo_image_surface_get_data(image);
    const int stride = cairo_image_surface_get_stride(image);
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            // Row 0 is the highest ky, so that ky points up.
            const double p = spectrum.at(col - spectrum.half_width, spectrum.half_width - row);
            const double g = std::clamp((std::log10(std::max(p, 1e-30)) + 1) / std::log10(40.0), 0.0, 1.0);
            const auto v = std::uint32_t(std::lround(g * 255));
            reinterpret_cast<std::uint32_t*>(data + row * stride)[col] = v << 16 | v << 8 | v;
        }
    cairo_surface_mark_dirty(image);
    try {
        write(stem, kSquare + 40, kSquare + 60, [&](cairo_t* cr, double w, double) {
            title(cr, w, fmt::format("{}: |k| up to {}", name, spectrum.half_width));
            cairo_save(cr);
            cairo_translate(cr, 20, 40);
            cairo_scale(cr, double(kSquare) / n, double(kSquare) / n);
            cairo_set_source_surface(cr, image, 0, 0);
            cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
            cairo_paint(cr);
            cairo_restore(cr);
        });
    } catch (...) {
        cairo_surface_destroy(image);
        throw;
    }
    cairo_surface_destroy(image);
}

void plot_radial(const std::string& stem, const RadialPower& radial, const std::string& name) {
    double top = 2;
    for (double p : radial.power) top = std::max(top, p * 1.05);
    const double right = radial.frequency.empty() ? 1 : radial.frequency.back();
    write(stem, kWidth, kHeight, [&](cairo_t* cr, double w, double h) {
        title(cr, w, name);
        const Frame f = axes(cr, w, h, 0, right, 0, top, "frequency (cycles per box side)", "radial mean power");
        cairo_set_source_rgb(cr, 0.5, 0.5, 0.5);
        dashed_line(cr, f.x(0), f.y(1), f.x(right), f.y(1));
        cairo_set_source_rgb(cr, 0.1, 0.3, 0.7);
        cairo_set_line_width(cr, 1.5);
        for (std::size_t i = 0; i < radial.power.size(); ++i) {
            if (i == 0)
                cairo_move_to(cr, f.x(radial.frequency[i]), f.y(radial.power[i]));
            else
                cairo_line_to(cr, f.x(radial.frequency[i]), f.y(radial.power[i]));
        }
        cairo_stroke(cr);
    });
}

void plot_histogram(const std::string& stem, const std::vector<std::uint64_t>& counts, double bin_width, double lo,
                    double hi, const std::vector<Marker>& markers, const std::string& x_label,
                    const std::string& name) {
    std::uint64_t total = 0, most = 1;
    for (std::uint64_t c : counts) {
        total += c;
        most = std::max(most, c);
    }
    const double share = total == 0 ? 1 : double(most) / double(total);
    write(stem, kWidth, kHeight, [&](cairo_t* cr, double w, double h) {
        title(cr, w, name);
        const Frame f = axes(cr, w, h, lo, hi, 0, share * 1.1, x_label, "share of values");
        cairo_set_source_rgb(cr, 0.3, 0.5, 0.8);
        for (std::size_t i = 0; i < counts.size() && total > 0; ++i) {
            const double a = std::max(lo, double(i) * bin_width), b = std::min(hi, double(i + 1) * bin_width);
            if (b <= a || counts[i] == 0) continue;
            const double v = double(counts[i]) / double(total);
            cairo_rectangle(cr, f.x(a), f.y(v), f.x(b) - f.x(a), f.y(0) - f.y(v));
        }
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
        cairo_set_line_width(cr, 1.5);
        for (std::size_t i = 0; i < markers.size(); ++i) {
            const Marker& m = markers[i];
            dashed_line(cr, f.x(m.at), f.y(0), f.x(m.at), f.y(share * 1.1));
            text(cr, f.x(m.at) + 4, f.top + 10 + 16 * double(i), m.label, 0.0);  // one line each
        }
    });
}

}  // namespace vrpd::figures
