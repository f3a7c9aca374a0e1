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
    void add(const std::string& name, double seconds) {
        auto it = std::find_if(phases_.begin(), phases_.end(), [&](const PhaseTime& p) { return p.name == name; });
        if (it == phases_.end()) it = phases_.insert(phases_.end(), PhaseTime{name, 0.0, 0});
        it->seconds += seconds;
        ++it->calls;
    }
    const std::vector<PhaseTime>& phases() const { return phases_; }

private:
    std::vector<PhaseTime> phases_;
};

}  // namespace vrpd::detail
