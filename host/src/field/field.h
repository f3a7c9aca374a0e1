// The sizing-field sampler (field/engine.cpp) on a tabulated field (field/table.h).
#pragma once

#include <cstdint>

#include "table.h"
#include "vrpd/vrpd.h"

namespace vrpd::detail {

// Bytes per expected sample, at the peak: the sample (12), its share of the leaves and tree
// (about 3 leaves of 17 bytes), the active cells (two lists of 16-byte cells, a few per sample)
// and the darts.
inline constexpr double kFieldBytesPerSample = 200;

// Samples a maximal sampling of o.box under the field's rule, on the host's threads (o.threads;
// one for Backend::Serial; the points do not depend on the count). tabulate() has already
// refused a field whose expected samples would not fit in memory.
Sampling sample_field(const SampleOptions& o, const FieldTable& table);

}  // namespace vrpd::detail
