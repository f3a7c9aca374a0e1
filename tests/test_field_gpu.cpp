// The sizing-field sampler's Vulkan kernels (vulkan/field_engine.cpp): the same points as the
// host's sampler, byte for byte, under every rule and weighting on both boundaries.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "field/table.h"
#include "field_support.h"
#include "vulkan/field_engine.h"

using namespace vrpd;
using test::field_options;

namespace {
// The samplings of o on the cpu backend and on the device.
std::pair<Sampling, Sampling> on_cpu_and_gpu(SampleOptions o) {
    o.backend = Backend::Cpu;
    Sampling cpu = sample(o);
    o.backend = Backend::Gpu;
    return {std::move(cpu), sample(o)};
}
}  // namespace

TEST_CASE("a sizing field samples the same points on gpu, cpu and serial under each rule and weighting",
          "[field][gpu]") {
    // A ramp on a free box (leaves of several sides, blocks outside the lattice at its edges), a
    // smooth field on a torus (searches across its seams), and a rectified sine on a 2 x 1 torus
    // (kinked table cells along its kinks, patches in its troughs, L 0.39: cover reaches grow well
    // past a sample's own r).
    struct Case {
        std::string expression;
        Box box;
    };
    for (const Case& c : {Case{"0.006 + 0.05*x", {1, 1, Boundary::Free}},
                          Case{"0.02 + 0.012*sin(2*pi*x)*cos(2*pi*y)", {1, 1, Boundary::Periodic}},
                          Case{"0.04 + (0.01 - 0.04)*abs(sin(4*pi*d))", {2, 1, Boundary::Periodic}}})
        for (const SizingRule rule : test::kRules)
            for (const Weighting w : {Weighting::Uniform, Weighting::Density}) {
                SampleOptions o = field_options(c.expression, rule, c.box.boundary, 11);
                o.box = c.box;
                o.sizing->weighting = w;
                INFO(c.expression << ", rule " << sizing_rule_name(rule) << ", "
                                  << (w == Weighting::Density ? "density" : "uniform"));
                const Sampling cpu = sample(o);
                o.backend = Backend::Gpu;
                const Sampling gpu = sample(o);
                o.backend = Backend::Serial;
                const Sampling serial = sample(o);
                REQUIRE(cpu.size() > 300);
                CHECK(gpu.backend == Backend::Gpu);
                CHECK(gpu.stats.rounds == cpu.stats.rounds);
                CHECK(gpu.stats.darts == cpu.stats.darts);
                CHECK(gpu.stats.levels == cpu.stats.levels);
                // A round waits on the device about three times: the darts' count, the throw with
                // the resolution and the ranking, and the emission with the refinement (its
                // scatter apart while the next list's worst case passes the memory peak);
                // setup, balancing and read-back add a few.
                CHECK(gpu.stats.round_trips <= 7 * gpu.stats.rounds / 2 + 12);
                REQUIRE(gpu.lattice == cpu.lattice);
                REQUIRE(serial.lattice == cpu.lattice);
                CHECK(gpu.local_radius == cpu.local_radius);
            }
    // Radii near half the torus: a cell may hold a sample's antipode, farther than its corners.
    SampleOptions o = field_options("0.4 + 0.05*sin(2*pi*x)", SizingRule::Bigger, Boundary::Periodic, 10);
    const auto [cpu, gpu] = on_cpu_and_gpu(o);
    REQUIRE(gpu.lattice == cpu.lattice);
    CHECK(test::judge(gpu, *o.sizing).uncovered == 0);
    // A triangle wave: kinked cells along each of its three kinks, which the device's kernels read
    // as the host does.
    SampleOptions wave = field_options("0.004 + 0.02*abs(abs(x - 0.5) - 0.25)", SizingRule::Smaller, Boundary::Free, 4);
    REQUIRE(detail::tabulate(*wave.sizing, wave.box).kink_count > 0);
    const auto [wave_cpu, wave_gpu] = on_cpu_and_gpu(wave);
    REQUIRE(wave_cpu.size() > 1000);
    CHECK(wave_gpu.lattice == wave_cpu.lattice);
}

TEST_CASE("darts crowding the leaves where r is large resolve on gpu as on cpu, within lavapipe's budget",
          "[field][gpu]") {
    // Radii 1 000 times apart: the first round's darts, of one intensity over the box, put
    // hundreds in one leaf near x = 1. A resolution that read every dart of a nearby leaf passed
    // lavapipe's budget here under both rules; the leaves' summaries read such a leaf in a step.
    for (const SizingRule rule : {SizingRule::Bigger, SizingRule::Smaller}) {
        SampleOptions o = field_options("0.0003 + 0.3*x", rule, Boundary::Free, 2);
        INFO("rule " << sizing_rule_name(rule));
        const auto [cpu, gpu] = on_cpu_and_gpu(o);
        REQUIRE(cpu.size() > 5000);
        CHECK(gpu.stats.darts == cpu.stats.darts);
        REQUIRE(gpu.lattice == cpu.lattice);
    }
}

TEST_CASE("a sample among leaves 50 times smaller stamps only those it may reach, within lavapipe's budget",
          "[field][gpu]") {
    // Under current a sample's cover reach grows to the largest r near it (up to 0.46 here), a
    // square that holds thousands of the leaves where r is 0.008. Stamping every one passed
    // lavapipe's budget; the search's gate enters only the blocks whose greatest r reaches the
    // sample.
    SampleOptions o = field_options("0.008 + 0.9*max(0, x - 0.5)", SizingRule::Current, Boundary::Free, 1);
    const auto [cpu, gpu] = on_cpu_and_gpu(o);
    REQUIRE(cpu.size() > 5000);
    CHECK(gpu.stats.darts == cpu.stats.darts);
    REQUIRE(gpu.lattice == cpu.lattice);
}

TEST_CASE("a sizing field's discrete hierarchy gives the same levels on gpu as on cpu under each rule",
          "[field][gpu]") {
    // Each level starts from the earlier levels' samples on its own table and leaves: the device
    // places them, drops the cells they cover and numbers its rounds on.
    for (const SizingRule rule : test::kRules) {
        SampleOptions o = field_options("0.012 + 0.006*sin(2*pi*x)*cos(2*pi*y)", rule, Boundary::Periodic, 3);
        o.hierarchy = {3, 2.5};
        o.sizing->weighting = rule == SizingRule::Bigger ? Weighting::Density : Weighting::Uniform;
        INFO("rule " << sizing_rule_name(rule));
        const auto [cpu, gpu] = on_cpu_and_gpu(o);
        REQUIRE(cpu.size() > 1000);
        CHECK(gpu.stats.rounds == cpu.stats.rounds);
        CHECK(gpu.stats.darts == cpu.stats.darts);
        REQUIRE(gpu.lattice == cpu.lattice);
        REQUIRE(gpu.birth == cpu.birth);
    }
}

TEST_CASE("a sizing field's continuous hierarchy gives the same samples and births on gpu as on cpu",
          "[field][gpu][hierarchy]") {
    // The first level runs on the device, the events after it on the host.
    for (const SizingRule rule : {SizingRule::Current, SizingRule::Bigger}) {
        SampleOptions o = field_options("0.02 + 0.008*sin(2*pi*x)*cos(2*pi*y)", rule, Boundary::Periodic, 4);
        o.hierarchy.continuous = true;
        o.hierarchy.start = 2;
        INFO("rule " << sizing_rule_name(rule));
        const auto [cpu, gpu] = on_cpu_and_gpu(o);
        REQUIRE(cpu.size() > 1000);
        CHECK(gpu.backend == Backend::Gpu);
        REQUIRE(gpu.lattice == cpu.lattice);
        REQUIRE(gpu.birth == cpu.birth);
    }
}

TEST_CASE("a sizing field completes given samples on gpu as on cpu, and refuses conflicting ones alike",
          "[field][gpu]") {
    // The given samples: the first 300 of a sampling under smaller, conflict-free under it (and
    // under bigger, whose f is larger: conflicting there).
    SampleOptions o = field_options("0.004 + 0.03*x", SizingRule::Smaller, Boundary::Free, 4);
    const Sampling base = sample(o);
    REQUIRE(base.size() > 600);
    for (std::size_t i = 0; i < 300; ++i) o.initial.push_back(base.point(i));
    o.seed = 5;
    const auto [cpu, gpu] = on_cpu_and_gpu(o);
    REQUIRE(gpu.lattice == cpu.lattice);
    CHECK(gpu.stats.rounds == cpu.stats.rounds);
    // The device samples a field tabulated before as the one it tabulates.
    SampleOptions reused = o;
    reused.backend = Backend::Gpu;
    CHECK(sample(reused, SizingField(*o.sizing, o.box)).lattice == gpu.lattice);
    auto refusal = [](SampleOptions options) {
        try {
            sample(options);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    o.sizing->rule = SizingRule::Bigger;
    o.backend = Backend::Gpu;
    const std::string on_gpu = refusal(o);
    o.backend = Backend::Cpu;
    CHECK_THAT(on_gpu, Catch::Contains("conflict under the bigger rule"));
    CHECK(on_gpu == refusal(o));
}

TEST_CASE("a field kernel's search past its step budget stops the run with one line naming the device",
          "[field][gpu]") {
    // The budget lavapipe needs (its loops end after 65 535 passes) cut to 40 steps: the first
    // round's searches pass it, and the run must say so rather than give other points.
    const SampleOptions o = field_options("0.01 + 0.05*x", SizingRule::Bigger, Boundary::Free, 1);
    const detail::FieldTable t = detail::tabulate(*o.sizing, o.box);
    detail::FieldDevice tight(o, t, 40);
    try {
        tight.run(t, 1u << 24, {}, 0);
        FAIL("the run passed its budget without an error");
    } catch (const Error& e) {
        const std::string what = e.what();
        CHECK_THAT(what, Catch::Contains("passed its 40 steps on " + tight.device_name()));
        CHECK(what.find('\n') == std::string::npos);
    }
    // With the device's own budget the same field samples.
    detail::FieldDevice own(o, t);
    CHECK(own.run(t, 1u << 24, {}, 0).size() > 100);
}

TEST_CASE("a sizing field's dispatches and passes longer than a row of workgroups take several rows", "[field][gpu]") {
    // Every dispatch, and every pass over the darts the pass before left undecided, runs in rows
    // of at most 65 535 workgroups; with rows of one workgroup every one of more than 64 items
    // takes several, and the points must be the cpu backend's.
    const SampleOptions o = field_options("0.01 + 0.05*x", SizingRule::Bigger, Boundary::Free, 1);
    const detail::FieldTable t = detail::tabulate(*o.sizing, o.box);
    detail::FieldDevice one_group(o, t, 0, 1);
    const Sampling s = one_group.run(t, 1u << 24, {}, 0);
    const Sampling expected = sample(o);
    CHECK(s.size() > 1000);
    CHECK(s.lattice == expected.lattice);
}

TEST_CASE("a field's profile names its phases on the host and on the device, and moves no point", "[field][gpu]") {
    SampleOptions o = field_options("0.01 + 0.02*x", SizingRule::Smaller, Boundary::Free, 4);
    const Sampling plain = sample(o);
    o.profile = true;
    for (const Backend b : {Backend::Cpu, Backend::Gpu}) {
        o.backend = b;
        const Sampling s = sample(o);
        CHECK(s.lattice == plain.lattice);
        std::vector<std::string> names;
        for (const PhaseTime& p : s.stats.profile) names.push_back(p.name);
        INFO("backend " << int(b));
        // The table and the leaves on the host either way; the kernels' own on the device.
        for (const char* name : {"tabulate", "leaves"}) CHECK(std::count(names.begin(), names.end(), name) == 1);
        if (b == Backend::Gpu) {
            CHECK(std::count(names.begin(), names.end(), "field_resolve") == 1);
            CHECK(s.stats.round_trips > 0);
        }
    }
}
