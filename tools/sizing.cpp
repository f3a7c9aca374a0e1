// `vrpd check --sizing EXPR --rule RULE`: a point file judged under a spatially varying radius
// (paper section 5): conflicts under the rule, coverage under the rule on a stated grid.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "cli_common.h"
#include "vrpd/io.h"
#include "vrpd/sizing.h"

namespace vrpd::cli {

int run_check_sizing(const CheckOptions& o) {
    if (o.radius || o.rf || o.rc) throw Error("give --sizing or radii, not both");
    const Sizing sizing = *parse_sizing(o.sizing);
    const SizingRule rule = sizing.rule;
    Box box;
    box.boundary = parse_boundary(o.boundary);
    parse_extent(o.extent, box);
    if (!(std::isfinite(box.width) && box.width > 0 && std::isfinite(box.height) && box.height > 0))
        throw Error("extent must be two finite numbers > 0");
    if (o.tolerance && !(*o.tolerance >= 0))
        throw Error(fmt::format("--tolerance must be >= 0 (got {})", *o.tolerance));
    // The field as vrpd sample tabulates it: the same r at each of its samples.
    if (!o.json.empty()) check_writable(o.json);
    const SizingField r = o.scale ? SizingField(sizing, box).scaled(*o.scale) : SizingField(sizing, box);
    // Scaled, each node is rounded again: r then lies within F + 2 lattice units of F times the
    // run's field (each interpolant rounds within 1, each scaled node within 1/2), which a
    // continuous hierarchy's births, exact at F times the run's field, do not follow.
    const double rounding = o.scale ? (*o.scale + 2) * r.quantum() : 0;
    const double tolerance =
        o.tolerance ? *o.tolerance : kDefaultTolerance * std::max(box.width, box.height) + rounding;
    const PointSet file = read_point_set(o.file);
    const std::vector<glm::dvec2>& points = file.points;
    const FieldStats f = r.stats();
    FieldSummary field{f.r_min, f.r_max, f.lipschitz, std::size_t(std::llround(std::sqrt(double(f.table_nodes))))};
    const SizingReport rep = check_sizing(points, std::cref(r), rule, box, tolerance, field);
    const double bound = rule_lipschitz_bound(rule);
    std::cout << fmt::format("{} points; r from {:.6g} to {:.6g} over the box, L {:.4g}, tabulated on {} nodes "
                             "within {:.3g} % of the source\n",
                             rep.points, rep.field.r_min, rep.field.r_max, rep.field.lipschitz, f.table_nodes,
                             100 * f.tabulation_error);
    // vrpd sample writes each sample's r: another r here means another field than the run's.
    const std::vector<double>* written = file.column("r");
    std::size_t differ = 0;
    if (written && !o.scale) {
        double most = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const double here = r(points[i]), there = (*written)[i];
            const double gap = std::abs(here - there) / here;
            if (gap > 1e-9) ++differ, most = std::max(most, gap);
        }
        if (differ)
            std::cout << fmt::format(
                "warning: the file's r column differs from this field's r at {} of {} points "
                "(by up to {:.3g} %): the run had other field options (--table-budget, "
                "--lipschitz, --extent, --boundary)?\n",
                differ, points.size(), 100 * most);
    }
    if (rep.field.lipschitz > bound)
        std::cout << fmt::format("warning: L {:.4g} exceeds the {} rule's bound {} (Table 1): its quality "
                                 "guarantees lapse\n",
                                 rep.field.lipschitz, sizing_rule_name(rule), bound);
    std::cout << fmt::format("conflicts under the {} rule (tolerance {:.3g}): {} pairs", sizing_rule_name(rule),
                             tolerance, rep.conflicts);
    if (rep.conflicts) std::cout << fmt::format(", the first points {} and {}", rep.first_a, rep.first_b);
    std::cout << "\n";
    const std::string worst = std::isfinite(rep.worst_ratio)
                                  ? fmt::format("is at {:.4f} of its covering radius", rep.worst_ratio)
                                  : std::string("is within no sample's reach");
    std::cout << fmt::format("coverage on a grid of spacing {:.4g} ({} nodes): {} uncovered; the worst node ({:.9g}, "
                             "{:.9g}) {}: {}\n",
                             rep.resolution, rep.grid_points, rep.uncovered, rep.worst_point.x, rep.worst_point.y,
                             worst, rep.uncovered ? "NOT maximal" : "maximal");
    std::cout << (rep.passed() ? "PASS" : "FAIL") << "\n";
    if (!o.json.empty()) {
        const nlohmann::json j{{"points", rep.points},
                               {"rule", sizing_rule_name(rule)},
                               {"scale", o.scale.value_or(1.0)},
                               {"r_min", f.r_min},
                               {"r_max", f.r_max},
                               {"lipschitz", f.lipschitz},
                               {"lipschitz_bound", bound},
                               {"table_nodes", f.table_nodes},
                               {"tabulation_error", f.tabulation_error},
                               {"r_column_differs", differ},
                               {"tolerance", tolerance},
                               {"conflicts", rep.conflicts},
                               {"first_conflict", {rep.first_a, rep.first_b}},
                               {"coverage_resolution", rep.resolution},
                               {"coverage_nodes", rep.grid_points},
                               {"uncovered", rep.uncovered},
                               {"worst_ratio", std::isfinite(rep.worst_ratio) ? rep.worst_ratio : -1.0},
                               {"worst_point", {rep.worst_point.x, rep.worst_point.y}},
                               {"passed", rep.passed()}};
        std::ofstream out(o.json);
        out << j.dump(2) << "\n";
        if (!out) throw Error("cannot write " + o.json);
    }
    return rep.passed() ? 0 : 1;
}

}  // namespace vrpd::cli
