// Sizing-field runs for the tests: their options, and the exact judgement of a sampling under its
// field (check_sizing on the field as the run tabulated it).
#pragma once

#include <functional>
#include <string>

#include "support.h"
#include "vrpd/sizing.h"
#include "vrpd/vrpd.h"

namespace vrpd::test {

inline const SizingRule kRules[] = {SizingRule::Prior, SizingRule::Current, SizingRule::Bigger, SizingRule::Smaller};

inline SampleOptions field_options(const std::string& expr, SizingRule rule, Boundary b, std::uint32_t seed) {
    SampleOptions o;
    o.box.boundary = b;
    o.seed = seed;
    o.backend = Backend::Cpu;
    o.sizing = Sizing{};
    o.sizing->expression = expr;
    o.sizing->rule = rule;
    return o;
}

// On a field tabulated before (the run's own, made from its sizing and box).
inline SizingReport judge(const Sampling& s, const SizingField& field, SizingRule rule) {
    const FieldStats f = field.stats();
    return check_sizing(points_of(s), std::cref(field), rule, s.box, 1e-9, {f.r_min, f.r_max, f.lipschitz, 0});
}

inline SizingReport judge(const Sampling& s, const Sizing& sizing) {
    return judge(s, SizingField(sizing, s.box), sizing.rule);
}

}  // namespace vrpd::test
