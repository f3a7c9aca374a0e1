// The interface between the sampling schedule (schedule.cpp) and the machines that run its rounds:
// the Vulkan engine and the host engines (parallel `cpu`, one-dart-at-a-time `serial`).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "phase_times.h"
#include "plan.h"

namespace vrpd::detail {

struct RoundSpec {
    std::uint32_t round;           // global round number, keys the RNG
    std::uint32_t side;            // side of the active cells, in lattice units
    std::uint32_t exp_neg_lambda;  // Poisson mean of darts per active cell, as exp(-lambda) * 2^32
    bool refine;                   // after the round, split surviving cells into 4 children
    bool every_free_cell;          // two radii: darts go to every base cell without a sample, not
                                   // only those near active cells (cheaper while U is everywhere)
    bool operator==(const RoundSpec&) const = default;
    // The refinement's children: four of half the side, or the cell itself.
    std::uint32_t fanout() const { return refine ? 4u : 1u; }
    std::uint32_t child_side() const { return refine ? side / 2u : side; }
};

struct RoundResult {
    std::uint64_t darts;           // thrown this round
    std::uint64_t active;          // active cells for the next round
};

class Engine {
public:
    virtual ~Engine() = default;
    virtual std::string device_name() const = 0;
    // Starts a run on `plan`: the engine's own plan, or a hierarchy step's (step_plan: the same
    // lattice, coarser cells, larger radii), so that one engine serves every step. The first
    // active list is every base cell (side 2^cell_bits) but those holding a sample; the samples
    // start as `initial` (conflict-free lattice points, checked by the caller), each in its base
    // cell's grid word. Returns the active count.
    virtual std::uint64_t start(const Plan& plan, const std::vector<glm::uvec2>& initial) = 0;
    // One round: throw darts into the active cells, resolve them in arrival order, commit the
    // accepted and append them to the samples in arrival order, and keep (or refine) the cells
    // still active. `next` is the round after this one when the schedule knows it already (one
    // radius: the schedule does not depend on a round's outcome), or null; an engine may count
    // its darts in this round's last submit.
    virtual RoundResult round(const RoundSpec& spec, const RoundSpec* next) = 0;
    // All samples so far, in acceptance order (rounds in order, each in arrival order).
    virtual std::vector<glm::uvec2> samples() = 0;
    // The most memory the engine's own arrays held at once: device memory (gpu) or host arrays
    // (cpu, serial). The process's resident memory adds the program and the Vulkan driver.
    virtual std::uint64_t peak_bytes() const = 0;
    // Submits the host has waited on so far (SamplingStats::round_trips).
    virtual std::uint64_t round_trips() const { return 0; }
    // Times the phases (host) or kernels (Vulkan) from now on; throws Error if the device cannot.
    virtual void start_profile() = 0;
    // The times so far, in the order the phases first ran; empty unless start_profile was called.
    virtual std::vector<PhaseTime> profile() const = 0;
};


// The error of a run in which a dart's T test went past its bounds (shared/t_membership.h).
inline constexpr const char* kTooComplex =
    "two radii: a dart's T-membership test went past its bounds (more than 64 samples within 2 Rc, or 8192 "
    "steps); this Rc/Rf and box are beyond what the kernels handle";

// The host engines: Parallel is the cpu backend (its darts decided in arrival order, a strip of
// rows a thread, up to two threads, and by the parallel resolution on more); ArrivalOrder decides
// in arrival order on any number of threads; Serial is the one-dart-at-a-time oracle.
enum class Resolution { Parallel, ArrivalOrder, Serial };
std::unique_ptr<Engine> make_host_engine(const Plan& plan, Resolution resolution, unsigned threads);

// A run with a sizing field (SampleOptions::sizing; field/run.cpp).
Sampling sample_sized(const SampleOptions& options);
std::unique_ptr<Engine> make_vulkan_engine(const Plan& plan, const std::string& device,
                                           const VulkanTarget* target = nullptr);

}  // namespace vrpd::detail
