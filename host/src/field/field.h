// The sizing-field sampler (field/engine.cpp) on a tabulated field (field/table.h).
#pragma once

#include <cstdint>

#include "table.h"
#include "vrpd/vrpd.h"

namespace vrpd::detail {

// Bytes per expected sample, at the peak: the first round's balance, with about 4.4 to 5.5 leaves
// a sample, each with its tree share (9 bytes), its stamp (4) and its cell twice (8 each), the
// samples, and the table (its patches and kinked cells up to 128 bytes a sample). Measured on large runs: 160-195
// bytes a sample on the rectified sine (Figure 16's scale 186, with patches; 255 bytes of peak
// RSS), 289 on a 500x ramp (docs/performance.md).
inline constexpr double kFieldBytesPerSample = 400;

// Samples a maximal sampling of o.box under the field's rule, on the host's threads (o.threads;
// one for Backend::Serial; the points do not depend on the count). tabulate() has already
// refused a field whose expected samples would not fit in memory.
Sampling sample_field(const SampleOptions& o, const FieldTable& table);

// Throws Error, naming `what`, when `expected` samples at `bytes_per_sample` would pass the
// host's memory limit (field/table.cpp).
void require_memory(const char* what, double expected, double bytes_per_sample);

// Bytes per final sample that a continuous hierarchy's events hold at the peak: the leaves and
// samples, the queue of blocks (about 10 a sample, 40 bytes each) and the table. Measured:
// 501-901 under the four rules on the bench's sine at S = 4 (docs/performance.md).
inline constexpr double kContinuousBytesPerSample = 1200;

// A continuous hierarchy's events (field/continuous.cpp): `samples`, a maximal sampling at S
// times the field t, born at t = 1, completed without steps down to t's own field, each event's
// sample appended with its t to `birth` (which it sets). Runs on the host, one thread besides the
// leaves' build, whatever the backend: the events are a sequence. Returns the bytes it held.
std::uint64_t continue_hierarchy(const FieldTable& t, const SampleOptions& o, std::uint64_t max_leaves,
                                 std::vector<glm::uvec2>& samples, std::vector<double>& birth);

}  // namespace vrpd::detail
