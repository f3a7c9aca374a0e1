// Turns a user's request (radius, box) into the integer lattice and base grid the kernels run on,
// and estimates the memory a run needs before anything is allocated.
#pragma once

#include <cstdint>

#include "vrpd/vrpd.h"
#include "shared/domain.h"

namespace vrpd::detail {

struct Plan {
    shared::Domain domain;
    double quantum;              // lattice spacing in user units
    std::uint32_t deepest_level; // cells of this level are single lattice points
    std::uint64_t base_cells;
    std::uint32_t seed;          // keys the RNG with each round (shared/darts.h, round_key)
    // The cpu backend on several threads decides a round in arrival order a strip of base-cell
    // rows a thread (cpu/arrival_order.h) from this many darts a thread: in smaller rounds
    // starting the threads costs more than it saves. Tests set 0 to run strips on small rounds.
    std::uint32_t strip_darts = 1024;
};

// max_cell_bits caps the lattice's resolution (tests use it to make runs reach the deepest
// level, where cells are single lattice points).
Plan make_plan(const SampleOptions& options, std::uint32_t max_cell_bits = 30);

// A periodic box tiled exactly by square cells of side at most max_side (and no smaller than
// max_side sqrt(2) / 3): W = nx s and H = ny s, with nx and ny multiples of `multiple` (a
// hierarchy's coarser grids group multiple x multiple cells). False if no such tiling exists.
bool periodic_tiling(double width, double height, double max_side, std::uint64_t multiple, std::uint64_t& nx,
                     std::uint64_t& ny);

// A hierarchy's S (HierarchyOptions::start, or K if that is 0).
double hierarchy_start(const SampleOptions& options);

// The given samples (SampleOptions::initial) on a lattice of spacing `quantum`, each at the
// lattice point nearest it. Throws Error for one outside the box.
std::vector<glm::uvec2> given_on_lattice(const SampleOptions& options, double quantum, const shared::Lattice& lattice);

// A discrete hierarchy's steps in order: t_k = 1 - (1 - 1/S) k / (K - 1) and the radii's scale
// S t_k, each as one division of exact numerators for whole S (so S = K = 10 gives t = 0.2, not
// 0.19999...). A direct run is one step at t = 1, scale 1; a continuous hierarchy's first level,
// one at t = 1, scale S.
struct HierarchyStep {
    double t, scale;
};
std::vector<HierarchyStep> hierarchy_steps(const SampleOptions& options);

// The plan of a hierarchy step at `scale` times the final radii (1 <= scale <= S), on the lattice
// of `finest` (make_plan's plan for the options): its base cells group 2^j x 2^j of the finest,
// the coarsest grouping whose cells a sample still covers.
Plan step_plan(const Plan& finest, const SampleOptions& options, double scale);

// Runs the schedule for a plan made from `options`: a direct sampling, from options.initial if
// given, or a hierarchy's steps.
Sampling sample_plan(const SampleOptions& options, const Plan& plan);

// sample_plan's run on `engine`, made for `plan` (tests run engines of other settings); the
// result's backend and time are the caller's to set.
class Engine;
Sampling run_plan(const SampleOptions& options, const Plan& plan, Engine& engine);

// Samples a run is expected to end with, give or take a few percent: the engines reserve room
// for them up front rather than growing their sample arrays by doubling.
std::uint64_t expected_samples(const Plan& plan);

// Peak bytes a run is expected to hold (device and host together on a CPU device).
std::uint64_t estimated_bytes(const Plan& plan);

// Peak bytes of device memory the Vulkan engine is expected to hold.
std::uint64_t estimated_device_bytes(const Plan& plan);

// The memory a run may use: the least of physical memory, the process's address-space limit
// (RLIMIT_AS, `ulimit -v`) and its cgroup's limit, with the name of the one that binds.
struct MemoryLimit {
    std::uint64_t bytes;
    const char* what;
};
MemoryLimit host_memory_limit();

}  // namespace vrpd::detail
