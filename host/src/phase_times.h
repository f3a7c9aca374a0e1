// Profiling: named phases' times, accumulated by the engines (SampleOptions::profile).
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "vrpd/vrpd.h"

namespace vrpd::detail {

// Accumulates named phases' times in the order they first ran.
class PhaseTimes {
public:
    void add(const std::string& name, double seconds) { add(PhaseTime{name, seconds, 1}); }
    // Adds a phase's seconds and calls (another run's, or one call).
    void add(const PhaseTime& p) {
        auto it = std::find_if(phases_.begin(), phases_.end(), [&](const PhaseTime& q) { return q.name == p.name; });
        if (it == phases_.end()) it = phases_.insert(phases_.end(), PhaseTime{p.name, 0.0, 0});
        it->seconds += p.seconds;
        it->calls += p.calls;
    }
    const std::vector<PhaseTime>& phases() const { return phases_; }

private:
    std::vector<PhaseTime> phases_;
};

}  // namespace vrpd::detail
