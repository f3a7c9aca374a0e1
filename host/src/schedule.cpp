// The sampling schedule (paper section 1; flat quadtree of Ebeida et al. 2012): rounds of darts
// per level, refinement of the cells still active, until no cell is active, i.e. the sampling is
// maximal. The engines keep each round's samples in arrival order: the sequence x_1..x_n.
#include <chrono>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "engine.h"

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
// time. Two radii throw fewer darts per round over more rounds at level 0 (share = (Rf / Rc)^2):
// a dart goes to a whole base cell, and one landing where T is already empty costs a full T
// test. Past level 0 their cells wait to split while they outnumber the last round's darts
// kCrowded times: the cells track U exactly at any size, but a gap of U fills no faster for its
// cells being small, while splitting multiplies them by up to 4; after a round that threw no dart
// they do not split at all. The measurements behind each number are in docs/performance.md.
constexpr double kCrowded = 8;

LevelSchedule schedule_for(std::uint32_t level, double share) {
    if (level > 0) return {0.5, 1};
    return share < 1.0 ? LevelSchedule{0.6 * share, 4} : LevelSchedule{0.5, 2};
}

constexpr std::uint32_t kMaxRounds = 100000;  // far above any run (a few dozen); a bug guard, not a limit

std::uint32_t exp_neg(double lambda) { return std::uint32_t(std::floor(std::exp(-lambda) * 4294967296.0)); }

std::unique_ptr<Engine> make_engine(const SampleOptions& o, Backend backend, const Plan& plan) {
    switch (backend) {
    case Backend::Gpu: return detail::make_vulkan_engine(plan, o.device);
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

Sampling sample(const SampleOptions& options) { return detail::sample_plan(options, detail::make_plan(options)); }

Sampling detail::sample_plan(const SampleOptions& options, const Plan& plan) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::uint64_t need = detail::estimated_bytes(plan);
    // Runs stay within 80 % of the memory they may use: the estimate is of the arrays' peak.
    const detail::MemoryLimit have = detail::host_memory_limit();
    if (need > have.bytes / 10 * 8)
        throw Error(fmt::format("radius {} needs about {:.2f} GiB ({} base cells), over 80 % of the {:.2f} GiB of "
                                "this process's {}",
                                options.radius, double(need) / (1 << 30), plan.base_cells,
                                double(have.bytes) / (1 << 30), have.what));

    const BackendChoice choice = choose_backend(options);
    std::unique_ptr<Engine> engine = make_engine(options, choice.backend, plan);
    if (options.profile) engine->start_profile();
    Sampling result;
    std::uint64_t active = engine->start();
    std::uint32_t level = 0, round = 0;
    std::uint64_t last_darts = 0;
    // Two radii: the share of a sample's Rc-disk its Rf-disk takes, (Rf / Rc)^2; 1 for one radius.
    const double share = double(plan.domain.radii.inhibition2) / double(plan.domain.radii.coverage2);
    while (active > 0) {
        const LevelSchedule s = schedule_for(level, share);
        const std::uint32_t side = 1u << (plan.deepest_level - level);
        for (std::uint32_t r = 0; r < s.rounds && active > 0;) {
            if (round >= kMaxRounds) throw Error(fmt::format("internal: not maximal after {} rounds", round));
            const bool crowded = share < 1.0 && level > 0 && double(active) > kCrowded * double(last_darts);
            const bool refine = !crowded && r + 1 == s.rounds && level < plan.deepest_level;
            // Two radii: while active cells fill half the base grid at level 0, listing the base
            // cells near them costs more than the few darts it saves.
            const bool every_free_cell = level == 0 && active >= plan.base_cells / 2;
            const detail::RoundResult rr = engine->round({round++, side, exp_neg(s.lambda), refine, every_free_cell});
            result.stats.darts += rr.darts;
            last_darts = rr.darts;
            active = rr.active;
            if (!crowded) ++r;  // a crowded round does not count towards the level's rounds
            if (refine) ++level;
        }
    }

    result.lattice = engine->samples();
    result.stats.peak_bytes = engine->peak_bytes();
    result.stats.profile = engine->profile();
    result.quantum = plan.quantum;
    result.radius = options.radius;
    result.coverage = options.coverage == 0.0 ? options.radius : options.coverage;
    result.box = options.box;
    result.backend = choice.backend;
    result.choice = choice.reason;
    result.device = engine->device_name();
    result.stats.levels = level + 1;
    result.stats.rounds = round;
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return result;
}

const char* version() { return VRPD_VERSION; }

}  // namespace vrpd
