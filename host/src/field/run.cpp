// Sampling with a sizing field (vrpd.h, Sizing): tabulate, then the field sampler, or the uniform
// engines when the field is one constant (every rule is then the one-radius case).
#include <chrono>
#include <optional>

#include <fmt/format.h>

#include "field.h"
#include "../plan.h"
#include "vrpd/sizing.h"

namespace vrpd {

SizingField::SizingField(const Sizing& sizing, const Box& box, unsigned threads)
    : table_(std::make_shared<const detail::FieldTable>(detail::tabulate(sizing, box, threads))),
      sizing_(sizing),
      box_(box) {}

SizingField::SizingField(const SampleOptions& o)
    : SizingField(o.sizing ? *o.sizing : throw Error("a field needs the options' sizing"), o.box,
                  o.backend == Backend::Serial ? 1 : o.threads) {}

bool SizingField::made_from(const Sizing& s, const Box& box) const {
    const Sizing& m = sizing_;
    return scale_ == 1 && s.expression == m.expression && s.image == m.image && s.r_min == m.r_min &&
           s.r_max == m.r_max && s.lipschitz == m.lipschitz && s.table_budget == m.table_budget &&
           box.width == box_.width && box.height == box_.height && box.boundary == box_.boundary;
}

double SizingField::operator()(glm::dvec2 p) const {
    const detail::FieldTable& t = *table_;
    auto coord = [&](double v, std::uint32_t extent) {
        const double u = std::round(v / t.quantum);
        return std::uint32_t(std::clamp(u, 0.0, double(extent - 1)));
    };
    return t.radius({coord(p.x, t.lattice.extent_x), coord(p.y, t.lattice.extent_y)}) * t.quantum;
}

SizingField SizingField::scaled(double scale, unsigned threads) const {
    if (!(std::isfinite(scale) && scale > 0)) throw Error(fmt::format("a field's scale must be > 0 (got {})", scale));
    detail::ThreadPool pool(threads);
    return SizingField(std::make_shared<const detail::FieldTable>(detail::scaled(*table_, scale, pool)), sizing_, box_,
                       scale_ * scale);
}

FieldStats SizingField::stats() const { return table_->stats(); }
double SizingField::quantum() const { return table_->quantum; }

namespace detail {
namespace {

// Samples `field`, tabulated from o.sizing over o.box by this run in `tabulation` seconds, or
// before it (none).
Sampling sample_tabulated(const SampleOptions& o, const SizingField& field, std::optional<double> tabulation) {
    const FieldTable& t = field.table();
    // A constant field's continuous hierarchy is the field sampler's: the one-radius one is CGAL's.
    const bool levels = o.hierarchy.steps != 0 || o.hierarchy.continuous;
    if (t.constant > 0 && !o.hierarchy.continuous) {
        SampleOptions uniform = o;
        uniform.sizing.reset();
        uniform.radius = t.constant;
        Sampling s = sample(uniform);
        s.local_radius.assign(s.size(), t.constant);
        s.field = t.stats();
        return s;
    }
    if (levels && o.box.boundary == Boundary::Periodic) {
        // The first step's field, S times r, within half the torus as every field is.
        const double top = t.r_hi * t.quantum * hierarchy_start(o), short_side = std::min(o.box.width, o.box.height);
        if (top >= short_side / 2)
            throw Error(
                fmt::format("the hierarchy's first step, at {} times the field: its largest radius {:.6g} is "
                            "too large for a periodic box of {} x {}: it must be < {} (half the shorter side)",
                            hierarchy_start(o), top, o.box.width, o.box.height, short_side / 2));
    }
    // Auto chooses as for one radius: the application's device, a named one or a hardware one,
    // else the host. It refuses the cpu and serial backends beside the application's device.
    const BackendChoice choice = choose_backend(o);
    SampleOptions chosen = o;
    chosen.backend = choice.backend;
    Sampling s = sample_field(chosen, t);
    s.choice = choice.reason;
    if (tabulation) {
        s.stats.seconds += *tabulation;
        if (o.profile) s.stats.profile.insert(s.stats.profile.begin(), PhaseTime{"tabulate", *tabulation, 1});
    }
    return s;
}

}  // namespace

Sampling sample_sized(const SampleOptions& o) {
    validate(o);
    const auto start = std::chrono::steady_clock::now();
    const SizingField field(o);  // on the threads the sampler will take
    const double tabulation = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return sample_tabulated(o, field, tabulation);
}

}  // namespace detail

Sampling sample(const SampleOptions& o, const SizingField& field) {
    if (!o.sizing) throw Error("sampling a tabulated field needs the options' sizing (its rule and weighting)");
    validate(o);
    if (!field.made_from(*o.sizing, o.box)) throw Error("the field was not tabulated from the options' sizing and box");
    return detail::sample_tabulated(o, field, std::nullopt);
}

}  // namespace vrpd
