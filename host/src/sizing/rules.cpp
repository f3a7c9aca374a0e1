// The four conflict rules of a sizing field (vrpd/sizing.h): their names and the radius each
// takes for a pair of samples (paper Table 1).
#include <algorithm>
#include <string>

#include <fmt/format.h>

#include "vrpd/sizing.h"

namespace vrpd {

SizingRule parse_sizing_rule(const std::string& name) {
    if (name == "prior") return SizingRule::Prior;
    if (name == "current") return SizingRule::Current;
    if (name == "bigger") return SizingRule::Bigger;
    if (name == "smaller") return SizingRule::Smaller;
    throw Error(fmt::format("unknown rule '{}': use prior, current, bigger or smaller", name));
}

const char* sizing_rule_name(SizingRule rule) {
    switch (rule) {
        case SizingRule::Prior:
            return "prior";
        case SizingRule::Current:
            return "current";
        case SizingRule::Bigger:
            return "bigger";
        case SizingRule::Smaller:
            return "smaller";
    }
    return "?";
}

double rule_radius(SizingRule rule, double r_earlier, double r_later) {
    switch (rule) {
        case SizingRule::Prior:
            return r_earlier;
        case SizingRule::Current:
            return r_later;
        case SizingRule::Bigger:
            return std::max(r_earlier, r_later);
        case SizingRule::Smaller:
            return std::min(r_earlier, r_later);
    }
    return r_earlier;
}

}  // namespace vrpd
