// Level of detail from a hierarchical sampling (paper section 4; SampleOptions::hierarchy): the
// samples in birth order, so that every level is a prefix. A renderer draws the first
// count_at_radius(r) samples: a maximal sampling at the nearest level whose radius is >= r.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec2.hpp>

#include "vrpd/vrpd.h"

namespace vrpd {

class Hierarchy {
public:
    // From a hierarchical run's output (birth filled in).
    explicit Hierarchy(const Sampling& sampling);
    // From positions and their birth t (a point file's t column), with Rf at t = 1: rf0 = S Rf for
    // a hierarchy of final radius Rf that starts at S. Throws Error unless birth has one value per
    // point, each in (0, 1], non-increasing.
    Hierarchy(std::vector<glm::dvec2> points, std::vector<double> birth, double rf0);

    std::size_t size() const { return points_.size(); }
    const std::vector<glm::dvec2>& points() const { return points_; }  // in birth order
    const std::vector<double>& birth() const { return birth_; }
    double rf0() const { return rf0_; }

    // The samples born at t or earlier (birth >= t): maximal at t (Rf0, Rc0) when t is a level's.
    std::size_t count_at(double t) const;
    // The samples born at a radius of r or more: count_at(r / rf0), a level conflict-free at r.
    std::size_t count_at_radius(double r) const { return count_at(r / rf0_); }
    // The levels' t values, from the first (largest).
    std::vector<double> levels() const;

private:
    std::vector<glm::dvec2> points_;
    std::vector<double> birth_;
    double rf0_;
};

}  // namespace vrpd
