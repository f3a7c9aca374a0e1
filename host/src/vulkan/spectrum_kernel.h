// The periodogram on a Vulkan device (shaders/spectrum.comp): vrpd/analysis.h's Backend::Gpu.
#pragma once

#include <string>
#include <vector>

#include "shared/bridge.h"

namespace vrpd::detail {

// Adds each set's P at the half plane's frequencies (shared/spectrum.h) to `sum`, which has one
// entry per frequency. Points are 32-bit fixed-point fractions of the box's sides. Returns the
// device's name.
std::string device_periodogram(const std::vector<std::vector<shared::uvec2>>& sets, std::uint32_t half_width,
                               const std::string& selector, std::vector<double>& sum);

}  // namespace vrpd::detail
