// Continuous hierarchies of a sizing field (paper section 4.2 under section 5's rules): after the
// first level, each sample is the lattice point farthest from the earlier ones under the rule
// (the greatest g = min over them of distance / f), born at t = g / S; every prefix is
// conflict-free and maximal at its scale; the same points on every host backend; bad options
// refused.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "cli_support.h"
#include "field/table.h"
#include "field_support.h"
#include "vrpd/hierarchy.h"

using namespace vrpd;
using namespace vrpd::test;

namespace {

// g^2 as a fraction of integers.
struct Ratio {
    std::uint64_t num, den;
    bool operator<(const Ratio& o) const {
        return static_cast<unsigned __int128>(num) * o.den < static_cast<unsigned __int128>(o.num) * den;
    }
};

// g^2 at lattice point y against the first k samples, by brute force on the run's own table.
Ratio g2_at(const Sampling& s, const detail::FieldTable& t, const std::vector<std::uint32_t>& r, SizingRule rule,
            std::size_t k, glm::uvec2 y) {
    const std::uint32_t ry = t.radius(y);
    Ratio best{1, 0};
    for (std::size_t j = 0; j < k; ++j) {
        const std::uint64_t f = shared::rule_f(std::uint32_t(rule), r[j], ry);
        const Ratio g{shared::distance2(t.lattice, s.lattice[j], y), f * f};
        if (g < best) best = g;
    }
    return best;
}

// The radius of the largest circle centred in the torus that holds none of the first k samples:
// the greatest circumradius of three of them (unwrapped near the first) whose circle is empty.
double largest_empty_circle(const Sampling& s, const shared::Lattice& l, std::size_t k, double within) {
    const double ex = l.extent_x, ey = l.extent_y;
    auto offset = [&](glm::uvec2 from, glm::uvec2 to) {
        return glm::dvec2(shared::axis_offset(from.x, to.x, l.extent_x, 1),
                          shared::axis_offset(from.y, to.y, l.extent_y, 1));
    };
    double best = 0;
    for (std::size_t i = 0; i < k; ++i) {
        std::vector<glm::dvec2> near;  // within 2 `within` of sample i, relative to it
        for (std::size_t j = 0; j < k; ++j)
            if (const glm::dvec2 d = offset(s.lattice[i], s.lattice[j]); j != i && glm::length(d) < 2 * within)
                near.push_back(d);
        for (std::size_t a = 0; a < near.size(); ++a)
            for (std::size_t b = a + 1; b < near.size(); ++b) {
                const glm::dvec2 p = near[a], q = near[b];
                const double det = 2 * (p.x * q.y - p.y * q.x);
                if (std::abs(det) < 1e-9) continue;
                const double pp = glm::dot(p, p), qq = glm::dot(q, q);
                const glm::dvec2 c((q.y * pp - p.y * qq) / det, (p.x * qq - q.x * pp) / det);
                const double radius = glm::length(c);
                if (radius <= best || radius > within) continue;
                const glm::dvec2 at = glm::dvec2(s.lattice[i]) + c;
                const glm::uvec2 centre(std::uint32_t(std::fmod(std::fmod(std::round(at.x), ex) + ex, ex)),
                                        std::uint32_t(std::fmod(std::fmod(std::round(at.y), ey) + ey, ey)));
                bool empty = true;
                for (std::size_t j = 0; j < k && empty; ++j)
                    empty = glm::length(offset(centre, s.lattice[j])) >= radius - 2;
                if (empty) best = radius;
            }
    }
    return best;
}

}  // namespace

TEST_CASE("a field's continuous hierarchy: each sample the lattice point farthest from the earlier ones, at its t",
          "[field][hierarchy]") {
    struct Case {
        const char* expression;
        Boundary boundary;
        double start;
    };
    // A ramp on a free box, a smooth field on a torus, and a constant one (every rule the same).
    const Case cases[] = {{"0.02 + 0.04*x", Boundary::Free, 3},
                          {"0.03 + 0.012*sin(2*pi*x)*cos(2*pi*y)", Boundary::Periodic, 2.5},
                          {"0.035", Boundary::Periodic, 3}};
    std::mt19937_64 rng(7);
    for (const Case& c : cases)
        for (const SizingRule rule : kRules) {
            INFO(c.expression << ", rule " << sizing_rule_name(rule));
            SampleOptions o = field_options(c.expression, rule, c.boundary, 5);
            o.hierarchy.continuous = true;
            o.hierarchy.start = c.start;
            const Sampling s = sample(o);
            const double S = c.start;
            REQUIRE(s.birth.size() == s.size());
            CHECK(s.hierarchy_start == S);
            const std::size_t first = std::size_t(std::count(s.birth.begin(), s.birth.end(), 1.0));
            REQUIRE(first > 10);
            REQUIRE(s.size() > first + 100);
            CHECK(std::is_sorted(s.birth.rbegin(), s.birth.rend()));
            CHECK(s.birth.back() >= 1 / S);

            const SizingField field(*o.sizing, o.box);
            const detail::FieldTable& t = field.table();
            std::vector<std::uint32_t> r;
            for (const glm::uvec2 p : s.lattice) r.push_back(t.radius(p));
            // Each later sample is born at its exact g over S, and no lattice point is farther
            // from the samples before it: none of a grid over the box, of random points, or of
            // the points around it.
            std::uniform_int_distribution<std::uint32_t> ux(0, t.lattice.extent_x - 1), uy(0, t.lattice.extent_y - 1);
            for (std::size_t k = first; k < s.size(); ++k) {
                const Ratio gk = g2_at(s, t, r, rule, k, s.lattice[k]);
                if (s.birth[k] < 1)
                    CHECK(std::abs(std::sqrt(double(gk.num) / double(gk.den)) / S - s.birth[k]) < 1e-12);
                CHECK(!(gk < Ratio{1, 1}));
                if ((k - first) % 41 != 0) continue;
                std::vector<glm::uvec2> probes;
                for (std::uint32_t j = 0; j < 32; ++j)
                    for (std::uint32_t i = 0; i < 32; ++i)
                        probes.push_back({std::uint32_t(std::uint64_t(t.lattice.extent_x) * (2 * i + 1) / 64),
                                          std::uint32_t(std::uint64_t(t.lattice.extent_y) * (2 * j + 1) / 64)});
                for (int i = 0; i < 1000; ++i) probes.push_back({ux(rng), uy(rng)});
                const std::int64_t step = std::max<std::int64_t>(1, r[k] / 64);
                for (std::int64_t dy = -4; dy <= 4; ++dy)
                    for (std::int64_t dx = -4; dx <= 4; ++dx) {
                        const std::int64_t x = std::int64_t(s.lattice[k].x) + dx * step,
                                           y = std::int64_t(s.lattice[k].y) + dy * step;
                        if (x >= 0 && y >= 0 && x < t.lattice.extent_x && y < t.lattice.extent_y)
                            probes.push_back({std::uint32_t(x), std::uint32_t(y)});
                    }
                std::size_t farther = 0;
                for (const glm::uvec2 y : probes) farther += gk < g2_at(s, t, r, rule, k, y);
                CHECK(farther == 0);
            }
            // A constant field on the torus: g r is the largest empty circle's radius, to the
            // lattice (a point within 1 unit of its centre), found independently.
            if (std::string(c.expression) == "0.035")
                for (const std::size_t k : {first + 5, (first + s.size()) / 2, s.size() - 1}) {
                    const Ratio gk = g2_at(s, t, r, rule, k, s.lattice[k]);
                    const double found = std::sqrt(double(gk.num) / double(gk.den)) * r[k];
                    const double circle = largest_empty_circle(s, t.lattice, k, S * r[k] * 1.01);
                    CHECK(found <= circle + 2);
                    CHECK(found >= circle - 2);
                }
            // The prefix at t: conflict-free and maximal at S t times the field, to the lattice
            // (the first level ran on S r with its nodes rounded: S + 2 lattice units).
            const FieldStats fs = field.stats();
            const double tolerance = (S + 2) * s.quantum;
            for (const double at : {1.0, 0.8, 0.6, 1 / S}) {
                const double scale = S * at;
                const std::size_t n = Hierarchy(points_of(s), s.birth, 1.0).count_at(at);
                INFO("t = " << at << ": " << n << " samples");
                std::vector<glm::dvec2> prefix = points_of(s);
                prefix.resize(n);
                const SizingReport rep =
                    check_sizing(prefix, [&](glm::dvec2 p) { return scale * field(p); }, rule, o.box, tolerance,
                                 {scale * fs.r_min, scale * fs.r_max, scale * fs.lipschitz, 0});
                CHECK(rep.conflicts == 0);
                CHECK(rep.uncovered == 0);
            }
            CHECK(judge(s, *o.sizing).passed());
            SampleOptions serial = o;
            serial.backend = Backend::Serial;
            const Sampling u = sample(serial);
            CHECK(u.lattice == s.lattice);
            CHECK(u.birth == s.birth);
        }
}

TEST_CASE("sample --sizing --hierarchy continuous: a level by t passes check at its scale", "[field][hierarchy][cli]") {
    const std::string out = (scratch() / "field_continuous.csv").string(),
                      level = (scratch() / "field_continuous_level.csv").string();
    const Run run =
        cli("sample --sizing \"0.01 + 0.02*x\" --rule current --boundary free --hierarchy continuous:4 -o " + out);
    REQUIRE(run.code == 0);
    CHECK(slurp(out).rfind("x,y,t,r\n", 0) == 0);
    CHECK(cli("lod " + out + " --t 0.5 -o " + level).code == 0);
    CHECK(cli("check " + level + " --sizing \"0.01 + 0.02*x\" --rule current --boundary free --scale 2").code == 0);
    CHECK(cli("check " + out + " --sizing \"0.01 + 0.02*x\" --rule current --boundary free").code == 0);
}

TEST_CASE("check --scale allows the scaled table's rounding: a level whose last sample is born just past t passes",
          "[field][hierarchy][cli]") {
    // The prefix at t = 0.75 ends with a sample born at 0.7500025, 3.4e-6 past its conflict with
    // an earlier one at S t = 1.5: exact there, but within the scaled table's rounding of it.
    const std::string expr = "\"0.03 + (0.005-0.03)*abs(sin(3*pi*d))\"";
    const std::string out = (scratch() / "field_continuous_tight.csv").string(),
                      level = (scratch() / "field_continuous_tight_level.csv").string();
    REQUIRE(cli("sample --sizing " + expr +
                " --rule smaller --boundary free --hierarchy continuous:2 --seed 1 --device cpu -o " + out)
                .code == 0);
    const Run lod = cli("lod " + out + " --t 0.75 -o " + level);
    REQUIRE(lod.code == 0);
    CHECK(lod.err.find("t >= 0.7500025") != std::string::npos);
    const std::string check = "check " + level + " --sizing " + expr + " --rule smaller --boundary free --scale 1.5";
    CHECK(cli(check).code == 0);
    // Without the rounding, the pair counts as a conflict.
    const std::string json = (scratch() / "field_continuous_tight.json").string();
    CHECK(cli(check + " --tolerance 2e-8 --json " + json).code == 1);
    CHECK(slurp(json).find("\"conflicts\": 2,") != std::string::npos);
}
