// `vrpd sample`'s runs: each seed's sampling, written and summarized.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli_common.h"
#ifdef VRPD_HAVE_GEOMETRY
#include "vrpd/continuous.h"
#endif
#include "vrpd/io.h"
#include "vrpd/sizing.h"
#include "vrpd/vrpd.h"

namespace vrpd::cli {
namespace {

// The phases' times, longest first, and the rest of the run's wall time (setup, host work
// between phases, submits, read-backs).
void print_profile(const SamplingStats& stats, std::ostream& out) {
    std::vector<PhaseTime> phases = stats.profile;
    std::stable_sort(phases.begin(), phases.end(),
                     [](const PhaseTime& a, const PhaseTime& b) { return a.seconds > b.seconds; });
    double timed = 0.0;
    out << fmt::format("vrpd: profile, {:.3f} s in all\n  {:<18} {:>9} {:>7} {:>7}\n", stats.seconds, "phase",
                       "seconds", "share", "calls");
    for (const PhaseTime& p : phases) {
        timed += p.seconds;
        out << fmt::format("  {:<18} {:9.3f} {:6.1f}% {:7}\n", p.name, p.seconds, 100.0 * p.seconds / stats.seconds,
                           p.calls);
    }
    const double rest = std::max(0.0, stats.seconds - timed);
    out << fmt::format("  {:<18} {:9.3f} {:6.1f}%\n", "(outside phases)", rest, 100.0 * rest / stats.seconds);
    if (stats.round_trips > 0)
        out << fmt::format("  host round trips: {}, {:.1f} per level ({} levels, {} rounds)\n", stats.round_trips,
                           double(stats.round_trips) / std::max(1u, stats.levels), stats.levels, stats.rounds);
}

// The output of the run with `seed`: `pattern` with each "{seed}" replaced by it.
std::string output_for(const std::string& pattern, std::uint32_t seed) {
    static const std::string mark = "{seed}";
    std::string name = pattern;
    for (std::size_t at = name.find(mark); at != std::string::npos; at = name.find(mark, at)) {
        const std::string digits = std::to_string(seed);
        name.replace(at, mark.size(), digits);
        at += digits.size();
    }
    return name;
}

// A continuous hierarchy, built on the geometry target.
Sampling continuous(const SampleOptions& options) {
#ifdef VRPD_HAVE_GEOMETRY
    return continuous_hierarchy(options);
#else
    (void)options;
    throw Error("continuous hierarchies need the geometry target (CGAL); this vrpd is built without it");
#endif
}

}  // namespace

// Runs of one sizing field share its table, tabulated once before the first.
void run_samples(SampleOptions o, const std::string& output, std::uint32_t runs) {
    if (runs > 1 && output.find("{seed}") == std::string::npos)
        throw Error(
            fmt::format("--runs {} writes a file a seed: give an output with {{seed}} in its name, e.g. "
                        "-o points_{{seed}}.csv",
                        runs));
    if (std::uint64_t(o.seed) + runs - 1 > UINT32_MAX)
        throw Error(fmt::format("--seed {} with --runs {}: the last seed would pass 4294967295", o.seed, runs));
    const std::uint32_t first = o.seed;
    for (std::uint32_t k = 0; k < runs; ++k) check_writable(output_for(output, first + k));
    std::optional<SizingField> field;
    if (o.sizing && runs > 1) {
        const auto start = std::chrono::steady_clock::now();
        field.emplace(o);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::cerr << fmt::format(
            "vrpd: the field tabulated once for {} runs in {:.3f} s (the runs' times leave it out)\n", runs, seconds);
    }
    for (std::uint32_t k = 0; k < runs; ++k) {
        o.seed = first + k;
        const Sampling s = field ? sample(o, *field) : o.hierarchy.continuous && !o.sizing ? continuous(o) : sample(o);
        write_points(s, output_for(output, o.seed));
        const std::string run = runs > 1 ? fmt::format("seed {}: ", o.seed) : "";
        if (o.sizing) {
            print_field_summary(s, *o.sizing, std::cerr, run);
            if (k == 0) print_field_warnings(s, *o.sizing, std::cerr);  // the field's, said once
        } else {
            std::cerr << fmt::format(
                "vrpd: {}{} samples, n*{}^2/area {:.5f}, {:.3f} s, {:.3g} points/s, {} levels, {} darts, {:.1f} MiB "
                "of arrays, device {}{}\n",
                run, s.size(), s.coverage == s.radius ? "r" : "Rf",
                double(s.size()) * s.radius * s.radius / (s.box.width * s.box.height), s.stats.seconds,
                double(s.size()) / s.stats.seconds, s.stats.levels, s.stats.darts,
                double(s.stats.peak_bytes) / (1 << 20), s.device, s.choice.empty() ? "" : " (auto: " + s.choice + ")");
        }
        if (o.profile) print_profile(s.stats, std::cerr);
    }
}

}  // namespace vrpd::cli
