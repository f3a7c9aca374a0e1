// Sizing fields (paper section 5): the expression language against direct evaluation, its errors
// with their positions, the field's range and Lipschitz constant, and the checker's four rules on
// hand-made pairs whose verdict each rule decides differently; an expression's kinks and its
// branches.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_support.h"
#include "support.h"
#include "vrpd/sizing.h"
#include "vrpd/verify.h"

using namespace vrpd;

TEST_CASE("sizing expressions evaluate as written", "[sizing]") {
    const Box box{2, 1, Boundary::Periodic};
    const struct {
        const char* text;
        double (*expected)(double x, double y);
    } cases[] = {
        {"0.001 + 0.3*x", [](double x, double) { return 0.001 + 0.3 * x; }},
        {"0.015 + (0.00015-0.015)*abs(sin(8*pi*d))",
         [](double x, double y) {
             return 0.015 + (0.00015 - 0.015) * std::abs(std::sin(8 * std::numbers::pi * std::hypot(x - 1, y - 0.5)));
         }},
        {"-2^2", [](double, double) { return -4.0; }},
        {"2^3^2", [](double, double) { return 512.0; }},  // right-associative
        {"1 - 2 - 3", [](double, double) { return -4.0; }},
        {"8 / 4 / 2", [](double, double) { return 1.0; }},
        {"clamp(x, 0.5, 1.5) + min(y, 0.25) * max(w, h)", [](double x, double y) {
             return std::clamp(x, 0.5, 1.5) + std::min(y, 0.25) * 2;
         }},
        {"sqrt(exp(log(x + 1))) * cos(y) + +1", [](double x, double y) {
             return std::sqrt(x + 1) * std::cos(y) + 1;
         }},
        {" 1e-3*(x+y) ", [](double x, double y) { return 1e-3 * (x + y); }},
    };
    for (const auto& c : cases) {
        const SizingExpression r(c.text);
        for (double x : {0.0, 0.3, 1.7})
            for (double y : {0.0, 0.6}) {
                INFO(c.text << " at (" << x << ", " << y << ")");
                CHECK(r(x, y, box) == Approx(c.expected(x, y)).epsilon(1e-14));
            }
    }
}

TEST_CASE("sizing expressions with constant operands folded: the doubles of the operations as written", "[sizing]") {
    // Operators on constants are folded into one value, and a constant operand of a binary
    // operator is taken from the step, on either side: each expected value below performs the
    // expression's operations in its order, so the results must be equal, not close.
    const Box box{2, 1, Boundary::Periodic};
    const struct {
        const char* text;
        double (*expected)(double x, double y, double d);
    } cases[] = {
        {"0.015 + (0.0015-0.015)*abs(sin(8*pi*d))",
         [](double, double, double d) {
             return 0.015 + (0.0015 - 0.015) * std::abs(std::sin((8 * std::numbers::pi) * d));
         }},
        {"2 - x/3 + 1/(y+1)", [](double x, double y, double) { return (2 - x / 3) + 1 / (y + 1); }},
        {"2^x + x^0.5 + min(0.3, x) + max(y, -0.1)",
         [](double x, double y, double) {
             return ((std::pow(2, x) + std::pow(x, 0.5)) + std::min(0.3, x)) + std::max(y, -0.1);
         }},
        {"clamp(x, 0.25, 2*0.5) + clamp(0.5, y, 1)",
         [](double x, double y, double) { return std::min(std::max(x, 0.25), 1.0) + std::min(std::max(0.5, y), 1.0); }},
        {"-(3) * sqrt(4) + exp(0) * x", [](double x, double, double) { return -6.0 + 1.0 * x; }},
        {"0.01 * 2 + 0", [](double, double, double) { return 0.01 * 2 + 0; }},
    };
    for (const auto& c : cases) {
        const SizingExpression r(c.text);
        for (double x : {0.0, 0.3, 1.7, 1.9999})
            for (double y : {0.0, 0.6, 0.123}) {
                INFO(c.text << " at (" << x << ", " << y << ")");
                const double dx = x - 1, dy = y - 0.5;
                CHECK(r(x, y, box) == c.expected(x, y, std::sqrt(dx * dx + dy * dy)));
            }
    }
}

TEST_CASE("sizing expressions evaluated over many points at once give each point's value", "[sizing]") {
    const Box box{2, 1, Boundary::Periodic};
    // 150 points: batches of 64 and a partial one; a NaN and an infinity pass through as they are.
    std::vector<double> x(150), y(150), out(150, -1);
    for (std::size_t i = 0; i < x.size(); ++i) {
        x[i] = 2.0 * double(i) / 149;
        y[i] = std::fmod(0.37 * double(i), 1.0);
    }
    for (const char* text :
         {"0.015 + (0.00015-0.015)*abs(sin(8*pi*d))", "clamp(x, 0.5, 1.5) + min(y, 0.25) * max(w, h)",
          "sqrt(exp(log(x + 1))) * cos(y) + -2^x", "log(x - 1) / (y - 0.37)", "0.02"}) {
        INFO(text);
        const SizingExpression r(text);
        r(x.data(), y.data(), out.data(), x.size(), box);
        for (std::size_t i = 0; i < x.size(); ++i) {
            const double one = r(x[i], y[i], box);
            INFO("point " << i << ": " << one << " against " << out[i]);
            CHECK(std::memcmp(&one, &out[i], sizeof one) == 0);
        }
    }
}

TEST_CASE("sizing expressions: malformed ones are refused with the place marked", "[sizing]") {
    const struct {
        const char* text;
        const char* message;
        std::size_t column;
    } bad[] = {
        {"0.01 + q*x", "unknown name 'q'", 8},
        {"(x + 1", "expected ')'", 7},
        {"x + ", "expected a number, a name or '('", 5},
        {"", "expected an expression", 1},
        {"x y", "unexpected 'y'", 3},
        {"min(x)", "min takes 2 arguments: expected ','", 6},
        {"sin x", "expected '(' after sin", 5},
        {"1.2.3", "unexpected '.'", 4},
        {"x # y", "unexpected '#'", 3},
    };
    for (const auto& b : bad) {
        INFO(b.text);
        try {
            SizingExpression r(b.text);
            FAIL("accepted");
        } catch (const Error& e) {
            const std::string m = e.what();
            CHECK(m.find(b.message) != std::string::npos);
            CHECK(m.find("at column " + std::to_string(b.column)) != std::string::npos);
            // The caret sits under that column, below the expression.
            const std::size_t last = m.rfind('\n');
            REQUIRE(last != std::string::npos);
            CHECK(m.substr(last + 1) == std::string(2 + b.column - 1, ' ') + "^");
        }
    }
    CHECK_THROWS_WITH(SizingExpression(std::string(5000, '1')), Catch::Contains("longer than 4096"));
    CHECK_THROWS_WITH(SizingExpression(std::string(100, '(') + "x" + std::string(100, ')')),
                      Catch::Contains("nested deeper than 64"));
    CHECK_THROWS_WITH(SizingExpression(std::string(100, '-') + "x"), Catch::Contains("nested deeper than 64"));
}

TEST_CASE("a field's range and Lipschitz constant, and a field not positive everywhere refused", "[sizing]") {
    const Box box{};
    const FieldSummary ramp = summarize_field(SizingExpression("0.001 + 0.3*x"), box);
    CHECK(ramp.r_min == Approx(0.001));
    CHECK(ramp.r_max == Approx(0.301));
    CHECK(ramp.lipschitz == Approx(0.3).epsilon(1e-9));
    CHECK(summarize_field(SizingExpression("0.02"), box).lipschitz == 0);
    CHECK_THROWS_WITH(summarize_field(SizingExpression("0.01 - x"), box), Catch::Contains("finite number > 0"));
    CHECK_THROWS_WITH(summarize_field(SizingExpression("log(x)"), box), Catch::Contains("r(0, 0) = -inf"));
    CHECK(rule_lipschitz_bound(SizingRule::Prior) == 0.5);
    CHECK(rule_lipschitz_bound(SizingRule::Smaller) == 1.0);
    CHECK_THROWS_WITH(parse_sizing_rule("largest"), Catch::Contains("prior, current, bigger or smaller"));
}

// Two points 0.08 apart where r = 0.05 + 0.2 x gives 0.07 at the left one and 0.086 at the right:
// prior and smaller judge by the smaller radius here, current and bigger by the larger, and the
// order of the two (which came first) decides prior against current.
TEST_CASE("check_sizing: the four rules decide a pair each their own way", "[sizing]") {
    const SizingExpression r("0.05 + 0.2*x");
    const Box box{1, 1, Boundary::Free};
    const std::vector<glm::dvec2> left_first{{0.1, 0.5}, {0.18, 0.5}}, right_first{{0.18, 0.5}, {0.1, 0.5}};
    auto conflicts = [&](const std::vector<glm::dvec2>& p, const char* rule) {
        return check_sizing(p, r, parse_sizing_rule(rule), box, 0).conflicts;
    };
    CHECK(conflicts(left_first, "prior") == 0);
    CHECK(conflicts(left_first, "current") == 1);
    CHECK(conflicts(right_first, "prior") == 1);
    CHECK(conflicts(right_first, "current") == 0);
    for (const auto& p : {left_first, right_first}) {
        CHECK(conflicts(p, "bigger") == 1);
        CHECK(conflicts(p, "smaller") == 0);
    }
    const SizingReport rep = check_sizing(left_first, r, SizingRule::Current, box, 0);
    CHECK(rep.first_a == 1);
    CHECK(rep.first_b == 2);
    CHECK(rep.uncovered > 0);  // two points do not cover the box
}

// At a constant field every rule is the uniform case: vrpd's own maximal sets pass, and a radius
// 10 % too large finds conflicts, 10 % too small finds holes.
TEST_CASE("check_sizing on uniform maximal sets: pass at their radius, fail either side", "[sizing]") {
    for (const Boundary boundary : {Boundary::Periodic, Boundary::Free}) {
        const Box box{1, 1, boundary};
        const Sampling s = sample(test::options(0.02, 3, Backend::Cpu, box));
        std::vector<glm::dvec2> p(s.size());
        for (std::size_t i = 0; i < s.size(); ++i) p[i] = s.point(i);
        for (SizingRule rule : {SizingRule::Prior, SizingRule::Current, SizingRule::Bigger, SizingRule::Smaller}) {
            INFO(sizing_rule_name(rule) << (boundary == Boundary::Free ? " free" : " periodic"));
            const SizingReport exact = check_sizing(p, SizingExpression("0.02"), rule, box, 2e-8);
            CHECK(exact.conflicts == 0);
            CHECK(exact.uncovered == 0);
            CHECK(exact.worst_ratio > 0.9);  // some node is near a hole's centre
            CHECK(check_sizing(p, SizingExpression("0.022"), rule, box, 2e-8).conflicts > 0);
            CHECK(check_sizing(p, SizingExpression("0.018"), rule, box, 2e-8).uncovered > 0);
        }
    }
}

// The coverage runs in bands of grid rows on the threads, joined in row order: the counts and the
// worst node (the first of the largest ratio, rows then columns) are the one-thread report's.
TEST_CASE("check_sizing gives one report on any number of threads", "[sizing]") {
    for (const Boundary boundary : {Boundary::Periodic, Boundary::Free}) {
        const Box box{1.5, 1, boundary};
        Sizing sizing;
        sizing.expression = "0.01 + 0.012*(1 + sin(2*pi*x/w))";
        sizing.rule = SizingRule::Smaller;
        SampleOptions o;
        o.box = box;
        o.seed = 7;
        o.backend = Backend::Cpu;
        o.sizing = sizing;
        const Sampling s = sample(o);
        std::vector<glm::dvec2> p(s.size());
        for (std::size_t i = 0; i < s.size(); ++i) p[i] = s.point(i);
        // The field 8 % larger than the sampled one (conflicts) and 8 % smaller (holes).
        for (const char* scaled :
             {"1.08*(0.01 + 0.012*(1 + sin(2*pi*x/w)))", "0.92*(0.01 + 0.012*(1 + sin(2*pi*x/w)))"})
            for (const SizingRule rule : {SizingRule::Prior, SizingRule::Bigger}) {
                const SizingExpression r(scaled);
                const FieldSummary field = summarize_field(r, box);
                auto judge = [&](unsigned threads) {
                    return check_sizing(
                        p, [&](glm::dvec2 q) { return r(q.x, q.y, box); }, rule, box, 1e-9, field, threads);
                };
                const SizingReport one = judge(1), three = judge(3);
                INFO(scaled << " " << sizing_rule_name(rule) << (boundary == Boundary::Free ? " free" : " periodic"));
                CHECK(one.conflicts + one.uncovered > 0);
                CHECK(three.conflicts == one.conflicts);
                CHECK(three.uncovered == one.uncovered);
                CHECK(three.worst_ratio == one.worst_ratio);
                CHECK(three.worst_point == one.worst_point);
            }
    }
}

TEST_CASE("check --sizing from the command line", "[sizing][cli]") {
    using test::cli;
    const auto dir = test::scratch();
    const std::string u = (dir / "uniform.csv").string();
    REQUIRE(cli("sample --radius 0.02 --seed 2 --device cpu -o " + u).code == 0);
    CHECK(cli("check " + u + " --sizing 0.02 --rule bigger").code == 0);
    // An image field, sampled and checked through the same options.
    const std::string pgm = (dir / "blob.pgm").string();
    {
        std::ofstream img(pgm, std::ios::binary);
        img << "P5\n32 32\n255\n";
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) img.put(char(std::min(255.0, 12.0 * std::hypot(x - 15.5, y - 15.5))));
    }
    const std::string stipple = (dir / "stipple.csv").string();
    const std::string image = " --sizing-image " + pgm + " --r-min 0.01 --r-max 0.04 --rule current --boundary free";
    REQUIRE(cli("sample" + image + " --seed 4 -o " + stipple).code == 0);
    // The file's r column is the run's field: another field (here a smaller one, which leaves
    // points uncovered) differs from it, which the report counts.
    const std::string differs = (dir / "differs.json").string();
    CHECK(cli("check " + stipple + image + " --json " + differs).code == 0);
    CHECK(nlohmann::json::parse(test::slurp(differs))["r_column_differs"] == 0);
    CHECK(cli("check " + stipple + image + " --lipschitz 0.01 --json " + differs).code == 1);
    CHECK(nlohmann::json::parse(test::slurp(differs))["r_column_differs"].get<int>() > 0);
    const std::string json = (dir / "sizing.json").string();
    REQUIRE(cli("check " + u + " --sizing \"0.02 + 0.01*x\" --rule smaller --boundary free --json " + json).code == 1);
    const auto j = nlohmann::json::parse(test::slurp(json));
    CHECK(j["rule"] == "smaller");
    CHECK(j["conflicts"].get<double>() > 0);
    CHECK(j["passed"] == false);
    CHECK(j["lipschitz"].get<double>() == Approx(0.01).epsilon(0.01));
    CHECK(cli("check " + u + " --sizing \"0.02 + 0.01*x\" --rule bigger").code == 1);
    const test::Run parse = cli("check " + u + " --sizing \"0.02 + q\" --rule prior");
    CHECK(parse.code == 2);
    CHECK(parse.err.find("unknown name 'q'") != std::string::npos);
    CHECK(parse.err.find("at column 8") != std::string::npos);
    CHECK(parse.err.find("\n  0.02 + q\n") != std::string::npos);
    for (const std::string& bad :
         {std::string("--sizing 0.02"), std::string("--sizing 0.02 --rule any"),
          std::string("--sizing 0.02 --rule prior --radius 0.02"), std::string("--rule prior --radius 0.02"),
          std::string("--sizing -1 --rule prior")}) {
        const test::Run r = cli("check " + u + " " + bad);
        INFO(bad << "\n" << r.err);
        CHECK(r.code == 2);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
}

TEST_CASE("Table 1 measured: Delaunay edges and angles within each rule's bounds, and its other columns", "[sizing]") {
    // A periodic field with L = 0.04 * 2 pi = 0.25, below every rule's bound.
    Sizing sizing;
    sizing.expression = "0.01 + 0.04*(1 + sin(2*pi*x))";
    const Box box{1, 1, Boundary::Periodic};
    const SizingField field(sizing, box);
    const double L = field.stats().lipschitz;
    REQUIRE(L == Approx(0.08 * std::numbers::pi).epsilon(1e-3));
    const FieldSummary summary{field.stats().r_min, field.stats().r_max, L, 0};
    const auto judge = [&](const std::vector<glm::dvec2>& p, SizingRule rule) {
        return check_sizing(p, std::cref(field), rule, box, 1e-9, summary);
    };
    for (const SizingRule rule : {SizingRule::Prior, SizingRule::Current, SizingRule::Bigger, SizingRule::Smaller}) {
        SampleOptions o;
        o.box = box;
        o.seed = 5;
        o.backend = Backend::Cpu;
        o.sizing = sizing;
        o.sizing->rule = rule;
        const Sampling s = sample(o);
        std::vector<glm::dvec2> p(s.size());
        for (std::size_t i = 0; i < s.size(); ++i) p[i] = s.point(i);
        const SizingQuality q = sizing_quality(p, s.local_radius, box);
        const bool half = rule == SizingRule::Prior || rule == SizingRule::Bigger;  // Max L 1/2, else 1
        const double edge_min = rule == SizingRule::Bigger ? 1 : 1 / (1 + L);
        const double edge_max = half ? 2 / (1 - 2 * L) : 2 / (1 - L);
        const double sin_min = half ? (1 - 2 * L) / 2 : (1 - L) / 2;
        INFO(sizing_rule_name(rule) << ": " << s.size() << " samples, edges " << q.edge_min << ".." << q.edge_max
                                    << " r, sin " << q.sin_min);
        REQUIRE(q.triangles > 1000);
        CHECK(q.edge_min >= edge_min * (1 - 1e-6));
        CHECK(q.edge_max <= edge_max);
        CHECK(q.sin_min >= sin_min);
        // Order independence: the symmetric rules hold in any order (here reversed); prior and
        // current have an order that breaks them (reversed, here).
        const std::vector<glm::dvec2> reversed(p.rbegin(), p.rend());
        if (rule == SizingRule::Bigger || rule == SizingRule::Smaller)
            CHECK(judge(reversed, rule).conflicts == 0);
        else
            CHECK(judge(reversed, rule).conflicts > 0);
        // Full coverage (every point within some sample's own r, i.e. prior's coverage): smaller
        // has it, bigger not. Conflict free (no sample inside another's own r, i.e. bigger's
        // conflicts in any order): bigger has it, smaller not.
        if (rule == SizingRule::Smaller) {
            CHECK(judge(p, SizingRule::Prior).uncovered == 0);
            CHECK(judge(p, SizingRule::Bigger).conflicts > 0);
        }
        if (rule == SizingRule::Bigger) CHECK(judge(p, SizingRule::Prior).uncovered > 0);
    }
}

TEST_CASE("an expression's kinks give its branches, one of which is its value at every point", "[field]") {
    const Box box{1.5, 1, Boundary::Periodic};
    std::mt19937_64 rng(7);
    std::vector<double> x(1000), y(1000);
    for (std::size_t i = 0; i < x.size(); ++i)
        x[i] = box.width * double(rng() % 4096) / 4096, y[i] = box.height * double(rng() % 4096) / 4096;
    // Each expression with the expressions of its branches, by mask (kink k is bit k, in program
    // order; a clamp's max, then its min).
    const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
        {"0.01 + 0.05*abs(x - 0.3)", {"0.01 + 0.05*(x - 0.3)", "0.01 + 0.05*(-(x - 0.3))"}},
        {"0.05 - 0.04*abs(sin(7*d))", {"0.05 - 0.04*sin(7*d)", "0.05 - 0.04*(-sin(7*d))"}},
        {"min(0.02, 0.01 + x*y)", {"0.02", "0.01 + x*y"}},
        {"max(0.3*x, 0.1*y) + 0.01", {"0.3*x + 0.01", "0.1*y + 0.01"}},
        {"0.02 + max(x - 0.5, 0)*0.1", {"0.02 + (x - 0.5)*0.1", "0.02 + 0*0.1"}},
        {"1/min(3*x + 1, 2)", {"1/(3*x + 1)", "1/2"}},
        {"clamp(0.01*(1 + sin(9*x*y)), 0.005, 0.015)", {"0.01*(1 + sin(9*x*y))", "0.005", "0.015", "0.015"}},
        {"0.01 + 0.05*abs(x - 0.7) + 0.02*abs(y - 0.6)",
         {"0.01 + 0.05*(x - 0.7) + 0.02*(y - 0.6)", "0.01 + 0.05*(-(x - 0.7)) + 0.02*(y - 0.6)",
          "0.01 + 0.05*(x - 0.7) + 0.02*(-(y - 0.6))", "0.01 + 0.05*(-(x - 0.7)) + 0.02*(-(y - 0.6))"}},
        {"min(abs(x - 0.5), 0.2) + 0.01", {"(x - 0.5) + 0.01", "-(x - 0.5) + 0.01", "0.2 + 0.01", "0.2 + 0.01"}},
    };
    for (const auto& [text, branches] : cases) {
        INFO(text);
        const SizingExpression e(text);
        REQUIRE(e.kinked());
        REQUIRE(std::size_t(1) << e.kinks() == branches.size());
        std::vector<double> plain(x.size()), taken(x.size()), forced(x.size()), expected(x.size());
        std::vector<std::uint8_t> mask(x.size());
        e(x.data(), y.data(), plain.data(), x.size(), box);
        e.taken(x.data(), y.data(), taken.data(), mask.data(), x.size(), box);
        // `taken`: the plain values, bit for bit, and the branch of the mask each point takes.
        std::vector<std::size_t> takes(branches.size(), 0);
        for (std::size_t i = 0; i < x.size(); ++i) {
            REQUIRE(std::memcmp(&taken[i], &plain[i], sizeof(double)) == 0);
            REQUIRE(mask[i] < branches.size());
            ++takes[mask[i]];
            const double branch = SizingExpression(branches[mask[i]])(x[i], y[i], box);
            REQUIRE(plain[i] == Approx(branch).epsilon(1e-12).margin(1e-15));
        }
        // Every branch is the plain value somewhere (a clamp's two kinks never take their second
        // branches both).
        for (std::size_t m = 0; m < branches.size(); ++m)
            if (!(text.starts_with("clamp") && m == 3)) CHECK(takes[m] > 0);
        // `forced`: each mask's branch at every point, the taken one the plain value.
        for (std::size_t m = 0; m < branches.size(); ++m) {
            const std::vector<std::uint8_t> all(x.size(), std::uint8_t(m));
            e.forced(x.data(), y.data(), forced.data(), all.data(), x.size(), box);
            const SizingExpression branch(branches[m]);
            branch(x.data(), y.data(), expected.data(), x.size(), box);
            for (std::size_t i = 0; i < x.size(); ++i) {
                REQUIRE(forced[i] == Approx(expected[i]).epsilon(1e-12).margin(1e-15));
                if (mask[i] == m) REQUIRE(forced[i] == plain[i]);
            }
        }
    }
    // No kink, or more than kMaxKinks: no branches.
    for (const std::string text :
         {"0.01 + 0.02*x", "0.01 + abs(-0.3)*x", "min(0.2, 0.3) + x",
          "0.1 + abs(x - 0.1) + abs(x - 0.2) + abs(x - 0.3) + abs(x - 0.4) + clamp(y, 0.1, 0.2) + min(x, y) + "
          "max(x, y)"}) {
        INFO(text);
        CHECK_FALSE(SizingExpression(text).kinked());
    }
    CHECK(SizingExpression(
              "0.1 + abs(x - 0.1) + abs(x - 0.2) + abs(x - 0.3) + clamp(y, 0.1, 0.2) + min(x, y) + max(x, y)")
              .kinks() == SizingExpression::kMaxKinks);
}
