// The vrpd command line: sample, lod, devices, bench; with the geometry target, check, analyze, plot,
// figures.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <malloc.h>
#include <optional>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "cli_common.h"
#ifdef VRPD_HAVE_GEOMETRY
#include <nlohmann/json.hpp>
#include "vrpd/verify.h"
#endif
#include "vrpd/hierarchy.h"
#include "vrpd/io.h"
#include "vrpd/vrpd.h"

namespace vrpd::cli {

Backend parse_backend(const std::string& name) {
    if (name == "auto") return Backend::Auto;
    if (name == "gpu") return Backend::Gpu;
    if (name == "cpu") return Backend::Cpu;
    if (name == "serial") return Backend::Serial;
    throw Error(fmt::format("unknown device '{}': use auto, gpu, cpu or serial", name));
}

const char* backend_name(Backend b) {
    switch (b) {
    case Backend::Auto: return "auto";
    case Backend::Gpu: return "gpu";
    case Backend::Cpu: return "cpu";
    case Backend::Serial: return "serial";
    }
    return "?";
}

Boundary parse_boundary(const std::string& name) {
    if (name == "periodic") return Boundary::Periodic;
    if (name == "free") return Boundary::Free;
    throw Error(fmt::format("unknown boundary '{}': use periodic or free", name));
}

HierarchyOptions parse_hierarchy(const std::string& text) {
    unsigned steps = 0;
    double start = 0;
    char tail = 0;
    if (text == "continuous") return {0, 0, true};
    if (text.rfind("continuous:", 0) == 0) {
        if (std::sscanf(text.c_str(), "continuous:%lf%c", &start, &tail) != 1 || !(start >= 1))
            throw Error(fmt::format("--hierarchy must be continuous or continuous:S with S >= 1 (got '{}')", text));
        return {0, start, true};
    }
    const int got = std::sscanf(text.c_str(), "discrete:%u:%lf%c", &steps, &start, &tail);
    if (text.rfind("discrete:", 0) != 0 || !(got == 1 || got == 2) || text.find('-') != std::string::npos)
        throw Error(fmt::format("--hierarchy must be discrete:K, discrete:K:S, continuous or continuous:S (got '{}')",
                                text));
    if (got == 2 && !(start >= 1)) throw Error(fmt::format("--hierarchy's S must be >= 1 (got '{}')", text));
    // 0 steps is the options' "no hierarchy": refused here, not read as a direct run.
    if (steps < 2) throw Error(fmt::format("--hierarchy discrete:K needs K >= 2 steps (got '{}')", text));
    return {steps, start};
}

std::optional<RadiiGiven> parse_radii(std::optional<double> radius, std::optional<double> rf,
                                      std::optional<double> rc) {
    if (!radius && !rf && !rc) return std::nullopt;
    if (radius && (rf || rc)) throw Error("give --radius R, or --rf Rf (and --rc Rc)");
    if (rc && !rf) throw Error("--rc needs --rf");
    for (const auto& [name, value] : {std::pair{"--radius", radius}, {"--rf", rf}, {"--rc", rc}})
        if (value && !(std::isfinite(*value) && *value > 0))
            throw Error(fmt::format("{} must be a finite number > 0 (got {})", name, *value));
    const RadiiGiven r = radius ? RadiiGiven{*radius, *radius} : RadiiGiven{*rf, rc ? *rc : *rf};
    if (r.rc < r.rf) throw Error(fmt::format("--rc must be >= --rf (got Rf {}, Rc {})", r.rf, r.rc));
    return r;
}

void parse_extent(const std::string& text, Box& box) {
    double w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%lf,%lf%c", &w, &h, &tail) != 2)
        throw Error(fmt::format("extent must be W,H (two numbers), got '{}'", text));
    box.width = w;
    box.height = h;
}

#ifdef VRPD_HAVE_GEOMETRY
// `vrpd check`: 0 pass, 1 conflicts or not maximal, 2 bad input.
int run_check(const CheckOptions& o) {
    if (o.sizing.given()) return run_check_sizing(o);
    if (o.scale) throw Error("--scale scales a sizing field: give --sizing or --sizing-image");
    Box box;
    box.boundary = parse_boundary(o.boundary);
    parse_extent(o.extent, box);
    const std::optional<RadiiGiven> given = parse_radii(o.radius, o.rf, o.rc);
    if (!given) throw Error("give --radius R, or --rf Rf (and --rc Rc)");
    Radii radii{given->rf, given->rc};
    if (o.tolerance && !(*o.tolerance >= 0))
        throw Error(fmt::format("--tolerance must be >= 0 (got {})", *o.tolerance));
    radii.tolerance = o.tolerance ? *o.tolerance : kDefaultTolerance * std::max(box.width, box.height);
    if (!o.json.empty()) check_writable(o.json);
    const bool tty = isatty(2);
    if (tty) std::cerr << "vrpd check: reading " << o.file << "\r" << std::flush;
    const std::vector<glm::dvec2> points = read_points(o.file);
    if (tty) std::cerr << "vrpd check: triangulating " << points.size() << " points\r" << std::flush;
    const Report r = verify(points, radii, box);
    if (tty) std::cerr << std::string(60, ' ') << "\r";
    std::cout << fmt::format("{} points, n*Rf^2/area {:.5f}\n", r.points, r.density);
    std::cout << fmt::format("minimum distance {:.9g} (Rf {}, tolerance {:.3g}): {} conflicting pairs\n",
                             r.min_distance, radii.inhibition, radii.tolerance, r.conflicts);
    std::cout << fmt::format("largest empty circle radius {:.9g} at ({:.9g}, {:.9g}); Rc {}: {}\n",
                             r.largest_empty_radius, r.largest_empty_centre.x, r.largest_empty_centre.y, radii.coverage,
                             r.maximal ? "maximal" : "NOT maximal");
    std::string edges_rc;
    if (radii.coverage != radii.inhibition)
        edges_rc = fmt::format(" = {:.4f}..{:.4f} Rc", r.min_edge / radii.coverage, r.max_edge / radii.coverage);
    const char* counted = box.boundary == Boundary::Free ? " (circumcentre in the box)" : "";
    if (r.triangles == 0)
        std::cout << fmt::format("Delaunay{}: no triangle counted\n", counted);
    else
        std::cout << fmt::format("Delaunay{}: {} triangles, angles {:.3f}..{:.3f} deg, edges {:.4f}..{:.4f} Rf{}\n",
                                 counted, r.triangles, r.min_angle_degrees, r.max_angle_degrees,
                                 r.min_edge / radii.inhibition, r.max_edge / radii.inhibition, edges_rc);
    std::cout << (r.passed() ? "PASS" : "FAIL") << "\n";
    if (!o.json.empty()) {
        nlohmann::json j{
            {"points", r.points},
            {"density", r.density},
            {"rf", radii.inhibition},
            {"rc", radii.coverage},
            {"tolerance", radii.tolerance},
            {"min_distance", r.min_distance},
            {"conflicts", r.conflicts},
            {"largest_empty_radius", r.largest_empty_radius},
            {"largest_empty_centre", {r.largest_empty_centre.x, r.largest_empty_centre.y}},
            {"maximal", r.maximal},
            {"triangles", r.triangles},
            {"triangles_counted", box.boundary == Boundary::Free ? "circumcentre in the box" : "all, once each"},
            {"min_angle_degrees", r.min_angle_degrees},
            {"max_angle_degrees", r.max_angle_degrees},
            {"angle_histogram", {{"bin_degrees", r.angles.bin_width}, {"counts", r.angles.counts}}},
            {"min_edge", r.min_edge},
            {"max_edge", r.max_edge},
            {"edge_histogram", {{"bin_rf", r.edges.bin_width}, {"counts", r.edges.counts}}},
            {"passed", r.passed()}};
        std::ofstream out(o.json);
        out << j.dump(2) << "\n";
        if (!out) throw Error("cannot write " + o.json);
    }
    return r.passed() ? 0 : 1;
}
#endif

// Flushes and closes standard output, so that a write or close error (a full disk) is an error
// too; returns `code` if all went out.
int finish_output(int code) {
    std::cout.flush();
    if (!std::cout) throw Error(fmt::format("cannot write standard output: {}", std::strerror(errno)));
    if (std::fclose(stdout) != 0) throw Error(fmt::format("cannot write standard output: {}", std::strerror(errno)));
    return code;
}

// SIGINT, SIGTERM and SIGHUP remove the temporary of a write in progress, then end the process
// as the signal would have.
void remove_partial_file_on_signals() {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        std::signal(sig, [](int s) {
            remove_partial_file();
            std::signal(s, SIG_DFL);
            std::raise(s);
        });
    }
}

}  // namespace vrpd::cli

int main(int argc, char** argv) {
    using namespace vrpd;
    cli::remove_partial_file_on_signals();
    // A run allocates and frees arrays of up to a few MiB in turn (a field table's drafts and
    // patches, each round's lists). glibc hands the heap's free top back to the system past
    // 128 KiB and grows it again for the next array, whose pages then fault again; a top kept
    // up to 32 MiB spares those faults.
    mallopt(M_TOP_PAD, 32 << 20);
    CLI::App app{"vrpd: maximal Poisson-disk sampling on Vulkan compute"};
    app.set_version_flag("--version", std::string("vrpd ") + version());
    app.require_subcommand(1);

    SampleOptions opt;
    std::string extent = "1,1", boundary = "periodic", device = "auto", output;
    auto* sample_cmd = app.add_subcommand("sample", "maximal Poisson-disk sampling of a box");
    double rf = 0, rc = 0;
    auto* radius_opt = sample_cmd->add_option("--radius,-r", opt.radius, "disk radius r (Rf = Rc = r)");
    auto* rf_opt = sample_cmd->add_option("--rf", rf, "inhibition radius Rf: no two samples closer (paper section 3)");
    auto* rc_opt = sample_cmd->add_option(
        "--rc", rc, "coverage radius Rc, 1.1 Rf <= Rc <= 4 Rf: every point within Rc of a sample");
    sample_cmd->add_option("--extent", extent, "box W,H (default 1,1)");
    sample_cmd->add_option("--boundary", boundary, "periodic (default) or free");
    // A seed is a whole number that fits 32 bits; anything else is refused in those words (a range
    // check would print its bounds as floating point).
    const CLI::Validator whole_seed(
        [](std::string& text) {
            std::uint64_t value = 0;
            const char* end = text.data() + text.size();
            const auto [at, ec] = std::from_chars(text.data(), end, value);
            return ec == std::errc() && at == end && value <= UINT32_MAX
                       ? std::string()
                       : "must be a whole number from 0 to 4294967295 (got " + text + ")";
        },
        "");
    sample_cmd->add_option("--seed", opt.seed, "random seed, 0 to 4294967295 (default 0)")->check(whole_seed);
    sample_cmd->add_option("--device", device,
                           "auto (default: a hardware GPU if present, else cpu), gpu (Vulkan, lavapipe included; "
                           "$VRPD_DEVICE picks the device), cpu or serial");
    sample_cmd->add_option("-o,--output", output, "FILE.csv or FILE.bin, or - for CSV to stdout (the default)");
    sample_cmd->add_option("--threads", opt.threads, "host threads for --device cpu (default: one per core)")
        ->check(CLI::Range(1u, 1024u));
    std::string hierarchy, from;
    sample_cmd->add_option("--hierarchy", hierarchy,
                           "discrete:K[:S]: K steps from S (default K) times the radii down to them; continuous[:S] "
                           "(default S 10): t lowered without steps; every sample with its birth t, every level a "
                           "prefix (paper section 4)");
    sample_cmd->add_option(
        "--from", from,
        "start from the samples of FILE (conflict-free at Rf, or under a sizing field's rule); output them first");
    cli::SizingArgs sizing;
    cli::add_sizing_options(*sample_cmd, sizing, true);
    std::uint32_t runs = 1;
    sample_cmd
        ->add_option("--runs", runs,
                     "N runs, seeds --seed to --seed + N - 1, each to the output with {seed} replaced by its "
                     "seed; a sizing field is tabulated once for all of them (default 1)")
        ->check(CLI::Range(1u, 4294967295u));
    sample_cmd->add_flag("--profile", opt.profile,
                         "also print where the time went: per phase (cpu, serial) or per kernel (gpu, device "
                         "timestamps)");

    std::string lod_file, lod_output = "-";
    std::optional<double> lod_t, lod_radius, lod_r0;
    auto* lod_cmd = app.add_subcommand("lod", "the prefix of a hierarchical sampling that is one of its levels");
    lod_cmd->add_option("file", lod_file, "point file with a t column, from sample --hierarchy")->required();
    lod_cmd->add_option("--t", lod_t, "the samples born at t or earlier");
    lod_cmd->add_option("--radius,-r", lod_radius, "the samples born at radius R or more (needs --r0)");
    lod_cmd->add_option("--r0", lod_r0, "Rf at t = 1: S times the final Rf (0.1 for --radius 0.01 --hierarchy "
                                        "discrete:10)");
    lod_cmd->add_option("-o,--output", lod_output, "FILE.csv or FILE.bin, or - for CSV to stdout (the default)");

    auto* devices_cmd = app.add_subcommand("devices", "list Vulkan devices, and what --device auto picks");

#ifdef VRPD_HAVE_GEOMETRY
    cli::CheckOptions check;
    auto* check_cmd = app.add_subcommand("check", "verify a point file: conflicts, maximality, Delaunay quality");
    check_cmd->add_option("file", check.file, "point file (.csv or .bin)")->required();
    check_cmd->add_option("--radius,-r", check.radius, "Rf = Rc = R");
    check_cmd->add_option("--rf", check.rf, "inhibition radius Rf");
    check_cmd->add_option("--rc", check.rc, "coverage radius Rc (default Rf)");
    check_cmd->add_option("--extent", check.extent, "box W,H (default 1,1)");
    check_cmd->add_option("--boundary", check.boundary, "periodic (default) or free");
    check_cmd->add_option("--tolerance", check.tolerance,
                          "points' resolution: conflict below Rf - T, maximal below Rc + T (default 2e-8 of the "
                          "box's longer side: vrpd's CSV digits and lattice)");
    check_cmd->add_option("--json", check.json, "also write the report as JSON to FILE");
    cli::add_sizing_options(*check_cmd, check.sizing, false);
    check_cmd->add_option(
        "--scale", check.scale,
        "judge under the sizing field times F, as a hierarchy's level at birth t has it (F = S t); the "
        "default tolerance adds the scaled table's rounding, F + 2 lattice units");

    cli::AnalyzeOptions analyze;
    auto* analyze_cmd = app.add_subcommand(
        "analyze", "spectrum, radial power, spacing and (with radii) Delaunay histograms of point files");
    analyze_cmd->add_option("files", analyze.files, "point files (.csv or .bin), averaged as sets")->required();
    analyze_cmd->add_option("--out", analyze.out, "directory for the figures (PNG, SVG) and metrics.json")
        ->required();
    analyze_cmd->add_option("--radius,-r", analyze.radius, "Rf = Rc = R: also Delaunay histograms and bounds");
    analyze_cmd->add_option("--rf", analyze.rf, "inhibition radius Rf");
    analyze_cmd->add_option("--rc", analyze.rc, "coverage radius Rc (default Rf)");
    analyze_cmd->add_option("--extent", analyze.extent, "box W,H (default 1,1)");
    analyze_cmd->add_option("--boundary", analyze.boundary, "periodic (default) or free");
    analyze_cmd->add_option("--frequencies", analyze.frequencies,
                            "spectrum up to this many cycles per box side (default 2 sqrt(n), at least 32)");
    analyze_cmd->add_option("--device", analyze.device, "auto (default), gpu, or cpu for the spectrum");
    analyze_cmd->add_option("--threads", analyze.threads, "host threads (default: one per core)")
        ->check(CLI::Range(1u, 1024u));

    cli::PlotOptions plot;
    auto* plot_cmd = app.add_subcommand("plot", "draw a point file as a PNG or SVG");
    plot_cmd->add_option("file", plot.file, "point file (.csv or .bin)")->required();
    plot_cmd->add_option("-o,--output", plot.output, "FILE.png or FILE.svg")->required();
    plot_cmd->add_option("--radius,-r", plot.radius, "draw disks of radius r/2 (default: dots)");
    plot_cmd->add_flag("--disks", plot.disks,
                       "draw each point's disk of radius r/2, r from its r column (sample --sizing)");
    plot_cmd->add_option("--colour,--color", plot.colour, "colour by a column of the file, e.g. t or r");
    plot_cmd->add_option("--extent", plot.extent, "box W,H (default 1,1)");

    cli::FiguresOptions figures;
    auto* figures_cmd = app.add_subcommand("figures", "regenerate the paper's section 6 figures, with index.html");
    figures_cmd->add_option("--out", figures.out, "directory for the figures")->required();
    figures_cmd->add_option("--sets", figures.sets, "point sets per figure, seeds 1.. (default 10)");
    figures_cmd->add_option("--device", figures.device, "auto (default), gpu, cpu or serial");
    figures_cmd->add_flag("--full", figures.full, "Figure 16 at the paper's scale (about 2.2 M samples)");
#endif

    cli::BenchOptions bench;
    auto* bench_cmd = app.add_subcommand("bench", "time sampling per radius and device");
    bench_cmd->add_option("--radii", bench.radii, "one-radius rows: r on the unit torus (default 0.01 0.002 0.001)");
    bench_cmd->add_option("--fields", bench.fields,
                          "rows of sizing fields under each rule: ramp (0.001 + 0.3 x, free), sine (0.015 down to "
                          "0.0015, periodic)");
    bench_cmd->add_option("--rc", bench.coverage_radii, "two-radii rows: Rc (default 0.002)");
    bench_cmd->add_option("--rc-ratio", bench.coverage_ratio, "two-radii rows: Rf = Rc / ratio (default 2)");
    bench_cmd->add_option(
        "--hierarchy", bench.hierarchy_steps,
        "also K-step discrete hierarchies to each one-radius r and each field and rule, with count_at's time");
    bench_cmd->add_option("--devices", bench.devices, "gpu cpu serial (default all)");
    bench_cmd->add_option("--repeat", bench.repeat, "runs per case, best time kept (default 3)");
    bench_cmd->add_option("--json", bench.json, "also write the table as JSON to FILE");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "vrpd: error: " << e.what() << " (see vrpd --help)\n";
        return 2;
    }

    try {
        if (*sample_cmd) {
            opt.sizing = cli::parse_sizing(sizing);
            if (opt.sizing && radius_opt->count() + rf_opt->count() + rc_opt->count() > 0)
                throw Error("give a sizing field or radii, not both");
            if (!opt.sizing && radius_opt->count() == (rf_opt->count() + rc_opt->count() > 0))
                throw Error("give --radius R, or --rf Rf and --rc Rc (or a sizing field)");
            if (!opt.sizing && !radius_opt->count()) {
                if (!rf_opt->count() || !rc_opt->count())
                    throw Error("give both --rf and --rc (or --radius for Rf = Rc)");
                opt.radius = rf;
                opt.coverage = rc;
            }
            if (rc_opt->count() && !(std::isfinite(rc) && rc > 0))
                throw Error(fmt::format("--rc must be a finite number > 0 (got {})", rc));
            if (!hierarchy.empty()) opt.hierarchy = cli::parse_hierarchy(hierarchy);
            if (!from.empty()) opt.initial = read_points(from);
            opt.backend = cli::parse_backend(device);
            opt.box.boundary = cli::parse_boundary(boundary);
            cli::parse_extent(extent, opt.box);
            validate(opt);
            if (output.empty()) output = "-";
            cli::run_samples(opt, output, runs);
            return cli::finish_output(0);
        }
        if (*lod_cmd) {
            if (lod_t.has_value() == lod_radius.has_value()) throw Error("give --t T, or --radius R with --r0 R0");
            if (lod_radius && !lod_r0) throw Error("--radius needs --r0, the hierarchy's Rf at t = 1");
            if (lod_t && !(*lod_t > 0 && *lod_t <= 1))
                throw Error(fmt::format("--t must be in (0, 1] (got {})", *lod_t));
            if (lod_radius && !(std::isfinite(*lod_radius) && *lod_radius > 0))
                throw Error(fmt::format("--radius must be a finite number > 0 (got {})", *lod_radius));
            check_writable(lod_output);
            PointSet set = read_point_set(lod_file);
            const std::vector<double>* t = set.column("t");
            if (!t) throw Error(fmt::format("{} has no t column: make it with vrpd sample --hierarchy", lod_file));
            const Hierarchy h(set.points, *t, lod_r0.value_or(1.0));
            const std::size_t n = lod_t ? h.count_at(*lod_t) : h.count_at_radius(*lod_radius);
            set.points.resize(n);
            for (auto& column : set.values) column.resize(n);
            write_point_set(set, lod_output);
            std::cerr << fmt::format("vrpd: {} of {} samples (t >= {})\n", n, h.size(),
                                     n == 0 ? 1.0 : h.birth()[n - 1]);
            return cli::finish_output(0);
        }
        if (*devices_cmd) {
            try {
                for (const DeviceInfo& d : list_devices())
                    std::cout << fmt::format(
                        "{}: {} ({}, {}){}\n", d.index, d.name, d.type, d.driver,
                        d.usable ? "" : " - not usable: needs Vulkan 1.2, shaderInt64, bufferDeviceAddress");
            } catch (const Error& e) {
                std::cout << "no Vulkan device: " << e.what() << "\n";
            }
            const BackendChoice c = choose_backend(SampleOptions{});
            std::cout << fmt::format("--device auto: {} ({})\n", cli::backend_name(c.backend), c.reason);
            return cli::finish_output(0);
        }
        if (*bench_cmd) return cli::finish_output(cli::run_bench(bench));
#ifdef VRPD_HAVE_GEOMETRY
        if (*check_cmd) return cli::finish_output(cli::run_check(check));
        if (*analyze_cmd) return cli::finish_output(cli::run_analyze(analyze));
        if (*plot_cmd) return cli::finish_output(cli::run_plot(plot));
        if (*figures_cmd) return cli::finish_output(cli::run_figures(figures));
#endif
    } catch (const Error& e) {
        std::cerr << "vrpd: error: " << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        std::cerr << "vrpd: error: out of host memory\n";
        return 2;
    } catch (const std::exception& e) {  // from the standard library (I/O, filesystem): still one line
        std::cerr << "vrpd: error: " << e.what() << "\n";
        return 2;
    }
    return 0;
}
