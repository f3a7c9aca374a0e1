// The sizing-field sampler on a Vulkan device (field_engine.cpp): the host sampler's rounds
// (field/engine.cpp) as compute dispatches, point for point the same sampling.
#pragma once

#include <cstdint>

#include "field/table.h"
#include "vrpd/vrpd.h"

namespace vrpd::detail {

// Samples the field t under the options' rule and weighting on the options' device (or the
// application's), with at most `max_leaves` leaves. Fills the Sampling's points and stats.
Sampling sample_field_vulkan(const SampleOptions& o, const FieldTable& t, std::uint64_t max_leaves);

}  // namespace vrpd::detail
