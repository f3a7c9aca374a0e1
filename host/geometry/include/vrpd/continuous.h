// A continuous hierarchy (paper section 4.2): from a maximal sampling at S times the final radii,
// t decreases without steps; at each t where the largest empty circle first exceeds rc(t), the
// sampling stops being maximal at that circle's centre u, and a sample is inserted: u itself with
// one radius, a uniform point of T (the free points within rc(t) of u) with two radii. Its birth
// is that t, so the samples born at t or earlier are maximal and conflict-free at t (Rf0, Rc0)
// for every t in [1/S, 1], not only at steps. Part of vrpd_geometry (CGAL).
#pragma once

#include "vrpd/vrpd.h"

namespace vrpd {

// options.hierarchy.continuous must be set (S = start, 10 if 0); the box periodic. The first
// sampling runs on options.backend; the rest on the host, deterministically from options.seed.
// Samples are rounded to the first sampling's lattice (about 2^-30 of the box), so a pair may
// come closer than rf(t) by up to one lattice step. Throws Error with the reason.
Sampling continuous_hierarchy(const SampleOptions& options);

}  // namespace vrpd
