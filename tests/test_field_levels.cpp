// Discrete hierarchies of a sizing field (paper sections 4 and 5): every level a prefix of the
// output, conflict-free and maximal under the rule at its field, S t times the final one on the
// same lattice; the same points on every host backend; a constant field's hierarchy is the
// one-radius hierarchy; bad options refused.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "cli_support.h"
#include "field_support.h"
#include "vrpd/hierarchy.h"

using namespace vrpd;
using namespace vrpd::test;

namespace {

SampleOptions levels(const std::string& expr, SizingRule rule, Boundary b, unsigned steps, double start) {
    SampleOptions o = field_options(expr, rule, b, 6);
    o.hierarchy = {steps, start};
    return o;
}

}  // namespace

TEST_CASE("a sizing field's hierarchy: each level a prefix, conflict-free and maximal at S t times the field",
          "[field][hierarchy]") {
    struct Field {
        const char* expression;
        Boundary boundary;
        unsigned steps;
        double start;
    };
    // S = K: scales K, K - 1, ..., 1; S = 3 over 4 steps: 3, 7/3, 5/3, 1.
    const Field fields[] = {{"0.004 + 0.012*x", Boundary::Free, 5, 0},
                            {"0.006 + 0.003*sin(2*pi*x)*cos(2*pi*y)", Boundary::Periodic, 4, 3}};
    for (const Field& f : fields)
        for (SizingRule rule : kRules)
            for (Weighting weighting : {Weighting::Uniform, Weighting::Density}) {
                INFO(f.expression << ", rule " << sizing_rule_name(rule) << ", weighting " << int(weighting));
                SampleOptions o = levels(f.expression, rule, f.boundary, f.steps, f.start);
                o.sizing->weighting = weighting;
                const Sampling s = sample(o);
                REQUIRE(s.birth.size() == s.size());
                const double start = f.start != 0 ? f.start : double(f.steps);
                CHECK(s.hierarchy_start == start);
                const SizingField field(*o.sizing, o.box);
                const Hierarchy h(points_of(s), s.birth, 1.0);
                const std::vector<double> births = h.levels();
                REQUIRE(births.size() == f.steps);
                std::size_t before = 0;
                for (const double t : births) {
                    const std::size_t n = h.count_at(t);
                    INFO("level t = " << t << ": " << n << " samples");
                    CHECK(n > before);
                    before = n;
                    std::vector<glm::dvec2> prefix = points_of(s);
                    prefix.resize(n);
                    const SizingField level = field.scaled(start * t);
                    // Its nodes rounded and r floored: within S t + 2 lattice units of S t r.
                    for (std::size_t i = 0; i < s.size(); i += 101)
                        CHECK(std::abs(level(s.point(i)) - start * t * field(s.point(i))) <=
                              (start * t + 2) * s.quantum);
                    const FieldStats fs = level.stats();
                    const SizingReport r = check_sizing(prefix, std::cref(level), rule, o.box, 1e-9,
                                                        {fs.r_min, fs.r_max, fs.lipschitz, 0});
                    CHECK(r.conflicts == 0);
                    CHECK(r.uncovered == 0);
                }
                // Each row's r is the final field's at the sample.
                for (std::size_t i = 0; i < s.size(); i += 97) CHECK(s.local_radius[i] == field(s.point(i)));
                if (weighting == Weighting::Density) continue;
                SampleOptions serial = o;
                serial.backend = Backend::Serial;
                const Sampling t = sample(serial);
                CHECK(t.lattice == s.lattice);
                CHECK(t.birth == s.birth);
            }
}

TEST_CASE("a constant field's hierarchy is the one-radius hierarchy, and bad hierarchies of a field are refused",
          "[field][hierarchy]") {
    const SampleOptions constant = levels("0.01", SizingRule::Bigger, Boundary::Periodic, 4, 0);
    SampleOptions uniform = test::options(0.01, 6, Backend::Cpu);
    uniform.hierarchy = {4, 0};
    const Sampling a = sample(constant), b = sample(uniform);
    CHECK(a.lattice == b.lattice);
    CHECK(a.birth == b.birth);

    auto refusal = [](const SampleOptions& o) {
        try {
            sample(o);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    const std::string ramp = "0.004 + 0.012*x";
    CHECK_THAT(refusal(levels(ramp, SizingRule::Prior, Boundary::Free, 1, 0)), Catch::Contains("2 to 1000 steps"));
    CHECK_THAT(refusal(levels(ramp, SizingRule::Prior, Boundary::Free, 4, 0.5)), Catch::Contains("start S must be"));
    SampleOptions continuous = field_options(ramp, SizingRule::Prior, Boundary::Free, 1);
    continuous.hierarchy = {0, 0.5, true};
    CHECK_THAT(refusal(continuous), Catch::Contains("start S must be"));
    continuous.hierarchy = {4, 0, true};
    CHECK_THAT(refusal(continuous), Catch::Contains("discrete (K steps) or continuous, not both"));
    continuous.hierarchy = {0, 0, true};
    continuous.initial = {{0.5, 0.5}};
    CHECK_THAT(refusal(continuous), Catch::Contains("give --from or --hierarchy, not both"));
    SampleOptions from = levels(ramp, SizingRule::Prior, Boundary::Free, 4, 0);
    from.initial = {{0.5, 0.5}};
    CHECK_THAT(refusal(from), Catch::Contains("give --from or --hierarchy, not both"));
    // r up to 0.1 on the torus: 10 times that passes half of it.
    CHECK(refusal(levels("0.06 + 0.04*sin(2*pi*x)", SizingRule::Smaller, Boundary::Periodic, 10, 0)) ==
          "the hierarchy's first step, at 10 times the field: its largest radius 1 is too large for a periodic box "
          "of 1 x 1: it must be < 0.5 (half the shorter side)");
    SampleOptions wide = field_options("0.06 + 0.04*sin(2*pi*x)", SizingRule::Smaller, Boundary::Periodic, 1);
    wide.hierarchy.continuous = true;  // S = 10 by default
    CHECK_THAT(refusal(wide), Catch::Contains("its largest radius 1 is too large for a periodic box"));
}

TEST_CASE("sample --sizing --hierarchy: levels a prefix by t, and a warning where S t L passes the rule's bound",
          "[field][hierarchy][cli]") {
    const std::string out = (scratch() / "field_levels.csv").string();
    // The ramp's L is 0.3, within bigger's 1/2; at S = 4 its levels above t = 0.417 are steeper.
    const Run steep =
        cli("sample --sizing \"0.005 + 0.3*x\" --rule bigger --boundary free --hierarchy discrete:4 -o " + out);
    CHECK(steep.code == 0);
    CHECK(steep.err.find("warning: the hierarchy's levels above t = 0.417 have L past the bigger rule's bound 0.5 "
                         "(t S L, 1.2 at t = 1)") != std::string::npos);
    // The level at t = 0.5 (S t = 2) passes check on the field scaled by 2, and its JSON says so.
    const std::string level = (scratch() / "field_level.csv").string(), json = (scratch() / "level.json").string();
    CHECK(cli("lod " + out + " --t 0.5 -o " + level).code == 0);
    CHECK(cli("check " + level + " --sizing \"0.005 + 0.3*x\" --rule bigger --boundary free --scale 2 --json " + json)
              .code == 0);
    CHECK(slurp(json).find("\"scale\": 2.0") != std::string::npos);
    const Run gentle =
        cli("sample --sizing \"0.005 + 0.1*x\" --rule bigger --boundary free --hierarchy discrete:4 -o " + out);
    CHECK(gentle.code == 0);
    CHECK(gentle.err.find("warning") == std::string::npos);
}
