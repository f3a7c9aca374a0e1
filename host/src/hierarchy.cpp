// Level of detail over a hierarchical sampling (vrpd/hierarchy.h).
#include "vrpd/hierarchy.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include <fmt/format.h>

namespace vrpd {

// Births are stored as t_k exactly, so a level's own t finds it; a t typed in decimal may miss the
// double it names by an ulp or two, which this relative slack absorbs.
constexpr double kSlack = 1e-12;

Hierarchy::Hierarchy(const Sampling& s)
    : Hierarchy(
          [&] {
              std::vector<glm::dvec2> p(s.size());
              for (std::size_t i = 0; i < s.size(); ++i) p[i] = s.point(i);
              return p;
          }(),
          s.birth, s.radius * s.hierarchy_start) {}

Hierarchy::Hierarchy(std::vector<glm::dvec2> points, std::vector<double> birth, double rf0)
    : points_(std::move(points)), birth_(std::move(birth)), rf0_(rf0) {
    if (birth_.size() != points_.size())
        throw Error(fmt::format("a hierarchy needs a birth t for each of its {} points (got {}; a file needs a t "
                                "column)",
                                points_.size(), birth_.size()));
    if (!(std::isfinite(rf0_) && rf0_ > 0)) throw Error(fmt::format("Rf at t = 1 must be > 0 (got {})", rf0_));
    for (std::size_t i = 0; i < birth_.size(); ++i) {
        if (!(birth_[i] > 0 && birth_[i] <= 1))
            throw Error(fmt::format("point {}: birth t {} is outside (0, 1]", i + 1, birth_[i]));
        if (i > 0 && birth_[i] > birth_[i - 1])
            throw Error(fmt::format("point {}: birth t {} after {}: the points are not in birth order", i + 1,
                                    birth_[i], birth_[i - 1]));
    }
}

std::size_t Hierarchy::count_at(double t) const {
    // birth is non-increasing: the first point born after t ends the prefix.
    const double bound = t * (1 - kSlack);
    return std::size_t(std::partition_point(birth_.begin(), birth_.end(), [&](double b) { return b >= bound; }) -
                       birth_.begin());
}

std::vector<double> Hierarchy::levels() const {
    std::vector<double> out;
    for (double b : birth_)
        if (out.empty() || b != out.back()) out.push_back(b);
    return out;
}

}  // namespace vrpd
