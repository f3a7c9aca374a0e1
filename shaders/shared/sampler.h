// The bodies of the sampler's kernels (one base cell, active cell or dart each), shared by the
// Vulkan shaders and the host backends: flat-quadtree maximal Poisson-disk sampling (Ebeida et
// al. 2012) driven as exact random sequential adsorption (paper section 1, Eqs. 1-4; two radii,
// section 3). No kernel reads what another invocation of the same pass writes: the passes are
// race-free on every device, and their results do not depend on timing.
//
// One concept a header: the radius model (radii.h), the lattice (lattice.h), the base grid and
// its words (domain.h, grid.h), the one neighbourhood scan (neighbourhood.h), the RNG and dart
// storage (darts.h), the active cells (active_cells.h), coverage by earlier samples (cover.h),
// throwing (throw.h), resolution (resolve.h; two radii: resolve_two_radii.h, t_membership.h),
// commit (commit.h), the quadtree's refinement (quadtree.h), mask mode (mask_mode.h) and the
// dart cells of two radii (dart_cells.h).
#ifndef VRPD_SAMPLER_H
#define VRPD_SAMPLER_H
#include "active_cells.h"
#include "commit.h"
#include "dart_cells.h"
#include "mask_mode.h"
#include "quadtree.h"
#include "resolve.h"
#include "resolve_two_radii.h"
#include "throw.h"
#endif
