// `vrpd figures`: the paper's section 6 figures regenerated with vrpd's samplers, each beside the
// paper's numbers, on a page a browser opens.
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>

#include <fmt/format.h>

#include "cli_common.h"
#include "report.h"

namespace vrpd::cli {
namespace {

struct Figure {
    const char* id;
    const char* title;
    double rf, rc;         // the sampler's radii; 0: uniform random points
    unsigned steps;        // a discrete hierarchy of this many steps to (rf, rc), or 0
    std::size_t count;     // uniform random: the points per set
    double paper_count;    // the paper's
    const char* paper_note;
};

constexpr Figure kFigures[] = {
    {"4", "Uniform MPS, r = 0.01", 0.01, 0.01, 0, 0, 6656, ""},
    {"5", "Two radii, Rc = 2 Rf = 0.01", 0.005, 0.01, 0, 0, 8566, "smallest angle 15.1 deg, bound 14.4 deg"},
    {"6", "Final level of a ten-step discrete hierarchy to r = 0.01", 0.01, 0.01, 10, 0, 6727, ""},
    {"7", "Ten steps to Rc = 2 Rf = 0.01", 0.005, 0.01, 10, 0, 8432, ""},
    {"8", "Two radii, Rc / 2 = Rf = 0.01", 0.01, 0.02, 0, 0, 2010, ""},
    {"9", "Ten steps to Rc / 2 = Rf = 0.01", 0.01, 0.02, 10, 0, 2006, ""},
    {"10", "Uniform random points", 0, 0, 0, 2010, 2010, ""},
};

Sets make_sets(const Figure& f, unsigned count, Backend backend, std::string& device) {
    Sets sets;
    for (unsigned s = 1; s <= count; ++s) {
        std::vector<glm::dvec2> pts;
        if (f.rf == 0) {
            std::mt19937_64 rng(s);
            std::uniform_real_distribution<double> u(0.0, 1.0);
            pts.resize(f.count);
            for (auto& p : pts) p = {u(rng), u(rng)};
            device = "host";
        } else {
            SampleOptions o;
            o.radius = f.rf;
            o.coverage = f.rc == f.rf ? 0.0 : f.rc;
            o.seed = s;
            o.backend = backend;
            o.hierarchy.steps = f.steps;
            const Sampling m = sample(o);
            device = m.device;
            pts.resize(m.size());
            for (std::size_t i = 0; i < m.size(); ++i) pts[i] = m.point(i);
        }
        sets.push_back(std::move(pts));
    }
    return sets;
}

std::string images(const std::string& stem, bool delaunay) {
    std::string html;
    for (const char* panel : {"points", "spectrum", "radial", "angles", "edges"}) {
        if (!delaunay && (std::string(panel) == "angles" || std::string(panel) == "edges")) continue;
        html += fmt::format("<a href=\"{0}-{1}.svg\"><img src=\"{0}-{1}.png\" width=\"320\"></a>\n", stem, panel);
    }
    return html;
}

}  // namespace

int run_figures(const FiguresOptions& o) {
    if (o.sets < 1 || o.sets > 100) throw Error(fmt::format("--sets must be 1 to 100 (got {})", o.sets));
    const Backend backend = parse_backend(o.device);
    ReportDir dir(o.out);
    Json all = Json::object();
    std::string body;
    for (const Figure& f : kFigures) {
        std::string device;
        const Sets sets = make_sets(f, o.sets, backend, device);
        SpectrumOptions so;
        so.half_width = 0;
        so.backend = backend;
        const std::optional<RadiiGiven> radii = f.rf > 0 ? std::optional(RadiiGiven{f.rf, f.rc}) : std::nullopt;
        const std::string stem = fmt::format("figure{}", f.id);
        Json j = analyse(sets, Box{}, radii, so, dir, stem, fmt::format("Figure {}", f.id));
        double sd = 0;
        for (std::size_t n : j["points_per_set"]) sd += std::pow(double(n) - j["n"].get<double>(), 2);
        sd = sets.size() > 1 ? std::sqrt(sd / double(sets.size() - 1)) : 0;
        j["paper_count"] = f.paper_count;
        j["sampler_device"] = device;
        std::string angle;
        if (radii)
            angle = fmt::format("<tr><td>smallest Delaunay angle</td><td>{:.2f} deg (bound {:.2f} deg)</td>"
                                "<td>{}</td></tr>\n",
                                j["min_angle_deg"].get<double>(), j["min_angle_bound_deg"].get<double>(),
                                *f.paper_note ? f.paper_note : "");
        body += fmt::format(
            "<h2>Figure {}: {}</h2>\n<table>\n<tr><th></th><th>vrpd</th><th>paper</th></tr>\n"
            "<tr><td>points</td><td>{:.1f} &plusmn; {:.1f} (mean &plusmn; sd over {} sets)</td><td>{}</td></tr>\n"
            "<tr><td>&delta;<sub>x</sub>, mean minimum distance</td><td>{:.3f}, {:.3f}</td><td></td></tr>\n{}"
            "</table>\n{}",
            f.id, f.title, j["n"].get<double>(), sd, sets.size(), f.paper_count, j["delta_x"].get<double>(),
            j["mean_min_distance"].get<double>(), angle, images(stem, radii.has_value()));
        if (std::string(f.id) == "4")
            body += "<h2>Figures 14 and 15: angle and edge-length histograms of uniform MPS</h2>\n"
                    "<p>Figure 4's Delaunay histograms above (figure4-angles, figure4-edges), with the bounds "
                    "of Propositions 1-2 marked.</p>\n";
        all[f.id] = j;
        std::cerr << fmt::format("vrpd: figure {}: {:.1f} points per set, delta_x {:.3f}\n", f.id,
                                 j["n"].get<double>(), j["delta_x"].get<double>());
    }
    body += sizing_figures(dir, backend, o.full, all);
    std::ofstream html(dir.path("index.html"));
    html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>vrpd: the paper's figures</title>\n"
            "<style>body{font-family:sans-serif;max-width:1400px;margin:auto}td,th{padding:2px 10px;"
            "text-align:left}</style></head><body>\n<h1>Variable radii Poisson-disk sampling: section 6 "
            "figures, regenerated by vrpd</h1>\n"
         << fmt::format("<p>Spectra averaged over {} sets per figure (PSA conventions: white noise reads 1). "
                        "Click a panel for its SVG.</p>\n",
                        o.sets)
         << body
         // On load the page says on its body whether every figure loaded: a headless browser's
         // dump of the DOM shows it (scripts/check-figures-page).
         << "<script>window.addEventListener('load', () => {\n"
            "  const bad = [...document.images].filter(i => !i.complete || i.naturalWidth === 0);\n"
            "  document.body.dataset.images = bad.length ? 'broken: ' + bad.map(i => i.getAttribute('src')).join(' ')\n"
            "                                            : 'all ' + document.images.length + ' loaded';\n"
            "});</script>\n</body></html>\n";
    html.close();
    if (!html) throw Error("cannot write index.html");
    write_json(dir.path("figures.json"), all);
    dir.commit();
    std::cout << fmt::format("figures, index.html and figures.json in {}\n", o.out);
    return 0;
}

}  // namespace vrpd::cli
