// Device-side profiling: a timestamp after every dispatch of a submit, read back after the
// submit, added to the dispatched kernel's time (SampleOptions::profile).
#pragma once

#include <cstdint>
#include <vector>

#include "handles.h"
#include "phase_times.h"

namespace vrpd::detail {

class Kernel;
class VulkanContext;

class Profiler {
public:
    // Throws Error if the context's queue has no timestamps.
    explicit Profiler(const VulkanContext& ctx);
    // At the start of a submit's recording: resets the queries, writes timestamp 0.
    void begin(VkCommandBuffer cmd);
    // After a dispatch of k: from the end of the work recorded before it to its own end.
    void after(VkCommandBuffer cmd, const Kernel& k);
    // After the submit has finished: adds its timestamps to the kernels' times.
    void read();
    const std::vector<PhaseTime>& phases() const { return times_.phases(); }

private:
    static constexpr std::uint32_t kQueries = 256;  // timestamps per submit: far more than its dispatches
    const VulkanContext& ctx_;
    OwnedQueryPool queries_;
    std::uint32_t timestamp_bits_ = 0;
    double timestamp_ns_ = 0.0;  // nanoseconds per timestamp tick
    std::vector<const Kernel*> timed_;  // the kernel behind timestamp i + 1
    PhaseTimes times_;
};

}  // namespace vrpd::detail
