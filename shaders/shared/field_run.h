// The sizing-field sampler's tests as its Vulkan kernels make them (the host's: field/cover.cpp):
// a point's conflict with the samples, whether one sample covers a block, which children of a
// cell stay open, and the reaches their searches take. Each answers the same predicate the host
// answers (exact integer tests on the same table); only the searches differ, which need only meet
// every sample that can matter: a wider reach changes the work, not the answer. Derivations:
// docs/design.md, "Sizing fields".
#ifndef VRPD_FIELD_RUN_H
#define VRPD_FIELD_RUN_H
#include "bridge.h"
#include "field.h"
#include "field_search.h"
#include "field_table.h"
#include "field_tree.h"
#include "lattice.h"

#ifndef __cplusplus
layout(buffer_reference, std430, buffer_reference_align = 8) buffer FieldPoints { uvec2 value[]; };
#endif

VRPD_BEGIN

#ifdef __cplusplus
struct FieldPoints {
    const uvec2* value;
};
#endif

// A field kernel's variant (specialization constant 1, kernel.h): the run's rule (RULE_*),
// FIELD_VARIANT_TORUS where its box is a torus, FIELD_VARIANT_DENSITY under Eq. 12's weighting.
const uint FIELD_VARIANT_TORUS = 4u;
const uint FIELD_VARIANT_DENSITY = 8u;
VRPD_FN uint field_variant(uint rule, bool torus, bool density) {
    return rule | (torus ? FIELD_VARIANT_TORUS : 0u) | (density ? FIELD_VARIANT_DENSITY : 0u);
}

// A leaf's sample slot when it holds none.
const uint FIELD_NO_SAMPLE = 0xFFFFFFFFu;

// A cell's fate when a list is balanced or refined: dropped (0), kept whole, or split, with the
// mask of its surviving children in bits 0-3 (child k: x, then y, low first).
const uint FIELD_KEEP = 0x10u;
const uint FIELD_SPLIT = 0x20u;

// The run as the kernels read it (one copy in a buffer; FieldArgs points at it).
struct FieldRun {
    FieldTableView table;
    FieldTreeView tree;
    Lattice lattice;
    uint rule;
    uint r_hi;               // the field's largest r
    uint r_lo;               // and least
    uint budget;             // the search steps an invocation may take (field_search.h)
    uint growth;             // 1 / (1 - L) in 2^-16 units, rounded up; 0 where L >= 1
    FieldWords leaf_sample;  // per leaf: its sample, or FIELD_NO_SAMPLE
    FieldPoints points;      // per sample: its lattice point
    FieldWords radii;        // and its r
    // Per leaf, the last round's stamp k (from 1) one of whose samples may cover part of it, or
    // conflict with a point of it (field_touch.comp): 2 k + 1 where one of them covers all of it,
    // else 2 k; 0 if none has yet.
    FieldWords touched;
    // Per inner node of the tree (at its children's index / 4), the least arrival key of the
    // round's darts below it (field_resolve.comp), for FieldGate.
    FieldWords keys;
    // Per leaf, while a round's darts are resolved, the first of them in it, where it holds some
    // (field_first_darts.comp); between resolutions, a sample near it (FIELD_NO_SAMPLE: none
    // yet), which the throw tests a dart against before it searches: one that stamped the leaf
    // (field_touch.comp) or rejected a dart there. A first dart's index left over stands for a
    // sample too where it is below the samples' count (any sample's test is a true one).
    FieldWords leaf_first;
};

// The push constants of the field sampler's kernels (shaders/field_*.comp): the run, the buffers
// each kernel reads and writes (by its own reading of them), the host's counters, and items
// [first, count) of the dispatch, with up to four parameters. A count or parameter with
// FIELD_COUNTED set is counter slot (value & ~FIELD_COUNTED)'s value on the device: a list whose
// length a scan earlier in the same submit found (the dispatch covers a bound on it).
struct FieldArgs {
    uint64_t run;     // the FieldRun
    uint64_t cells;   // the active list (uvec4: corner, side's bits, weight)
    uint64_t target;  // a list written (cells or darts)
    uint64_t words0;  // uint arrays
    uint64_t words1;
    uint64_t words2;
    uint64_t counters;  // host-visible (FIELD_COUNTER_*)
    uint count;
    uint first;
    uint p0;
    uint p1;
    uint p2;
    uint p3;
};

// The counters' words: a search past its budget, darts left undecided by a resolution pass, the
// least side's bits in a list written, cells split by balance, the scans' totals, the cells
// with darts this round, the
// resolution's two work lists (FIELD_COUNTER_WORK + 4 k: an indirect dispatch's workgroups x,
// y, z, then list k's length), and the written list's cells per exponent of their weighted area
// (+ FIELD_EXPONENT_BIAS).
const uint FIELD_COUNTER_OVERFLOW = 0u;
const uint FIELD_COUNTER_UNDECIDED = 1u;
const uint FIELD_COUNTER_LEAST_BITS = 2u;
const uint FIELD_COUNTER_SPLITS = 3u;
const uint FIELD_COUNTER_TOTAL = 4u;
const uint FIELD_COUNTER_DART_CELLS = 12u;
const uint FIELD_COUNTER_WORK = 16u;
const uint FIELD_COUNTER_EXPONENTS = 24u;
const uint FIELD_EXPONENT_BIAS = 64u;
const uint FIELD_COUNTER_WORDS = FIELD_COUNTER_EXPONENTS + 128u;
const uint FIELD_COUNTED = 0x80000000u;
// Refinement's flag (field_triage.comp's p0, field_fates.comp's beside the list): every open cell
// splits, not only those that took darts (field::splits_every_cell).
const uint FIELD_SPLIT_EVERY = 2u;

// The search steps an invocation has left, and whether it ran out (then its answers are void
// and the run stops with an error).
struct FieldBudget {
    uint left;
    uint overflow;
};

// A search around [a, b] on the budget's remaining steps.
VRPD_FN FieldSearch field_run_search(VRPD_IN(FieldRun) run, uvec2 a, uvec2 b, uint64_t reach, uint need,
                                     VRPD_IN(FieldBudget) budget) {
    return field_search_begin(run.tree, run.lattice, a, b, reach, need, budget.left);
}
#ifdef FIELD_SEARCH_GATED
// Gates search s around point p of radius r (shared/field_search.h): of reach, the searched
// leaves' points earlier (later == 0) or later than p.
VRPD_FN void field_run_gate(VRPD_IN(FieldRun) run, VRPD_INOUT(FieldSearch) s, uvec2 p, uint r, uint later) {
    field_search_gate_reach(s, run.table, run.lattice, run.rule, run.r_hi, p, r, later);
}
#endif
// Takes a search's steps from the budget.
VRPD_FN void field_run_spend(VRPD_IN(FieldSearch) s, VRPD_INOUT(FieldBudget) budget) {
    if (s.steps > s.budget) {
        budget.overflow = 1u;
        budget.left = 0u;
    } else {
        budget.left -= s.steps;
    }
}

// The greatest r at the lattice points of the square `reach` around [a, b] (on a torus, around
// any image; on a free box, clipped to it): each axis as one or two ranges, a bound from the table
// over each of the up to four blocks.
VRPD_FN uint field_max_near(VRPD_IN(FieldRun) run, uvec2 a, uvec2 b, uint64_t reach) {
    uint from_x[2];
    uint to_x[2];
    uint from_y[2];
    uint to_y[2];
    uint nx = 1u;
    uint ny = 1u;
    for (uint axis = 0u; axis < 2u; axis++) {
        uint extent = axis == 0u ? run.lattice.extent_x : run.lattice.extent_y;
        int64_t lo = int64_t(axis == 0u ? a.x : a.y) - int64_t(reach);
        int64_t hi = int64_t(axis == 0u ? b.x : b.y) + int64_t(reach);
        uint f0 = 0u;
        uint t0 = extent - 1u;
        uint f1 = 0u;
        uint t1 = 0u;
        uint n = 1u;
        if (run.lattice.periodic == 0u) {
            f0 = uint(max(lo, int64_t(0)));
            t0 = uint(min(hi, int64_t(extent) - 1));
        } else if (hi - lo + 1 < int64_t(extent)) {
            if (lo < 0) {
                t0 = uint(hi);
                f1 = uint(lo + int64_t(extent));
                t1 = extent - 1u;
                n = 2u;
            } else if (hi >= int64_t(extent)) {
                f0 = uint(lo);
                f1 = 0u;
                t1 = uint(hi - int64_t(extent));
                n = 2u;
            } else {
                f0 = uint(lo);
                t0 = uint(hi);
            }
        }
        if (axis == 0u) {
            from_x[0] = f0;
            to_x[0] = t0;
            from_x[1] = f1;
            to_x[1] = t1;
            nx = n;
        } else {
            from_y[0] = f0;
            to_y[0] = t0;
            from_y[1] = f1;
            to_y[1] = t1;
            ny = n;
        }
    }
    uint m = 0u;
    for (uint j = 0u; j < ny; j++)
        for (uint i = 0u; i < nx; i++)
            m = max(m, field_max_over(run.table, uvec2(from_x[i], from_y[j]), uvec2(to_x[i], to_y[j])));
    return m;
}

// How far from [a, b] a sample x can be whose r(x) matters, when f <= max(r(x), r_hi) and r_hi
// >= r over [a, b]: from the Lipschitz growth (r(z) <= r_hi + L |z - [a, b]| + 1, L the table's,
// so such an x is within (r_hi + 1) / (1 - L)) or the field's largest r, then the largest r
// within the reach found so far, while that shrinks it.
VRPD_FN uint field_grown_reach(VRPD_IN(FieldRun) run, uvec2 a, uvec2 b, uint r_hi) {
    uint rho = max(run.r_hi, r_hi);
    if (run.growth != 0u)
        rho = uint(min(uint64_t(rho), ((uint64_t(r_hi) + 1u) * uint64_t(run.growth) + 0xFFFFu) / 65536u + 2u));
    for (uint k = 0u; k < 4u; k++) {
        uint m = max(field_max_near(run, a, b, uint64_t(rho)), r_hi);
        if (m >= rho) break;
        rho = m;
    }
    return rho;
}

// How far from [a, b] an earlier sample x can be when f(r(x), r(y)) passes its distance to some
// point y of [a, b], given r_hi >= r over [a, b]: r_hi where f is at most the later point's r
// (current, smaller); else (prior, bigger) f <= max(r(x), r_hi), the grown reach.
VRPD_FN uint field_reach(VRPD_IN(FieldRun) run, uvec2 a, uvec2 b, uint r_hi) {
    if (run.rule == RULE_CURRENT || run.rule == RULE_SMALLER) return r_hi;
    return field_grown_reach(run, a, b, r_hi);
}

// How far a sample x of radius r may cover a point y, or conflict with a later point y: f <= r
// under prior and smaller; else (current, bigger) f <= max(r, r(y)), the grown reach.
VRPD_FN uint field_cover_reach(VRPD_IN(FieldRun) run, uvec2 x, uint r) {
    if (run.rule == RULE_PRIOR || run.rule == RULE_SMALLER) return r;
    return field_grown_reach(run, x, x, r);
}

// Does sample s cover every point of [a, b], given r's least value `lo` over it?
VRPD_FN bool field_covers(VRPD_IN(FieldRun) run, uint s, uint lo, uvec2 a, uvec2 b) {
    uint f = rule_f(run.rule, run.radii.value[s], lo);
    return field_conflict(f, far_distance2(run.lattice, run.points.value[s], a, b));
}

// Does sample x conflict with point p of radius r, a later point?
VRPD_FN bool field_conflicts_with(VRPD_IN(FieldRun) run, uint x, uvec2 p, uint r) {
    return field_conflict(rule_f(run.rule, run.radii.value[x], r), distance2(run.lattice, run.points.value[x], p));
}

// A sample in conflict with point p of radius r, a later point, or FIELD_NO_SAMPLE. (p's leaf
// holds no sample.)
VRPD_FN uint field_conflicting(VRPD_IN(FieldRun) run, uvec2 p, uint r, VRPD_INOUT(FieldBudget) budget) {
    FieldSearch s = field_run_search(run, p, p, uint64_t(field_reach(run, p, p, r)), FIELD_OCCUPIED, budget);
    uint found = FIELD_NO_SAMPLE;
    for (uint leaf = field_search_next(run.tree, s); leaf < FIELD_SEARCH_OVERFLOW;
         leaf = field_search_next(run.tree, s)) {
        uint x = run.leaf_sample.value[leaf];
        if (field_conflicts_with(run, x, p, r)) {
            found = x;
            break;
        }
    }
    field_run_spend(s, budget);
    return found;
}

// Does one sample in a leaf flagged `need` (FIELD_FRESH: this round's) cover every point of [a, b]?
VRPD_FN bool field_covered(VRPD_IN(FieldRun) run, uvec2 a, uvec2 b, uint need, VRPD_INOUT(FieldBudget) budget) {
    uvec2 range = field_extremes_over(run.table, a, b);
    // A cover's f is at most the block's least r under current and smaller; else within the reach.
    bool own = run.rule == RULE_CURRENT || run.rule == RULE_SMALLER;
    uint reach = own ? range.x : field_reach(run, a, b, range.y);
    FieldSearch s = field_run_search(run, a, b, uint64_t(reach), need, budget);
    bool found = false;
    for (uint leaf = field_search_next(run.tree, s); leaf < FIELD_SEARCH_OVERFLOW;
         leaf = field_search_next(run.tree, s))
        if (field_covers(run, run.leaf_sample.value[leaf], range.x, a, b)) {
            found = true;
            break;
        }
    field_run_spend(s, budget);
    return found;
}

// The last lattice point of the block of side 2^bits at `corner`, clipped to the lattice.
VRPD_FN uvec2 field_far_corner(Lattice l, uvec2 corner, uint bits) {
    uint64_t s = (uint64_t(1) << bits) - uint64_t(1);
    return uvec2(uint(min(uint64_t(corner.x) + s, uint64_t(l.extent_x - 1u))),
                 uint(min(uint64_t(corner.y) + s, uint64_t(l.extent_y - 1u))));
}

// The mask of the children (bit k: child k, x then y, low first) of the cell of side 2^bits at
// `corner` (bits >= 1) that lie in the lattice and that no sample covers wholly.
VRPD_FN uint field_open_children(VRPD_IN(FieldRun) run, uvec2 corner, uint bits, VRPD_INOUT(FieldBudget) budget) {
    uint side = 1u << (bits - 1u);
    uvec2 a = corner;
    uvec2 b = field_far_corner(run.lattice, corner, bits);
    uvec2 ka[4];
    uvec2 kb[4];
    uint open = 0u;
    for (uint k = 0u; k < 4u; k++) {
        ka[k] = uvec2(corner.x + (k & 1u) * side, corner.y + (k >> 1u) * side);
        kb[k] = field_far_corner(run.lattice, ka[k], bits - 1u);
        if (ka[k].x < run.lattice.extent_x && ka[k].y < run.lattice.extent_y) open |= 1u << k;
    }
    uvec4 lo = run.rule == RULE_PRIOR ? uvec4(0u) : field_children_min(run.table, a, kb[0], ka[3], b, open);
    // A sample covering a child lies within its f of the whole child, inside the cell.
    uint reach = field_reach(run, a, b, field_max_over(run.table, a, b));
    FieldSearch s = field_run_search(run, a, b, uint64_t(reach), FIELD_OCCUPIED, budget);
    for (uint leaf = field_search_next(run.tree, s); leaf < FIELD_SEARCH_OVERFLOW && open != 0u;
         leaf = field_search_next(run.tree, s)) {
        uint x = run.leaf_sample.value[leaf];
        s.steps += 4u;  // the passes over the children
        for (uint k = 0u; k < 4u; k++)
            if ((open >> k & 1u) != 0u && field_covers(run, x, lo[k], ka[k], kb[k])) open &= ~(1u << k);
    }
    field_run_spend(s, budget);
    return open;
}

VRPD_END
#endif
