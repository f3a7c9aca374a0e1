// `vrpd bench`: best-of-N wall time, points/s, darts per sample and peak memory per (radii,
// device) on the unit torus: one radius r, two radii Rf < Rc (paper section 3), and with
// --hierarchy K, ten-step-style discrete hierarchies to each r (section 4), and with --fields,
// sizing fields under each rule (section 5), with --hierarchy their hierarchies too. Each case runs
// in a child process so its peak RSS is its own.
#include <chrono>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "vrpd/hierarchy.h"
#include "vrpd/io.h"
#include "vrpd/sizing.h"

namespace vrpd::cli {
namespace {

struct CaseResult {
    int ok;
    char error[240];
    char device[160];
    std::uint64_t samples;
    std::uint64_t darts;
    std::uint32_t levels;
    double best_seconds;
    double peak_bytes;   // the process's peak resident memory
    double array_bytes;  // the sampler's own arrays at their peak (SamplingStats::peak_bytes)
    double count_at_ns;  // hierarchy rows: mean time of Hierarchy::count_at over a million calls
    double tabulation;   // field rows: the field's tabulation, once for all repeats (in best_seconds)
};

struct Radii {
    double rf, rc;
    unsigned steps;  // a discrete hierarchy of this many steps (S = steps), or 0
    std::string field;  // a sizing field's name (kFields), with `rule`; rf and rc then unused
    SizingRule rule = SizingRule::Smaller;
};

// The sizing fields of --fields: Figure 11's ramp (free box) and a rectified sine (periodic).
struct NamedField {
    const char* name;
    const char* expression;
    Boundary boundary;
};
constexpr NamedField kFields[] = {
    {"ramp", "0.001 + 0.3*x", Boundary::Free},
    {"sine", "0.015 + (0.0015 - 0.015)*abs(sin(8*pi*d))", Boundary::Periodic},
};

SampleOptions options_for(const Radii& radii) {
    SampleOptions opt;
    for (const NamedField& f : kFields)
        if (radii.field == f.name) {
            opt.sizing = Sizing{};
            opt.sizing->expression = f.expression;
            opt.sizing->rule = radii.rule;
            opt.box.boundary = f.boundary;
            opt.hierarchy.steps = radii.steps;
            return opt;
        }
    opt.radius = radii.rf;
    opt.coverage = radii.rc;
    opt.hierarchy.steps = radii.steps;
    return opt;
}

CaseResult run_case(Radii radii, Backend backend, const BenchOptions& o) {
    CaseResult r{};
    try {
        SampleOptions opt = options_for(radii);
        opt.seed = o.seed;
        opt.backend = backend;
        r.best_seconds = 1e300;
        // A field is tabulated once, as the repeats of a run with several seeds would share it;
        // its time counts in the row's, and its own line shows it.
        std::optional<SizingField> field;
        if (opt.sizing) {
            const auto t0 = std::chrono::steady_clock::now();
            field.emplace(opt);
            r.tabulation = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        for (unsigned i = 0; i < o.repeat; ++i) {
            Sampling s = field ? sample(opt, *field) : sample(opt);
            if (radii.steps != 0 && i == 0) {
                const Hierarchy h(s);
                constexpr int kCalls = 1000000;
                std::size_t sum = 0;
                const auto t0 = std::chrono::steady_clock::now();
                for (int k = 0; k < kCalls; ++k) sum += h.count_at(double(k % 1000 + 1) / 1000.0);
                const auto t1 = std::chrono::steady_clock::now();
                r.count_at_ns = std::chrono::duration<double, std::nano>(t1 - t0).count() / kCalls;
                if (sum == 0) throw Error("count_at found no sample");
            }
            r.best_seconds = std::min(r.best_seconds, s.stats.seconds + r.tabulation);
            r.samples = s.size();
            r.darts = s.stats.darts;
            r.levels = s.stats.levels;
            r.array_bytes = double(s.stats.peak_bytes);
            std::snprintf(r.device, sizeof r.device, "%s", s.device.c_str());
        }
        rusage usage{};
        getrusage(RUSAGE_SELF, &usage);
        r.peak_bytes = double(usage.ru_maxrss) * 1024.0;
        r.ok = 1;
    } catch (const std::exception& e) {
        std::snprintf(r.error, sizeof r.error, "%s", e.what());
    }
    return r;
}

CaseResult run_in_child(Radii radii, Backend backend, const BenchOptions& o) {
    int fds[2];
    if (pipe(fds) != 0) throw Error("bench: pipe failed");
    pid_t pid = fork();
    if (pid < 0) throw Error("bench: fork failed");
    if (pid == 0) {
        close(fds[0]);
        CaseResult r = run_case(radii, backend, o);
        ssize_t ignored = write(fds[1], &r, sizeof r);
        (void)ignored;
        _exit(0);
    }
    close(fds[1]);
    CaseResult r{};
    ssize_t got = read(fds[0], &r, sizeof r);
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (got != ssize_t(sizeof r)) {
        r.ok = 0;
        std::snprintf(r.error, sizeof r.error, "the benchmark process died (status %d)", status);
    }
    return r;
}

}  // namespace

int run_bench(const BenchOptions& o) {
    if (o.repeat == 0) throw Error("--repeat must be >= 1");
    std::vector<Backend> backends;
    for (const auto& d : o.devices) backends.push_back(parse_backend(d));
    std::vector<Radii> cases;
    for (double r : o.radii) cases.push_back({r, r, 0});
    for (double rc : o.coverage_radii) cases.push_back({rc / o.coverage_ratio, rc, 0});
    if (o.hierarchy_steps != 0)
        for (double r : o.radii) cases.push_back({r, r, o.hierarchy_steps});
    for (const std::string& name : o.fields) {
        bool known = false;
        for (const NamedField& f : kFields) known = known || name == f.name;
        if (!known) throw Error(fmt::format("unknown field '{}': use ramp or sine", name));
        for (SizingRule rule : {SizingRule::Prior, SizingRule::Current, SizingRule::Bigger, SizingRule::Smaller}) {
            cases.push_back({0, 0, 0, name, rule});
            if (o.hierarchy_steps != 0) cases.push_back({0, 0, o.hierarchy_steps, name, rule});
        }
    }
    for (const Radii& c : cases) validate(options_for(c));
    if (!o.json.empty()) check_writable(o.json);

    nlohmann::json rows = nlohmann::json::array();
    std::cout << fmt::format("{:>17} {:>7} {:>9} {:>8} {:>9} {:>10} {:>8} {:>7} {:>9} {:>8} {:>8}  {}\n", "Rf/Rc",
                             "device", "samples", "n*Rc^2", "best s", "points/s", "us/point", "darts/n", "peak MiB",
                             "B/sample", "arrays/n", "device name");
    int failures = 0;
    for (const Radii& radii : cases) {
        std::string label =
            radii.rf == radii.rc ? fmt::format("{}", radii.rf) : fmt::format("{}/{}", radii.rf, radii.rc);
        if (radii.steps != 0) label += fmt::format(" h{}", radii.steps);
        if (!radii.field.empty())
            label = radii.field + " " + sizing_rule_name(radii.rule) +
                    (radii.steps != 0 ? fmt::format(" h{}", radii.steps) : std::string());
        for (Backend b : backends) {
            CaseResult c = run_in_child(radii, b, o);
            if (!c.ok) {
                std::cout << fmt::format("{:>17} {:>7}  error: {}\n", label, backend_name(b), c.error);
                rows.push_back({{"rf", radii.rf}, {"rc", radii.rc}, {"device", backend_name(b)}, {"error", c.error}});
                ++failures;
                continue;
            }
            const double pps = double(c.samples) / c.best_seconds;
            std::cout << fmt::format(
                "{:>17} {:>7} {:>9} {:>8} {:>9.3f} {:>10.3g} {:>8.2f} {:>7.2f} {:>9.1f} {:>8.1f} {:>8.1f}  {}\n", label,
                backend_name(b), c.samples,
                // A field has no one radius: its n r^2 is not a density.
                radii.field.empty() ? fmt::format("{:.5f}", double(c.samples) * radii.rc * radii.rc) : "-",
                c.best_seconds, pps, 1e6 / pps, double(c.darts) / double(c.samples), c.peak_bytes / (1 << 20),
                c.peak_bytes / double(c.samples), c.array_bytes / double(c.samples), c.device);
            if (radii.steps != 0)
                std::cout << fmt::format("{:>17} {:>7}  count_at: {:.1f} ns\n", "", "", c.count_at_ns);
            if (!radii.field.empty())
                std::cout << fmt::format(
                    "{:>17} {:>7}  tabulation {:.3f} s; sampling alone {:.3f} s, {:.3g} points/s\n", "", "",
                    c.tabulation, c.best_seconds - c.tabulation, double(c.samples) / (c.best_seconds - c.tabulation));
            std::cout.flush();
            rows.push_back({{"rf", radii.rf},
                            {"rc", radii.rc},
                            {"field", radii.field},
                            {"rule", sizing_rule_name(radii.rule)},
                            {"device", backend_name(b)},
                            {"device_name", c.device},
                            {"samples", c.samples},
                            {"darts", c.darts},
                            {"levels", c.levels},
                            {"best_seconds", c.best_seconds},
                            {"points_per_second", pps},
                            {"peak_rss_bytes", c.peak_bytes},
                            {"peak_array_bytes", c.array_bytes},
                            {"repeat", o.repeat}});
            if (!radii.field.empty()) rows.back()["tabulation_seconds"] = c.tabulation;
            if (radii.steps != 0) {
                rows.back()["hierarchy_steps"] = radii.steps;
                rows.back()["count_at_ns"] = c.count_at_ns;
            }
        }
    }
    if (!o.json.empty()) {
        std::ofstream out(o.json);
        out << nlohmann::json{{"benchmark", "unit torus, seed " + std::to_string(o.seed)}, {"rows", rows}}.dump(2)
            << "\n";
        if (!out) throw Error("cannot write " + o.json);
    }
    return failures ? 1 : 0;
}

}  // namespace vrpd::cli
