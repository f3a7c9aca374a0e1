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
};

// max_cell_bits caps the lattice's resolution (tests use it to make runs reach the deepest
// level, where cells are single lattice points).
Plan make_plan(const SampleOptions& options, std::uint32_t max_cell_bits = 30);

// Runs the schedule for a plan made from `options`.
Sampling sample_plan(const SampleOptions& options, const Plan& plan);

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
