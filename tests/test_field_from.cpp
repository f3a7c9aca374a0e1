// A sizing-field run from given samples (SampleOptions::initial): they come first, in their
// order, and the run completes them to a sampling maximal under the rule; a given set in conflict
// under the rule, in its order, is refused. A run from a field tabulated before (SizingField)
// gives the points of a run that tabulates it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_support.h"
#include "field/table.h"
#include "field_support.h"

using namespace vrpd;
using namespace vrpd::test;

namespace {

// The first n samples of s, as given samples.
std::vector<glm::dvec2> prefix(const Sampling& s, std::size_t n) {
    std::vector<glm::dvec2> p = points_of(s);
    p.resize(n);
    return p;
}

// The error a run of o gives (from `field` when one is given), or "accepted".
std::string refusal(const SampleOptions& o, const SizingField* field = nullptr) {
    try {
        if (field)
            sample(o, *field);
        else
            sample(o);
    } catch (const Error& e) {
        return e.what();
    }
    return "accepted";
}

}  // namespace

TEST_CASE("a field run from given samples: they come first, then a completion maximal under the rule", "[field]") {
    struct Field {
        const char* expression;
        Boundary boundary;
    };
    const Field fields[] = {{"0.005 + 0.03*x", Boundary::Free},
                            {"0.008 + 0.004*sin(2*pi*x)*cos(2*pi*y)", Boundary::Periodic}};
    for (const Field& f : fields) {
        // One table for every run (a run from it gives the points of a run that tabulates it).
        const SizingField field(*field_options(f.expression, SizingRule::Prior, f.boundary, 3).sizing,
                                {1, 1, f.boundary});
        for (SizingRule rule : kRules)
            for (Weighting weighting : {Weighting::Uniform, Weighting::Density}) {
                INFO(f.expression << ", rule " << sizing_rule_name(rule) << ", weighting " << int(weighting));
                SampleOptions o = field_options(f.expression, rule, f.boundary, 3);
                o.sizing->weighting = weighting;
                const Sampling full = sample(o, field);
                // A prefix of a run is conflict-free under the rule in its order (a prefix of the
                // acceptance order): completed with another seed, it is kept as it is.
                SampleOptions from = o;
                from.seed = 8;
                from.initial = prefix(full, full.size() / 4);
                const Sampling s = sample(from, field);
                REQUIRE(s.size() > from.initial.size());
                const auto n = std::ptrdiff_t(from.initial.size());
                CHECK(std::equal(full.lattice.begin(), full.lattice.begin() + n, s.lattice.begin()));
                CHECK(std::equal(full.local_radius.begin(), full.local_radius.begin() + n, s.local_radius.begin()));
                CHECK(s.lattice != full.lattice);
                const SizingReport r = judge(s, field, rule);
                CHECK(r.conflicts == 0);
                CHECK(r.uncovered == 0);
                if (weighting == Weighting::Density) continue;
                // The same points on the serial backend.
                from.backend = Backend::Serial;
                CHECK(sample(from, field).lattice == s.lattice);
                // A maximal set given whole gains nothing. The leaves one given sample covers are
                // dropped before the first round; the darts go to those that several cover.
                SampleOptions whole = o;
                whole.initial = points_of(full);
                const Sampling again = sample(whole, field);
                CHECK(again.lattice == full.lattice);
                CHECK(again.stats.darts < full.stats.darts / 2);
            }
    }
}

TEST_CASE("a field tabulated once samples as the runs that tabulate it, under each rule and weighting", "[field]") {
    for (const Boundary boundary : {Boundary::Free, Boundary::Periodic}) {
        SampleOptions o = field_options("0.025 + 0.0125*abs(sin(2*pi*x/w))", SizingRule::Prior, boundary, 6);
        o.box.width = 1.5;
        const SizingField field(*o.sizing, o.box);
        // The kinks' cells interpolate both branches of abs (kinked cells).
        CHECK(field.table().kink_count > 0);
        for (SizingRule rule : kRules)
            for (Weighting weighting : {Weighting::Uniform, Weighting::Density}) {
                INFO("boundary " << int(boundary) << ", rule " << sizing_rule_name(rule) << ", weighting "
                                 << int(weighting));
                o.sizing->rule = rule;
                o.sizing->weighting = weighting;
                o.backend = Backend::Cpu;
                const Sampling direct = sample(o), reused = sample(o, field);
                REQUIRE(direct.size() > 500);
                CHECK(reused.lattice == direct.lattice);
                CHECK(reused.local_radius == direct.local_radius);
                CHECK(reused.stats.darts == direct.stats.darts);
                CHECK(reused.field.tabulation_error == direct.field.tabulation_error);
                if (rule != SizingRule::Bigger) continue;
                // The host names its backend as the one-radius engines do.
                CHECK_THAT(direct.device, Catch::StartsWith("cpu (host, "));
                o.backend = Backend::Serial;
                const Sampling serial = sample(o, field);
                CHECK(serial.lattice == direct.lattice);
                CHECK(serial.device == "serial (host, one thread)");
            }
        // Two runs on one field at once, each on a thread of its own.
        o.sizing->rule = SizingRule::Current;
        o.backend = Backend::Cpu;
        o.threads = 1;
        std::vector<Sampling> both(2);
        std::vector<std::thread> runs;
        for (std::uint32_t k = 0; k < 2; ++k)
            runs.emplace_back([&, k] {
                SampleOptions mine = o;
                mine.seed = 20 + k;
                both[k] = sample(mine, field);
            });
        for (std::thread& t : runs) t.join();
        for (std::uint32_t k = 0; k < 2; ++k) {
            SampleOptions alone = o;
            alone.seed = 20 + k;
            CHECK(both[k].lattice == sample(alone).lattice);
        }
        o.threads = 0;
        // A hierarchy's levels scale the field it is given.
        o.hierarchy.steps = 3;
        o.backend = Backend::Cpu;
        const Sampling levels = sample(o, field);
        CHECK(levels.lattice == sample(o).lattice);
        CHECK(levels.birth.size() == levels.size());
    }
    // The field must be the options' sizing over their box; the rule and weighting are the run's.
    SampleOptions o = field_options("0.02 + 0.01*x", SizingRule::Smaller, Boundary::Free, 1);
    const SizingField field(*o.sizing, o.box);
    const std::string mismatch = "the field was not tabulated from the options' sizing and box";
    CHECK(refusal(o, &field) == "accepted");
    SampleOptions other = o;
    other.box.boundary = Boundary::Periodic;
    CHECK(refusal(other, &field) == mismatch);
    other = o;
    other.box.height = 0.5;
    CHECK(refusal(other, &field) == mismatch);
    other = o;
    other.sizing->expression = "0.02 + 0.011*x";
    CHECK(refusal(other, &field) == mismatch);
    other = o;
    other.sizing->table_budget = 16;
    CHECK(refusal(other, &field) == mismatch);
    other = o;
    other.sizing->lipschitz = 0.5;
    CHECK(refusal(other, &field) == mismatch);
    const SizingField doubled = field.scaled(2);
    CHECK(refusal(o, &doubled) == mismatch);
    other = o;
    other.sizing.reset();
    CHECK(refusal(other, &field) == "sampling a tabulated field needs the options' sizing (its rule and weighting)");
    other = o;
    other.threads = 100000;
    CHECK_THAT(refusal(other, &field), Catch::Contains("threads must be at most"));
}

TEST_CASE("given samples in conflict under a field's rule, in their order, are refused", "[field]") {
    // On r = 0.005 + 0.03 x: r(0.6) = 0.023, r(0.5775) = 0.022325, 0.0225 apart. The earlier
    // sample's r decides under prior: 0.6 first conflicts, 0.5775 first does not.
    const std::vector<glm::dvec2> larger_first = {{0.2, 0.2}, {0.6, 0.5}, {0.5775, 0.5}};
    const std::vector<glm::dvec2> smaller_first = {{0.2, 0.2}, {0.5775, 0.5}, {0.6, 0.5}};
    auto run = [&](SizingRule rule, const std::vector<glm::dvec2>& given) {
        SampleOptions o = field_options("0.005 + 0.03*x", rule, Boundary::Free, 1);
        o.initial = given;
        return refusal(o);
    };
    CHECK(run(SizingRule::Prior, larger_first) ==
          "given samples 2 (0.6, 0.5) and 3 (0.5775, 0.5) conflict under the prior rule on the run's lattice");
    CHECK(run(SizingRule::Prior, smaller_first) == "accepted");
    // current: the later sample's r; bigger conflicts both ways; smaller neither.
    CHECK(run(SizingRule::Current, larger_first) == "accepted");
    CHECK_THAT(run(SizingRule::Current, smaller_first), Catch::Contains("conflict under the current rule"));
    CHECK_THAT(run(SizingRule::Bigger, larger_first), Catch::Contains("conflict under the bigger rule"));
    CHECK_THAT(run(SizingRule::Bigger, smaller_first), Catch::Contains("conflict under the bigger rule"));
    CHECK(run(SizingRule::Smaller, larger_first) == "accepted");
    CHECK(run(SizingRule::Smaller, smaller_first) == "accepted");
    // Two samples in one leaf (1e-5 apart), across a torus's seam, and outside the box.
    auto refused = [](const std::vector<glm::dvec2>& given) {
        SampleOptions o = field_options("0.01 + 0.005*sin(2*pi*x)", SizingRule::Smaller, Boundary::Periodic, 1);
        o.initial = given;
        return refusal(o);
    };
    CHECK_THAT(refused({{0.3, 0.3}, {0.30001, 0.3}}), Catch::Contains("given samples 1 (0.3, 0.3) and 2"));
    CHECK_THAT(refused({{0.001, 0.5}, {0.998, 0.5}}), Catch::Contains("given samples 1 (0.001, 0.5) and 2"));
    CHECK(refused({{0.5, 1.0}}) == "given sample 1 (0.5, 1) is outside the box [0,1) x [0,1)");
}

TEST_CASE("sample --sizing --from: the given rows first and unchanged, a conflicting file one line and exit 2",
          "[field][cli]") {
    const std::filesystem::path dir = scratch();
    const std::string field = "--sizing \"0.01 + 0.02*x\" --rule prior --boundary free";
    const std::string full = (dir / "field_full.csv").string(), part = (dir / "field_part.csv").string(),
                      done = (dir / "field_done.csv").string();
    REQUIRE(cli("sample " + field + " --seed 4 -o " + full).code == 0);
    // The header and the first 200 rows.
    std::string text = slurp(full), head;
    std::size_t at = 0;
    for (int line = 0; line <= 200; ++line) at = text.find('\n', at) + 1;
    head = text.substr(0, at);
    std::ofstream(part) << head;
    REQUIRE(cli("sample " + field + " --seed 5 --from " + part + " -o " + done).code == 0);
    const std::string completed = slurp(done);
    CHECK(completed.compare(0, head.size(), head) == 0);
    CHECK(completed.size() > head.size());
    CHECK(cli("check " + done + " " + field).code == 0);
    // The 0.6 sample's r (0.022) exceeds the distance to the later one: a conflict under prior.
    const std::string bad = (dir / "field_bad.csv").string(), never = (dir / "field_never.csv").string();
    std::ofstream(bad) << "x,y\n0.6,0.5\n0.58,0.5\n";
    const Run r = cli("sample " + field + " --from " + bad + " -o " + never);
    CHECK(r.code == 2);
    CHECK(r.err == "vrpd: error: given samples 1 (0.6, 0.5) and 2 (0.58, 0.5) conflict under the prior rule on the "
                   "run's lattice\n");
    CHECK(!std::filesystem::exists(never));
}
