// The sizing-field options of sample and check (cli_common.h, SizingArgs).
#include <cmath>
#include <ostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "cli_common.h"
#include "vrpd/sizing.h"

namespace vrpd::cli {

bool SizingArgs::given() const {
    return !expression.empty() || !image.empty() || !rule.empty() || !weighting.empty() || r_min || r_max ||
           lipschitz || table_budget;
}

std::optional<Sizing> parse_sizing(const SizingArgs& a) {
    if (!a.given()) return std::nullopt;
    if (a.expression.empty() == a.image.empty()) throw Error("give --sizing EXPR or --sizing-image FILE (one of them)");
    if (!a.image.empty() && !(a.r_min && a.r_max)) throw Error("--sizing-image needs --r-min and --r-max");
    if (a.image.empty() && (a.r_min || a.r_max)) throw Error("--r-min and --r-max go with --sizing-image");
    if (a.rule.empty()) throw Error("a sizing field needs --rule prior, current, bigger or smaller");
    Sizing s;
    s.expression = a.expression;
    s.image = a.image;
    s.r_min = a.r_min.value_or(0);
    s.r_max = a.r_max.value_or(0);
    s.rule = parse_sizing_rule(a.rule);
    if (a.lipschitz) {
        if (!(std::isfinite(*a.lipschitz) && *a.lipschitz >= 0))
            throw Error(fmt::format("--lipschitz must be a finite number >= 0 (got {})", *a.lipschitz));
        s.lipschitz = *a.lipschitz;
    }
    if (a.table_budget) {
        if (!(*a.table_budget >= 1 && *a.table_budget <= 1024))
            throw Error(fmt::format("--table-budget must be 1 to 1024 words a sample (got {})", *a.table_budget));
        s.table_budget = *a.table_budget;
    }
    if (a.weighting == "density")
        s.weighting = Weighting::Density;
    else if (!a.weighting.empty() && a.weighting != "uniform")
        throw Error(fmt::format("unknown weighting '{}': use uniform or density", a.weighting));
    return s;
}

void add_sizing_options(CLI::App& app, SizingArgs& a, bool weighting) {
    app.add_option("--sizing", a.expression,
                   "a sizing field r(x, y) (paper section 5), e.g. \"0.001 + 0.3*x\"; variables x y d w h pi");
    app.add_option("--sizing-image", a.image,
                   "a greyscale PNG or binary PGM sizing field: r = r-min + (r-max - r-min) grey, dark = dense");
    app.add_option("--r-min", a.r_min, "with --sizing-image: r at black");
    app.add_option("--r-max", a.r_max, "with --sizing-image: r at white");
    app.add_option("--lipschitz", a.lipschitz, "use the largest L-Lipschitz field below r");
    app.add_option("--rule", a.rule, "with a sizing field: prior, current, bigger or smaller (Table 1)");
    app.add_option("--table-budget", a.table_budget,
                   "table words a sample (default 32) that patches may add where the table strays from the "
                   "source (kinks, sharp bends): more brings it closer, at that memory; give check the same");
    if (weighting)
        app.add_option("--weighting", a.weighting,
                       "uniform (default: each sample uniform over the uncovered set) or density (1/r^2, Eq. 12)");
}

void print_field_summary(const Sampling& s, const Sizing& sizing, std::ostream& out, const std::string& run) {
    const FieldStats& f = s.field;
    out << fmt::format(
        "vrpd: {}{} samples, r {:.6g} to {:.6g}, rule {}, {} weighting; table of {} nodes within "
        "{:.3g} % of the source, L {:.4g}; {:.3f} s, {:.3g} points/s, {} rounds, {} darts, {:.1f} MiB "
        "of arrays, device {}{}\n",
        run, s.size(), f.r_min, f.r_max, sizing_rule_name(sizing.rule),
        sizing.weighting == Weighting::Density ? "density" : "uniform", f.table_nodes, 100 * f.tabulation_error,
        f.lipschitz, s.stats.seconds, double(s.size()) / s.stats.seconds, s.stats.rounds, s.stats.darts,
        double(s.stats.peak_bytes) / (1 << 20), s.device, s.choice.empty() ? "" : " (auto: " + s.choice + ")");
}

void print_field_warnings(const Sampling& s, const Sizing& sizing, std::ostream& out) {
    const FieldStats& f = s.field;
    const double bound = rule_lipschitz_bound(sizing.rule);
    // --lipschitz L makes the nodes L-Lipschitz; a bilinear cell is up to sqrt(2) times steeper
    // at a corner, and the rounding to lattice units adds under 1e-4: L = bound / sqrt(2), cut to
    // three decimals, keeps the table within the bound.
    if (f.lipschitz > bound)
        out << fmt::format(
            "vrpd: warning: the field's L {:.4g} exceeds the {} rule's bound {} (Table 1): its quality "
            "guarantees lapse (--lipschitz {:.3f} enforces it)\n",
            f.lipschitz, sizing_rule_name(sizing.rule), bound, std::floor(bound / std::sqrt(2.0) * 1000) / 1000);
    // A hierarchy's level at birth t has the field t S r, and its slope: about t S L.
    else if (!s.birth.empty() && f.lipschitz * s.hierarchy_start > bound)
        out << fmt::format(
            "vrpd: warning: the hierarchy's levels above t = {:.3g} have L past the {} rule's bound {} (t S L, "
            "{:.4g} at t = 1): their quality guarantees lapse\n",
            bound / (f.lipschitz * s.hierarchy_start), sizing_rule_name(sizing.rule), bound,
            f.lipschitz * s.hierarchy_start);
    if (f.tabulation_error > 0.001)
        out << fmt::format(
            "vrpd: warning: the table is {:.3g} % from the source somewhere (more than 0.1 %): at a kink or "
            "a jump (on a torus, a field that does not wrap) the lattice or the node budgets (the table's, "
            "and its patches' at kinks: --table-budget, {:g} words a sample) stopped its refinement\n",
            100 * f.tabulation_error, sizing.table_budget);
}

}  // namespace vrpd::cli
