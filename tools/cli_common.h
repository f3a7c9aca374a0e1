// Small pieces shared by the vrpd CLI's subcommands.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "vrpd/vrpd.h"

namespace CLI {
class App;
}

namespace vrpd::cli {

Backend parse_backend(const std::string& name);
const char* backend_name(Backend b);
// "W,H" -> box extent; throws Error on anything else.
void parse_extent(const std::string& text, Box& box);
Boundary parse_boundary(const std::string& name);
// "discrete:K" or "discrete:K:S"; throws Error on anything else.
HierarchyOptions parse_hierarchy(const std::string& text);

// --radius R, or --rf Rf with an optional --rc Rc, as check and analyze take them.
struct RadiiGiven {
    double rf, rc;
};
// Throws Error for a mix of the two forms, --rc without --rf, a value not finite and > 0, or
// Rc < Rf; none given: nullopt.
std::optional<RadiiGiven> parse_radii(std::optional<double> radius, std::optional<double> rf,
                                      std::optional<double> rc);

// The resolution of vrpd's own files, relative to the box's longer side: CSV coordinates carry 9
// significant digits (5e-9 of the side at worst, so distances move by up to 1.5e-8), and the
// samples lie on a lattice of at most 2^30 steps across it (the largest empty circle may exceed
// r by half a step's diagonal).
inline constexpr double kDefaultTolerance = 2e-8;

// A sizing field's options as sample and check take them: --sizing EXPR or --sizing-image FILE
// with --r-min and --r-max, --lipschitz L, --rule R, and (sample) --weighting W.
struct SizingArgs {
    std::string expression, image, rule, weighting;
    std::optional<double> r_min, r_max, lipschitz, table_budget;
    bool given() const;  // any of them
};
// The Sizing they name, or nullopt if none is given; throws Error for a half-given field (an
// image without its radii, radii without an image, no --rule), an unknown rule or weighting.
std::optional<Sizing> parse_sizing(const SizingArgs& args);
// Registers the options on a subcommand (weighting: only where `weighting`).
void add_sizing_options(CLI::App& app, SizingArgs& args, bool weighting);
// `vrpd sample`: `runs` runs (>= 1) of `o`, seeds o.seed on, each written to `output` (or "-") with
// "{seed}" replaced by its seed, and summarized on stderr. Refuses, before the first run, an
// output without {seed} for several runs, seeds past 32 bits, and any output it cannot write.
void run_samples(SampleOptions o, const std::string& output, std::uint32_t runs);

// The summary line of a sizing-field run: n, the field's range, measured L, the tabulation error,
// time and memory; `run` names the run ("seed 7: ") where there are several.
void print_field_summary(const Sampling& s, const Sizing& sizing, std::ostream& out, const std::string& run = "");
// The field's warnings, a line each: L past the rule's bound (Table 1), at t = 1 or at a
// hierarchy's upper levels, and a table farther than 0.1 % from the source.
void print_field_warnings(const Sampling& s, const Sizing& sizing, std::ostream& out);

struct CheckOptions {
    std::string file;
    std::optional<double> radius, rf, rc;  // each as given, if given
    std::optional<double> tolerance;       // default: kDefaultTolerance
    std::string extent = "1,1", boundary = "periodic", json;
    SizingArgs sizing;                     // a sizing field and its rule, instead of radii
    std::optional<double> scale;           // the field times this (a hierarchy's level: S t)
};
// `vrpd check --sizing`: 0 pass, 1 conflicts or not covered, 2 bad input.
int run_check_sizing(const CheckOptions& options);

struct AnalyzeOptions {
    std::vector<std::string> files;
    std::string out;
    std::optional<double> radius, rf, rc;  // with radii: Delaunay histograms and their bounds
    std::string extent = "1,1", boundary = "periodic", device = "auto";
    int frequencies = 0;  // the spectrum's half width; 0: 2 sqrt(n), at least 32
    unsigned threads = 0;
};
int run_analyze(const AnalyzeOptions& options);

struct PlotOptions {
    std::string file, output, extent = "1,1", colour;
    double radius = 0;  // disks of radius r/2 (touching at distance r); 0: dots
    bool disks = false;  // each point's disk of radius r/2 from its r column
};
int run_plot(const PlotOptions& options);

struct FiguresOptions {
    std::string out, device = "auto";
    unsigned sets = 10;
    bool full = false;  // Figure 16 at the paper's smallest radius (about 2.2 M samples)
};
int run_figures(const FiguresOptions& options);

struct BenchOptions {
    std::vector<double> radii{0.01, 0.002, 0.001};
    std::vector<double> coverage_radii{0.002};  // two-radii rows: Rc, with Rf = Rc / coverage_ratio
    double coverage_ratio = 2.0;
    unsigned hierarchy_steps = 0;  // rows of discrete:K hierarchies to each one-radius r; 0: none
    std::vector<std::string> fields;  // rows of these sizing fields (ramp, sine) under each rule
    std::vector<std::string> devices{"gpu", "cpu", "serial"};
    unsigned repeat = 3;
    std::uint32_t seed = 1;
    std::string json;
};
int run_bench(const BenchOptions& options);

}  // namespace vrpd::cli
