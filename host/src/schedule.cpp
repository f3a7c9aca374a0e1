// The sampling schedule (paper section 1; flat quadtree of Ebeida et al. 2012): rounds of darts
// per level, refinement of the cells still active, until no cell is active, i.e. the sampling is
// maximal. The engines keep each round's samples in arrival order: the sequence x_1..x_n.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <optional>

#include <fmt/format.h>

#include "engine.h"
#include "shared/neighbourhood.h"

namespace vrpd {
namespace {

using detail::Engine;
using detail::Plan;

struct LevelSchedule {
    double lambda;           // Poisson mean of darts per active cell per round
    std::uint32_t rounds;    // rounds before the active cells are refined
};

// The schedule: one radius throws Poisson(0.5) darts per active cell for 2 rounds at level 0,
// then one round per level; per-cell work (counts, scans, cover tests), not darts, dominates the
// time. A run from given samples (each step of a hierarchy) throws one round of 0.7 at level 0:
// the given samples cover much of the box already, and its darts there are rejected, so the
// first cover test comes a round sooner. Two radii throw fewer darts per round over more rounds at level 0 (share = (Rf / Rc)^2):
// a dart goes to a whole base cell, and one landing where T is already empty costs a full T
// test. Past level 0 their cells wait to split while they outnumber the last round's darts
// kCrowded times: the cells track U exactly at any size, but a gap of U fills no faster for its
// cells being small, while splitting multiplies them by up to 4; after a round that threw no dart
// they do not split at all. The measurements behind each number are in docs/performance.md.
constexpr double kCrowded = 8;

LevelSchedule schedule_for(std::uint32_t level, double share, bool given) {
    if (level > 0) return {0.5, 1};
    if (share < 1.0) return {0.6 * share, 4};
    return given ? LevelSchedule{0.7, 1} : LevelSchedule{0.5, 2};
}

constexpr std::uint32_t kMaxRounds = 100000;  // far above any run (a few dozen); a bug guard, not a limit

std::uint32_t exp_neg(double lambda) { return std::uint32_t(std::floor(std::exp(-lambda) * 4294967296.0)); }

std::unique_ptr<Engine> make_engine(const SampleOptions& o, Backend backend, const Plan& plan) {
    switch (backend) {
    case Backend::Gpu: return detail::make_vulkan_engine(plan, o.device, o.vulkan);
    case Backend::Cpu: return detail::make_host_engine(plan, detail::Resolution::Parallel, o.threads);
    case Backend::Serial: return detail::make_host_engine(plan, detail::Resolution::Serial, o.threads);
    case Backend::Auto: break;
    }
    throw Error("internal: no engine for this backend");
}

}  // namespace

// A CPU Vulkan driver (lavapipe) runs the kernels on the same cores as the cpu backend, one
// SIMD lane an invocation and every branch of a batch, several times slower for the same bytes:
// Auto takes it only when named.
BackendChoice choose_backend(const SampleOptions& o) {
    if (o.vulkan && o.backend != Backend::Auto && o.backend != Backend::Gpu)
        throw Error("a run on the application's Vulkan device needs the gpu backend (or auto)");
    if (o.vulkan) return {Backend::Gpu, "the options give the application's Vulkan device"};
    if (o.backend != Backend::Auto) return {o.backend, ""};
    if (!o.device.empty()) return {Backend::Gpu, "the options name a Vulkan device"};
    if (const char* env = std::getenv("VRPD_DEVICE"); env && *env)
        return {Backend::Gpu, "VRPD_DEVICE names a Vulkan device"};
    std::vector<DeviceInfo> devices;
    try {
        devices = list_devices();
    } catch (const Error&) {
        return {Backend::Cpu, "no Vulkan driver on this machine"};
    }
    for (const DeviceInfo& d : devices)
        if (d.usable && (d.type == "discrete" || d.type == "integrated" || d.type == "virtual"))
            return {Backend::Gpu, fmt::format("hardware Vulkan device {}", d.name)};
    return {Backend::Cpu, "no hardware Vulkan device; a CPU Vulkan driver gives the same points, slower"};
}

Sampling sample(const SampleOptions& options) {
    if (options.sizing) return detail::sample_sized(options);
    if (options.hierarchy.continuous)
        throw Error("a continuous hierarchy is built on CGAL's triangulation: vrpd_geometry's continuous_hierarchy "
                    "(vrpd/continuous.h)");
    return detail::sample_plan(options, detail::make_plan(options));
}

namespace {

// Runs rounds on `engine` (started) until no cell of `plan` is active: the sampling is maximal.
// Rounds are numbered on from `round`, so that the steps of a hierarchy draw other darts.
// `given`: the run started from given samples. Returns the levels visited.
std::uint32_t run_to_maximal(Engine& engine, const Plan& plan, std::uint64_t active, std::uint32_t& round,
                             SamplingStats& stats, bool given) {
    std::uint32_t level = 0;
    const std::uint32_t first_round = round;
    std::uint64_t last_darts = 0;
    // Two radii: the share of a sample's Rc-disk its Rf-disk takes, (Rf / Rc)^2; 1 for one radius.
    const double share = double(plan.domain.radii.inhibition2) / double(plan.domain.radii.coverage2);
    // The spec of round `number`, the r-th of `level`'s rounds.
    auto spec_at = [&](std::uint32_t level, std::uint32_t r, std::uint32_t number, bool crowded) {
        const LevelSchedule s = schedule_for(level, share, given);
        const bool refine = !crowded && r + 1 == s.rounds && level < plan.deepest_level;
        // Two radii: while active cells fill half the base grid at level 0, listing the base
        // cells near them costs more than the few darts it saves.
        const bool every_free_cell = share < 1.0 && level == 0 && active >= plan.base_cells / 2;
        return detail::RoundSpec{number, 1u << (plan.deepest_level - level), exp_neg(s.lambda), refine,
                                 every_free_cell};
    };
    std::uint32_t r = 0;  // rounds of this level so far
    while (active > 0) {
        if (round - first_round >= kMaxRounds)
            throw Error(fmt::format("internal: not maximal after {} rounds", round - first_round));
        const std::uint32_t rounds = schedule_for(level, share, given).rounds;
        const bool crowded = share < 1.0 && level > 0 && double(active) > kCrowded * double(last_darts);
        const detail::RoundSpec spec = spec_at(level, r, round, crowded);
        // The level and round that come next; a crowded round does not count towards the level's
        // rounds, and past the deepest level the rounds go on at it.
        const std::uint32_t next_level = spec.refine ? level + 1 : level;
        const std::uint32_t next_r = crowded ? r : (r + 1 == rounds ? 0 : r + 1);
        // One radius: no round is crowded, so the next spec does not depend on this round.
        const std::optional<detail::RoundSpec> next =
            share < 1.0 ? std::nullopt : std::optional(spec_at(next_level, next_r, round + 1, false));
        const detail::RoundResult rr = engine.round(spec, next ? &*next : nullptr);
        ++round;
        stats.darts += rr.darts;
        last_darts = rr.darts;
        active = rr.active;
        level = next_level;
        r = next_r;
    }
    return level + 1;
}

// The given samples on the plan's lattice (each rounded to the nearest lattice point), checked
// exactly: inside the box and no pair closer than Rf.
std::vector<glm::uvec2> initial_samples(const SampleOptions& o, const Plan& plan) {
    const shared::Domain& d = plan.domain;
    const std::vector<glm::uvec2> out = detail::given_on_lattice(o, plan.quantum, d.lattice);
    std::vector<std::uint32_t> owner(plan.base_cells, ~0u);
    auto conflict = [&](std::size_t i, std::size_t j) {
        const glm::dvec2 a = o.initial[std::min(i, j)], b = o.initial[std::max(i, j)];
        return Error(fmt::format("given samples {} ({}, {}) and {} ({}, {}) are closer than Rf = {} on the run's "
                                 "lattice",
                                 std::min(i, j) + 1, a.x, a.y, std::max(i, j) + 1, b.x, b.y, o.radius));
    };
    for (std::size_t i = 0; i < out.size(); ++i) {
        std::uint32_t& cell = owner[shared::base_of_point(d, out[i])];
        if (cell != ~0u) throw conflict(cell, i);  // a base cell's diagonal is shorter than Rf
        cell = std::uint32_t(i);
    }
    using namespace shared;  // the neighbourhood macro names the shared headers' functions
    const int reach = conflict_reach(d.radii);
    for (std::size_t i = 0; i < out.size(); ++i) {
        const glm::uvec2 cell = shared::base_cell_of(d, out[i]);
        VRPD_FOR_EACH_NEIGHBOUR(d, cell, reach, d.radii.inhibition2, dx, dy, nb) {
            const std::uint32_t j = owner[std::size_t(nb)];
            if (j != ~0u && j != i && shared::inhibits(d.radii, shared::distance2(d.lattice, out[i], out[j])))
                throw conflict(i, j);
        }
    }
    return out;
}

}  // namespace

Sampling detail::sample_plan(const SampleOptions& options, const Plan& plan) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::uint64_t need = detail::estimated_bytes(plan);
    // Runs stay within 80 % of the memory they may use: the estimate is of the arrays' peak (a
    // hierarchy's steps grow to the finest, this plan).
    const detail::MemoryLimit have = detail::host_memory_limit();
    if (need > have.bytes / 10 * 8)
        throw Error(fmt::format("radius {} needs about {:.2f} GiB ({} base cells), over 80 % of the {:.2f} GiB of "
                                "this process's {}",
                                options.radius, double(need) / (1 << 30), plan.base_cells,
                                double(have.bytes) / (1 << 30), have.what));

    const BackendChoice choice = choose_backend(options);
    // One engine, made for the finest plan, runs every step.
    std::unique_ptr<Engine> engine = make_engine(options, choice.backend, plan);
    Sampling result = run_plan(options, plan, *engine);
    result.backend = choice.backend;
    result.choice = choice.reason;
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return result;
}

Sampling detail::run_plan(const SampleOptions& options, const Plan& plan, Engine& engine) {
    Sampling result;
    const unsigned steps = options.hierarchy.steps;
    std::vector<glm::uvec2> samples = initial_samples(options, plan);
    if (options.profile) engine.start_profile();
    std::uint32_t round = 0;
    for (const auto& [t, scale] : hierarchy_steps(options)) {
        const Plan step = steps == 0 ? plan : step_plan(plan, options, scale);
        const std::size_t before = samples.size();
        const std::uint32_t levels =
            run_to_maximal(engine, step, engine.start(step, samples), round, result.stats, !samples.empty());
        samples = engine.samples();
        if (steps != 0) result.birth.resize(samples.size(), t);
        result.stats.levels = std::max(result.stats.levels, levels);
        if (samples.size() < before) throw Error("internal: a step lost samples");
    }
    result.stats.peak_bytes = engine.peak_bytes();
    result.stats.profile = engine.profile();
    result.stats.round_trips = engine.round_trips();
    result.device = engine.device_name();
    result.lattice = std::move(samples);
    result.quantum = plan.quantum;
    result.radius = options.radius;
    result.coverage = options.coverage == 0.0 ? options.radius : options.coverage;
    result.box = options.box;
    result.hierarchy_start = steps == 0 ? 1.0 : hierarchy_start(options);
    result.stats.rounds = round;
    return result;
}

const char* version() { return VRPD_VERSION; }

}  // namespace vrpd
