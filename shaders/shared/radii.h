// The radius model (paper sections 1 and 3, Eqs. 1-9): which squared lattice distances conflict
// and which cover. Every kernel decides conflicts and coverage through the predicates below, and
// asks two_radii() for the kind of run, never compares radii itself. docs/design.md says how
// the coming kinds (radii scaled by t, section 4; a sizing field r(x) with a conflict rule,
// section 5) map onto this model.
#ifndef VRPD_RADII_H
#define VRPD_RADII_H
#include "bridge.h"

VRPD_BEGIN

// The kinds of radius model. One radius: Rf = Rc = r. Two radii: Rf < Rc (section 3), where a
// dart is kept only in T = S ∩ (U ⊕ Rc) (t_membership.h).
const uint RADII_ONE = 0u;
const uint RADII_TWO = 1u;

struct Radii {
    uint64_t inhibition2;  // Rf^2 in lattice units: samples closer than Rf conflict (Eqs. 1, 5)
    uint64_t coverage2;    // Rc^2: a point closer than Rc to a sample is covered (Eqs. 2, 7); with two
                           // radii at most MAX_COVER2 (t_membership.h)
    uint kind;             // RADII_ONE or RADII_TWO
    uint reach;            // base cells within this many rows/columns may hold: a conflicting sample
                           // (bits 0-7, <= MAX_REACH), a covering one (bits 8-15), one within 2 Rc
                           // (bits 16-23); bits 24 + 2 |dy|: conflict_row's table (neighbourhood.h)
};
#ifdef __cplusplus
static_assert(sizeof(Radii) == 24 && offsetof(Radii, coverage2) == 8 && offsetof(Radii, kind) == 16 &&
              offsetof(Radii, reach) == 20);
#endif

// A kernel built for one radius only defines VRPD_ONE_RADIUS before its includes: two_radii() is
// then false, and the code that serves two radii (T tests, corner bookkeeping, the grid-scan
// fallback of a cell test) is left out of its SPIR-V by #ifndef VRPD_ONE_RADIUS where kernels
// reach it (glslang does not fold a call, so the guard is what keeps the code out; the driver
// would otherwise compile it, and llvmpipe runs every branch of a SIMD batch whether a lane
// takes it or not). The kernel variants are listed in one table in CMakeLists.txt.
#ifdef VRPD_ONE_RADIUS
VRPD_FN bool two_radii(Radii r) { return false; }
#else
VRPD_FN bool two_radii(Radii r) { return r.kind == RADII_TWO; }
#endif

// Eq. 1 (and 5): a sample at squared distance d2 inhibits a point, i.e. they conflict.
VRPD_FN bool inhibits(Radii r, uint64_t d2) { return d2 < r.inhibition2; }
// Eqs. 2 and 7: a sample at squared distance d2 covers a point. A point at exactly Rc is not
// covered, so both predicates are strict. A quadtree cell is covered by one sample when its
// farthest point is (cells are convex): callers pass that point's squared distance.
VRPD_FN bool covers(Radii r, uint64_t d2) { return d2 < r.coverage2; }

// The two radii a scan may ask about, by name: conflicts (Rf) or coverage (Rc).
const uint INHIBITION = 0u;
const uint COVERAGE = 1u;
VRPD_FN uint64_t radius2(Radii r, uint which) { return which == COVERAGE ? r.coverage2 : r.inhibition2; }
VRPD_FN bool within(Radii r, uint which, uint64_t d2) { return which == COVERAGE ? covers(r, d2) : inhibits(r, d2); }

// Two radii, T = S ∩ (U ⊕ Rc) (Eq. 9): the closed Rc-disk of a point reaches a point (or a cell's
// nearest point) at squared distance d2.
VRPD_FN bool reaches(Radii r, uint64_t d2) { return d2 <= r.coverage2; }

// Squared radius of the influence neighbourhood of two radii: samples at distance^2 <= 4 Rc^2
// can change a dart's membership in T.
VRPD_FN uint64_t influence2(Radii r) { return uint64_t(4) * r.coverage2 + uint64_t(1); }

VRPD_FN int conflict_reach(Radii r) { return int(r.reach & 0xFFu); }
VRPD_FN int cover_reach(Radii r) { return int((r.reach >> 8u) & 0xFFu); }
// The widest neighbourhood any kernel scans: 2 Rc with two radii, else Rf.
VRPD_FN uint influence_reach(Radii r) { return (r.reach >> 16u) & 0xFFu; }

VRPD_FN int radius_reach(Radii r, uint which) { return which == COVERAGE ? cover_reach(r) : conflict_reach(r); }

const uint MAX_REACH = 3u;

VRPD_END
#endif
