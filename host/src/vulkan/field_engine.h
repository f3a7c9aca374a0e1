// The sizing-field sampler on a Vulkan device (field_engine.cpp): the host sampler's rounds
// (field/engine.cpp) as compute dispatches, point for point the same sampling.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "field/table.h"
#include "vrpd/vrpd.h"

namespace vrpd::detail {

class FieldVulkan;

// The options' device (or the application's), its kernels made once for every run on it.
class FieldDevice {
public:
    // `budget`: the search steps an invocation may take (shared/field_search.h); 0 for the
    // device's own (6 000 on lavapipe, no limit elsewhere). `work_groups`: the most workgroups
    // in a row of a dispatch or a pass over a work list (work_args.comp); 0 for the least limit
    // Vulkan allows. Its kernels read kinked cells where `field` has them; the tables it runs
    // have them where it does (a hierarchy's levels are `field` scaled).
    FieldDevice(const SampleOptions& o, const FieldTable& field, std::uint32_t budget = 0,
                std::uint32_t work_groups = 0);
    ~FieldDevice();
    // Samples the field t under the options' rule and weighting until maximal, from `given`
    // (lattice points, conflict-free under the rule: a hierarchy's earlier levels), first in the
    // output in their order, with the darts of rounds first_round on and at most `max_leaves`
    // leaves. Fills the Sampling's points, rounds, darts, levels and peak bytes.
    Sampling run(const FieldTable& t, std::uint64_t max_leaves, const std::vector<glm::uvec2>& given,
                 std::uint32_t first_round);
    std::string device_name();
    std::uint64_t round_trips();       // so far, over every run
    std::vector<PhaseTime> profile();  // so far, with SampleOptions::profile

private:
    std::unique_ptr<FieldVulkan> impl_;
    unsigned threads_;  // the host's, for the leaves' build
};

}  // namespace vrpd::detail
