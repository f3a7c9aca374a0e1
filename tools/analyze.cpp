// `vrpd analyze`, `vrpd plot` and `vrpd figures`: the paper's section 6 analysis of point files,
// and its figures regenerated with vrpd's samplers.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <cstring>
#include <unistd.h>

#include <fmt/format.h>

#include "cli_common.h"
#include "report.h"
#include "vrpd/analysis.h"
#include "vrpd/figures.h"
#include "vrpd/io.h"
#include "vrpd/verify.h"

namespace vrpd::cli {

namespace fs = std::filesystem;

ReportDir::ReportDir(const std::string& target) : target_(fs::absolute(target.empty() ? "." : target)) {
    if (!target_.has_filename()) target_ = target_.parent_path();  // "report/" is "report"
    if (fs::exists(target_) && !fs::is_directory(target_))
        throw Error(fmt::format("{} exists and is not a directory", target_.string()));
    const fs::path parent = target_.parent_path();
    std::string name = (parent / ".vrpd-report-XXXXXX").string();
    if (!::mkdtemp(name.data()))
        throw Error(fmt::format("cannot write in {}: {}", parent.string(), std::strerror(errno)));
    staging_ = name;
}

ReportDir::~ReportDir() {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
}

void ReportDir::commit() {
    fs::create_directories(target_);
    for (const auto& entry : fs::directory_iterator(staging_))
        fs::rename(entry.path(), target_ / entry.path().filename());
}

void write_json(const std::string& path, const Json& j) {
    std::ofstream out(path);
    out << j.dump(2) << "\n";
    out.close();
    if (!out) throw Error(fmt::format("cannot write {}", path));
}

Json analyse(const Sets& sets, const Box& box, std::optional<RadiiGiven> radii, SpectrumOptions spectrum_options,
             const ReportDir& dir, const std::string& stem, const std::string& name) {
    const bool tty = isatty(2);
    auto progress = [&](const std::string& what) {
        if (tty) std::cerr << fmt::format("\rvrpd: {}: {:<40}", name, what) << std::flush;
    };
    double mean_n = 0;
    for (const auto& s : sets) mean_n += double(s.size()) / double(sets.size());
    if (spectrum_options.half_width == 0)
        spectrum_options.half_width = std::clamp(int(std::ceil(2 * std::sqrt(mean_n))), 32, 1024);
    progress("spectrum");
    const Spectrum spectrum = periodogram(sets, box, spectrum_options);
    const RadialPower radial = radial_power(spectrum);
    progress("spacing");
    Json j;
    j["sets"] = sets.size();
    j["n"] = mean_n;
    Json per_set = Json::array(), radial_json = Json::array(), anisotropy = Json::array();
    double delta = 0, delta_min = INFINITY, mean_min = 0;
    for (const auto& s : sets) {
        per_set.push_back(s.size());
        const Spacing sp = spacing(s, box);
        delta += sp.delta_x / double(sets.size());
        delta_min = std::min(delta_min, sp.delta_x);
        mean_min += sp.mean_min_distance / double(sets.size());
    }
    for (std::size_t i = 0; i < radial.power.size(); ++i) {
        radial_json.push_back({radial.frequency[i], radial.power[i]});
        anisotropy.push_back({radial.frequency[i], std::isfinite(radial.anisotropy_db[i])
                                                       ? Json(radial.anisotropy_db[i])
                                                       : Json(nullptr)});
    }
    j["points_per_set"] = per_set;
    j["delta_x"] = delta;
    j["delta_x_min"] = delta_min;
    j["mean_min_distance"] = mean_min;
    j["radial_power"] = radial_json;
    j["anisotropy_db"] = anisotropy;
    j["spectrum"] = {{"half_width", spectrum.half_width},
                     {"backend", backend_name(spectrum.backend)},
                     {"device", spectrum.device}};

    progress("figures");
    const std::string sets_note = sets.size() == 1 ? "" : fmt::format(", {} sets", sets.size());
    figures::PointStyle style;
    if (radii) style.disk_radius = radii->rf / 2;
    figures::plot_points(dir.path(stem + "-points"), sets.front(), box, style,
                         fmt::format("{}: {} points", name, sets.front().size()));
    figures::plot_spectrum(dir.path(stem + "-spectrum"), spectrum, name + " spectrum" + sets_note);
    figures::plot_radial(dir.path(stem + "-radial"), radial, name + " radial power" + sets_note);
    if (radii) {
        progress("Delaunay");
        Radii r{radii->rf, radii->rc, kDefaultTolerance * std::max(box.width, box.height)};
        Histogram angles{1.0, 180, std::vector<std::uint64_t>(180, 0)};
        Histogram edges{0.05, 200, std::vector<std::uint64_t>(200, 0)};
        double min_angle = 180, max_angle = 0, min_edge = INFINITY, max_edge = 0;
        std::uint64_t conflicts = 0, maximal = 0;
        for (const auto& s : sets) {
            const Report rep = verify(s, r, box);
            for (std::size_t i = 0; i < rep.angles.counts.size(); ++i) angles.counts[i] += rep.angles.counts[i];
            for (std::size_t i = 0; i < rep.edges.counts.size(); ++i) edges.counts[i] += rep.edges.counts[i];
            if (rep.triangles > 0) {
                min_angle = std::min(min_angle, rep.min_angle_degrees);
                max_angle = std::max(max_angle, rep.max_angle_degrees);
                min_edge = std::min(min_edge, rep.min_edge / r.inhibition);
                max_edge = std::max(max_edge, rep.max_edge / r.inhibition);
            }
            conflicts += rep.conflicts;
            maximal += rep.maximal ? 1 : 0;
        }
        // Propositions 1-2: edges within [Rf, 2 Rc], angles at least asin(Rf / (2 Rc)).
        const double angle_bound = std::asin(r.inhibition / (2 * r.coverage)) * 180 / std::numbers::pi;
        const double edge_bound = 2 * r.coverage / r.inhibition;
        j["rf"] = r.inhibition;
        j["rc"] = r.coverage;
        j["conflicts"] = conflicts;
        j["maximal_sets"] = maximal;
        j["min_angle_deg"] = min_angle;
        j["max_angle_deg"] = max_angle;
        j["min_angle_bound_deg"] = angle_bound;
        j["edge_ratio_min"] = min_edge;
        j["edge_ratio_max"] = max_edge;
        j["edge_ratio_bounds"] = {1.0, edge_bound};
        figures::plot_histogram(dir.path(stem + "-angles"), angles.counts, 1.0, 0, 180,
                                {{angle_bound, fmt::format("bound {:.1f} deg", angle_bound)},
                                 {min_angle, fmt::format("min {:.1f}", min_angle)}},
                                "Delaunay angle (degrees)", name + " angles" + sets_note);
        figures::plot_histogram(dir.path(stem + "-edges"), edges.counts, 0.05, 0, std::ceil(edge_bound + 0.5),
                                {{1.0, "Rf"}, {edge_bound, "2 Rc"}}, "Delaunay edge length / Rf",
                                name + " edge lengths" + sets_note);
    }
    if (tty) std::cerr << "\r" << std::string(80, ' ') << "\r" << std::flush;
    return j;
}

int run_analyze(const AnalyzeOptions& o) {
    Box box;
    box.boundary = parse_boundary(o.boundary);
    parse_extent(o.extent, box);
    const std::optional<RadiiGiven> radii = parse_radii(o.radius, o.rf, o.rc);
    if (o.frequencies != 0 && !(o.frequencies >= 1 && o.frequencies <= 1024))
        throw Error(fmt::format("--frequencies must be 1 to 1024 (got {})", o.frequencies));
    Sets sets;
    for (const std::string& f : o.files) sets.push_back(read_points(f));
    ReportDir dir(o.out);
    SpectrumOptions so;
    so.half_width = o.frequencies;
    so.backend = parse_backend(o.device);
    so.threads = o.threads;
    const Json j = analyse(sets, box, radii, so, dir, "analysis", fs::path(o.files.front()).stem().string());
    write_json(dir.path("metrics.json"), j);
    dir.commit();
    std::cout << fmt::format("{} sets, {:.1f} points each: delta_x {:.4f}, mean minimum distance {:.4f}{}\n",
                             sets.size(), j["n"].get<double>(), j["delta_x"].get<double>(),
                             j["mean_min_distance"].get<double>(),
                             radii ? fmt::format(", minimum angle {:.2f} deg (bound {:.2f})",
                                                 j["min_angle_deg"].get<double>(),
                                                 j["min_angle_bound_deg"].get<double>())
                                   : "");
    std::cout << fmt::format("figures and metrics.json in {}\n", o.out);
    return 0;
}

int run_plot(const PlotOptions& o) {
    Box box;
    parse_extent(o.extent, box);
    if (!(std::isfinite(o.radius) && o.radius >= 0))
        throw Error(fmt::format("--radius must be a finite number >= 0 (got {})", o.radius));
    const std::string ext = fs::path(o.output).extension().string();
    if (ext != ".png" && ext != ".svg")
        throw Error(fmt::format("-o must name a .png or .svg file (got '{}')", o.output));
    const PointSet set = read_point_set(o.file);
    figures::PointStyle style;
    style.disk_radius = o.radius / 2;
    if (o.disks) {
        if (o.radius > 0) throw Error("give --radius or --disks, not both");
        const std::vector<double>* r = set.column("r");
        if (!r) throw Error(fmt::format("{} has no r column for --disks (sample --sizing writes one)", o.file));
        for (std::size_t i = 0; i < r->size(); ++i) {
            if (!((*r)[i] > 0))
                throw Error(fmt::format("{}: point {} has r = {}; --disks needs every r > 0", o.file, i + 1, (*r)[i]));
            style.disk_radii.push_back((*r)[i] / 2);
        }
    }
    if (!o.colour.empty()) {
        const std::vector<double>* values = set.column(o.colour);
        if (!values) throw Error(fmt::format("{} has no column '{}' to colour by", o.file, o.colour));
        style.colour_by = *values;
        style.colour_name = o.colour;
    }
    const fs::path target = fs::absolute(o.output);
    ReportDir dir(target.parent_path().string());
    const std::string stem = target.stem().string();
    figures::plot_points(dir.path(stem), set.points, box, style,
                         fmt::format("{}: {} points", fs::path(o.file).filename().string(), set.points.size()));
    // Both forms are drawn; only the one asked for is kept.
    fs::remove(dir.path(stem + (ext == ".png" ? ".svg" : ".png")));
    dir.commit();
    return 0;
}

}  // namespace vrpd::cli
