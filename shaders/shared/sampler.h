// The bodies of the sampler's kernels (one base cell, active cell or dart each), shared by the
// Vulkan shaders and the CPU backends. No kernel reads what another invocation of the same pass
// writes: the passes are race-free on every device, and their results do not depend on timing. Flat-quadtree maximal Poisson-disk sampling (Ebeida et al. 2012)
// driven as exact random sequential adsorption: paper section 1, Eqs. 1-4.
#ifndef VRPD_SAMPLER_H
#define VRPD_SAMPLER_H
#include "bridge.h"
#include "coverage.h"
#include "darts.h"
#include "domain.h"
#include "kernels.h"

VRPD_BEGIN

VRPD_FN uint base_of_point(Domain dom, uvec2 p) { return base_index(dom, base_cell_of(dom, p)); }

// Active cells are ordered by base cell, so the darts of one base cell are one contiguous range.
VRPD_FN bool first_in_base_cell(Domain dom, Cells cells, uint e) {
    return e == 0u || base_of_point(dom, cells.cell[e - 1u]) != base_of_point(dom, cells.cell[e]);
}

// The active cells after e that share its base cell: [e, group_end).
VRPD_FN uint group_end(Domain dom, Cells cells, uint e, uint count) {
    uint b = base_of_point(dom, cells.cell[e]);
    uint end = e + 1u;
    while (end < count && base_of_point(dom, cells.cell[end]) == b) end++;
    return end;
}

// For the first active cell e of a base cell: the grid word of the base cell becomes the range of
// this round's darts in it (the exclusive prefix sums of the counts). A pass of its own, so that
// throwing, which reads the neighbours' words, never races with this write.
VRPD_FN void mark_dart_range(CellArgs a, Cells cells, Uints scan, Grid grid, uint e) {
    uint end_cell = group_end(a.domain, cells, e, a.cell_count);
    grid.word[base_of_point(a.domain, cells.cell[e])] = uvec2(GRID_TAG | scan.value[e], scan.value[end_cell]);
}

// Is point p closer than sqrt(limit2) (radius2 or cover2, with its reach) to a sample of an earlier
// round? The samples near base cell `base` are read from the grid; dom is local_domain(base).
VRPD_FN bool near_sample(Domain dom, Grid grid, uvec2 base, uvec2 p, uint64_t limit2, int reach) {
    bool inner = inner_cell(dom, base);
    for (int dy = -reach; dy <= reach; dy++) {
        int row = row_reach(dom, dy, reach, limit2);
        for (int dx = -row; dx <= row; dx++) {
            uint nb = neighbour_index(dom, base, inner, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (grid_is_sample(w) && distance2(dom, w, p) < limit2) return true;
        }
    }
    return false;
}

// Is point p in the disk of a sample of an earlier round (or off the domain)?
VRPD_FN bool covered_by_sample(Domain dom, Grid grid, uvec2 base, uvec2 p) {
    return !in_domain(dom, p) || near_sample(dom, grid, base, p, dom.radius2, conflict_reach(dom));
}

// Two radii: does the closed Rc-disk around p reach a point of the domain outside the open Rc-disks
// around disk_at[0, n) (offsets from p)? A free boundary's box is passed as offsets from p.
// T_INSIDE, T_OUTSIDE or T_UNKNOWN (see coverage.h).
VRPD_FN uint reaches_uncovered_at(Domain dom, uvec2 p, uint n) {
    ivec2 lo = ivec2(-FAR_SIDE, -FAR_SIDE);
    ivec2 hi = ivec2(FAR_SIDE, FAR_SIDE);
    if (dom.periodic == 0u) {
        lo = max(lo, -ivec2(p));
        hi = min(hi, ivec2(dom.lattice_x - 1u - p.x, dom.lattice_y - 1u - p.y));
    }
    return reaches_uncovered(n, dom.cover2, lo, hi, true);
}

// Two radii: fills disk_at with the samples whose Rc-disk meets the box [cc, cc + hi] (hi >= 0),
// as offsets from cc: only they can cover a point of it or cross inside it. Returns the count,
// MAX_DISKS + 1 if they do not fit.
VRPD_FN uint gather_near_box(Domain dom, Grid grid, uvec2 base, uvec2 cc, ivec2 hi) {
    uint n = 0u;
    int reach = cover_reach(dom);
    bool inner = inner_cell(dom, base);
    for (int dy = -reach; dy <= reach; dy++) {
        int row = row_reach(dom, dy, reach, dom.cover2 + uint64_t(1));
        for (int dx = -row; dx <= row; dx++) {
            uint nb = neighbour_index(dom, base, inner, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (!grid_is_sample(w)) continue;
            ivec2 o = offset_to(dom, cc, w);
            int64_t gx = int64_t(max(max(-o.x, o.x - hi.x), 0));
            int64_t gy = int64_t(max(max(-o.y, o.y - hi.y), 0));
            if (uint64_t(gx * gx + gy * gy) > dom.cover2) continue;
            if (n == MAX_DISKS) return MAX_DISKS + 1u;
            disk_at[n++] = o;
        }
    }
    return n;
}

// Early acceptance is tried with at most this many undecided darts before d within 2 Rc: its T
// test, with them counted as accepted, grows as n^3.
const uint EARLY_UNDECIDED = 4u;
VRPD_PRIVATE ivec2 undecided_at[EARLY_UNDECIDED];

// Two radii, in one scan of the 2 Rc neighbourhood of dart d: fills disk_at with the samples of
// earlier rounds and this round's accepted darts before d (offsets from d). Returns their count,
// MAX_DISKS + 1 if they do not fit (the scan then stops). `conflict`: an accepted dart is closer
// than Rf. `undecided` counts the undecided darts before d there, the first EARLY_UNDECIDED of
// which go to undecided_at; `undecided_conflict`: one of those is closer than Rf.
VRPD_FN uint gather_accepted(Domain dom, Grid grid, Darts darts, uint d, VRPD_OUT(bool) conflict, VRPD_OUT(uint) undecided,
                             VRPD_OUT(bool) undecided_conflict) {
    uvec4 me = dart_at(darts, d);
    uvec2 p = uvec2(me.x, me.y);
    uvec2 cell = base_cell_of(dom, p);
    int reach = int(influence_reach(dom));
    bool inner = inner_cell(dom, cell);
    uint64_t limit2 = influence2(dom);
    uint n = 0u;
    conflict = false;
    undecided = 0u;
    undecided_conflict = false;
    for (int dy = -reach; dy <= reach; dy++) {
        int row = row_reach(dom, dy, reach, limit2);
        for (int dx = -row; dx <= row; dx++) {
            uint nb = neighbour_index(dom, cell, inner, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (grid_is_sample(w) && distance2(dom, p, w) < limit2) {
                if (n == MAX_DISKS) return MAX_DISKS + 1u;
                disk_at[n++] = offset_to(dom, p, w);
            }
            if (!grid_is_darts(w)) continue;
            uvec2 range = grid_darts(w);
            for (uint j = range.x; j < range.y; j++) {
                uvec4 other = dart_at(darts, j);
                if (j == d || other.w == DART_REJECTED || !arrives_before(other.z, j, me.z, d)) continue;
                uint64_t gap2 = distance2(dom, p, uvec2(other.x, other.y));
                if (gap2 >= limit2) continue;
                if (other.w == DART_UNDECIDED) {
                    if (undecided < EARLY_UNDECIDED) undecided_at[undecided] = offset_to(dom, p, uvec2(other.x, other.y));
                    undecided_conflict = undecided_conflict || gap2 < dom.radius2;
                    undecided++;
                    continue;
                }
                conflict = conflict || gap2 < dom.radius2;
                if (n == MAX_DISKS) return MAX_DISKS + 1u;
                disk_at[n++] = offset_to(dom, p, uvec2(other.x, other.y));
            }
        }
    }
    return n;
}

// Throwing writes a base cell's darts in index order; their states are or-ed into their blocks'
// state words (darts.h) once per word, not once per dart: each atomic costs.
struct StateBits {
    uint word;
    uint bits;
};
VRPD_FN StateBits no_state_bits(uint j) {
    StateBits s;
    s.word = dart_state_word(j);
    s.bits = 0u;
    return s;
}
// Adds dart j's state, first or-ing the bits gathered for an earlier block.
VRPD_FN StateBits add_state(Darts darts, StateBits s, uint j, uint state) {
    if (dart_state_word(j) != s.word) {
        or_dart_states(darts, s.word, s.bits);
        s = no_state_bits(j);
    }
    s.bits |= state << dart_state_shift(j);
    return s;
}

// Writes the `count` darts of the cell at `corner` (side `side`, random stream `stream`) from
// index `first` on, each rejected if it lies off the domain or in the disk of a sample of an
// earlier round; gathers their states in `states` and counts the undecided ones. `no_samples`:
// the grid holds no sample yet (a run's first round), so only the domain is tested. Scanning an
// empty grid for each of the first round's darts took 3.3 % of the cpu's instructions at
// r = 0.002, and 0.2 of lavapipe's 1.4 s in throw_masked at r = 0.001.
VRPD_FN void throw_cell(Domain dom, Grid grid, uvec2 base, Darts darts, uint stream, uvec2 corner, uint side, uint first,
                        uint count, VRPD_INOUT(StateBits) states, VRPD_INOUT(uint) undecided, bool no_samples) {
    for (uint i = 0u; i < count; i++) {
        uvec4 dart = make_dart(stream, i, corner, side);
        uvec2 p = uvec2(dart.x, dart.y);
        bool rejected = no_samples ? !in_domain(dom, p) : covered_by_sample(dom, grid, base, p);
        undecided += rejected ? 0u : 1u;
        store_dart_record(darts, first + i, dart);
        states = add_state(darts, states, first + i, rejected ? DART_REJECTED : DART_UNDECIDED);
    }
}

// For the first active cell e of a base cell: writes the darts of all active cells of that base
// cell (cell i's at scan[i] .. scan[i+1]), each rejected if it lies off the domain or in the disk
// of a sample of an earlier round (with two radii, membership in T is left to the resolution,
// which sees this round's earlier darts as well). Each dart is made, tested and written once (on GPUs each
// buffer access costs; most base cells have 0-2 darts). Returns how many are still undecided.
VRPD_FN uint throw_base_cell(CellArgs a, Cells cells, Uints scan, Darts darts, Grid grid, uint e) {
    uint end_cell = group_end(a.domain, cells, e, a.cell_count);
    uvec2 base = base_cell_of(a.domain, cells.cell[e]);
    Domain dom = local_domain(a.domain, base);
    uint undecided = 0u;
    StateBits states = no_state_bits(scan.value[e]);
    for (uint i = e; i < end_cell; i++) {
        uint cell_first = scan.value[i];
        uint cell_end = scan.value[i + 1u];
        if (cell_first == cell_end) continue;
        uvec2 corner = cells.cell[i];
        uint stream = cell_stream(a.domain.seed, a.round, corner);
        throw_cell(dom, grid, base, darts, stream, corner, a.side, cell_first, cell_end - cell_first, states, undecided, false);
    }
    or_dart_states(darts, states.word, states.bits);
    return undecided;
}

// Two radii: what lies within Rc of dart d (at p, in base cell `cell`), as bits: NEAR_* below.
// Samples of earlier rounds count as accepted; darts count only if they arrive before d.
const uint NEAR_ACCEPTED_RF = 1u;   // a sample or accepted dart closer than Rf
const uint NEAR_ACCEPTED_RC = 2u;   // ... closer than Rc
const uint NEAR_UNDECIDED_RF = 4u;  // an undecided dart closer than Rf
const uint NEAR_UNDECIDED_RC = 8u;  // ... closer than Rc
VRPD_FN uint census(Domain dom, Grid grid, Darts darts, uint d, uvec2 p, uvec2 cell) {
    uint key = dart_at(darts, d).z;
    uint found = 0u;
    int reach = cover_reach(dom);
    bool inner = inner_cell(dom, cell);
    for (int dy = -reach; dy <= reach; dy++) {
        int row = row_reach(dom, dy, reach, dom.cover2);
        for (int dx = -row; dx <= row; dx++) {
            uint nb = neighbour_index(dom, cell, inner, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (grid_is_sample(w)) {
                uint64_t g = distance2(dom, w, p);
                found |= (g < dom.cover2 ? NEAR_ACCEPTED_RC : 0u) | (g < dom.radius2 ? NEAR_ACCEPTED_RF : 0u);
                continue;
            }
            if (!grid_is_darts(w)) continue;
            uvec2 range = grid_darts(w);
            for (uint j = range.x; j < range.y; j++) {
                uvec4 other = dart_at(darts, j);
                if (j == d || other.w == DART_REJECTED || !arrives_before(other.z, j, key, d)) continue;
                uint64_t g = distance2(dom, uvec2(other.x, other.y), p);
                uint shift = other.w == DART_ACCEPTED ? 0u : 2u;
                found |= ((g < dom.cover2 ? NEAR_ACCEPTED_RC : 0u) | (g < dom.radius2 ? NEAR_ACCEPTED_RF : 0u)) << shift;
            }
        }
    }
    return found;
}

// Two radii, the textbook decision for the serial backend: the state of dart d (at p, in base
// cell `cell`) given the samples and this round's darts accepted before it: rejected (one is
// closer than Rf, or d is outside T), accepted, or DART_TOO_COMPLEX (coverage.h's bounds).
// Cheap tests first: a conflict within Rf, and a dart that nothing covers is in U, so in T.
VRPD_FN uint state_given_accepted(Domain dom, Grid grid, Darts darts, uint d, uvec2 p, uvec2 cell) {
    uint near = census(dom, grid, darts, d, p, cell);
    if ((near & NEAR_ACCEPTED_RF) != 0u) return DART_REJECTED;
    if ((near & NEAR_ACCEPTED_RC) == 0u) return DART_ACCEPTED;
    bool conflict;
    uint undecided;
    bool undecided_conflict;
    uint n = gather_accepted(dom, grid, darts, d, conflict, undecided, undecided_conflict);
    if (conflict) return DART_REJECTED;
    uint t = n <= MAX_DISKS ? reaches_uncovered_at(dom, p, n) : T_UNKNOWN;
    return t == T_INSIDE ? DART_ACCEPTED : (t == T_OUTSIDE ? DART_REJECTED : DART_TOO_COMPLEX);
}

// One step of the exact parallel resolution of a round: dart d is accepted once every earlier
// conflicting dart (in arrival order) is rejected, and rejected as soon as one is accepted.
// Decisions are only taken when they are final, so the outcome is the sequential process's.
// A pass reads the states left by the previous pass and applies its decisions after it
// (Jacobi): no invocation reads a state another one is writing.
//
// With two radii a dart is accepted iff it is free and in T given the samples and the darts
// accepted before it. Both only shrink as earlier darts are accepted, so: rejected as soon as the
// accepted ones exclude it; accepted once it is free of, and in T despite, all the undecided too.
VRPD_FN uint resolve_dart_two_radii(Domain global, Grid grid, Darts darts, uint d) {
    uvec4 me = dart_at(darts, d);
    uvec2 p = uvec2(me.x, me.y);
    uvec2 cell = base_cell_of(global, p);
    Domain dom = local_domain(global, cell);
    // Cheap cases first. A conflict rejects d. If nothing covers d, even counting the undecided
    // darts before it, d is in U, so in T, whatever they become: accepted. An undecided dart closer
    // than Rf blocks d until it is decided (d may yet be rejected by T; that can wait).
    uint near = census(dom, grid, darts, d, p, cell);
    if ((near & NEAR_ACCEPTED_RF) != 0u) return DART_REJECTED;
    if ((near & (NEAR_ACCEPTED_RC | NEAR_UNDECIDED_RC)) == 0u) return DART_ACCEPTED;
    if ((near & NEAR_UNDECIDED_RF) != 0u) return DART_UNDECIDED;
    bool conflict;
    uint undecided;
    bool undecided_conflict;
    uint n = gather_accepted(dom, grid, darts, d, conflict, undecided, undecided_conflict);
    if (conflict) return DART_REJECTED;
    // Many undecided darts around: d waits (the earliest undecided dart of any neighbourhood always
    // decides, so the passes end), and its T test with them, growing as n^3, is not tried.
    if (undecided > EARLY_UNDECIDED) return DART_UNDECIDED;
    uint t = n <= MAX_DISKS ? reaches_uncovered_at(dom, p, n) : T_UNKNOWN;
    if (t != T_INSIDE) return t == T_OUTSIDE ? DART_REJECTED : DART_TOO_COMPLEX;
    if (undecided == 0u) return DART_ACCEPTED;
    if (undecided_conflict || n + undecided > MAX_DISKS) return DART_UNDECIDED;
    for (uint i = 0u; i < undecided; i++) disk_at[n + i] = undecided_at[i];
    return reaches_uncovered_at(dom, p, n + undecided) == T_INSIDE ? DART_ACCEPTED : DART_UNDECIDED;
}

// `none_accepted`: no dart of the round is accepted yet (the Vulkan engine's first pass), so the
// first earlier undecided dart in conflict leaves d undecided: no accepted one can follow it.
// Stopping there cut lavapipe's first passes at r = 0.001 from 1.17 s to 0.92 s (round 0's from
// 0.66 s to 0.51 s, where four in five darts wait).
VRPD_FN uint resolve_dart(Domain global, Grid grid, Darts darts, uint d, bool none_accepted) {
#ifndef VRPD_ONE_RADIUS
    if (two_radii(global)) return resolve_dart_two_radii(global, grid, darts, d);
#endif
    uvec4 me = dart_at(darts, d);
    uvec2 p = uvec2(me.x, me.y);
    uvec2 cell = base_cell_of(global, p);
    Domain dom = local_domain(global, cell);
    bool waiting = false;
    int reach = conflict_reach(dom);
    bool inner = inner_cell(dom, cell);
    for (int dy = -reach; dy <= reach; dy++) {
        int row = row_reach(dom, dy, reach, dom.radius2);
        for (int dx = -row; dx <= row; dx++) {
            uint nb = neighbour_index(dom, cell, inner, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (!grid_is_darts(w)) continue;
            uvec2 range = grid_darts(w);
            for (uint j = range.x; j < range.y; j++) {
                if (j == d) continue;
                uvec4 other = dart_at(darts, j);
                if (other.w == DART_REJECTED || !arrives_before(other.z, j, me.z, d)) continue;
                if (!in_disk(dom, uvec2(other.x, other.y), p)) continue;
                if (other.w == DART_ACCEPTED) return DART_REJECTED;
                if (none_accepted) return DART_UNDECIDED;
                waiting = true;
            }
        }
    }
    return waiting ? DART_UNDECIDED : DART_ACCEPTED;
}

// The cpu backend decides each dart once, not in passes (HostEngine::resolve): when resolve_dart
// leaves d undecided, a dart d waits for is decided first, and d is tried again. This finds one:
// an undecided dart before d within its influence radius (Rf, or 2 Rc with two radii), which
// exists whenever resolve_dart leaves d undecided; GRID_EMPTY if there is none.
VRPD_FN uint undecided_before(Domain global, Grid grid, Darts darts, uint d) {
    uvec4 me = dart_at(darts, d);
    uvec2 p = uvec2(me.x, me.y);
    uvec2 cell = base_cell_of(global, p);
    Domain dom = local_domain(global, cell);
    int reach = int(influence_reach(dom));
    uint64_t limit2 = two_radii(dom) ? influence2(dom) : dom.radius2;
    bool inner = inner_cell(dom, cell);
    for (int dy = -reach; dy <= reach; dy++) {
        int row = row_reach(dom, dy, reach, limit2);
        for (int dx = -row; dx <= row; dx++) {
            uint nb = neighbour_index(dom, cell, inner, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (!grid_is_darts(w)) continue;
            uvec2 range = grid_darts(w);
            for (uint j = range.x; j < range.y; j++) {
                uvec4 other = dart_at(darts, j);
                if (j != d && other.w == DART_UNDECIDED && arrives_before(other.z, j, me.z, d) &&
                    distance2(dom, p, uvec2(other.x, other.y)) < limit2)
                    return j;
            }
        }
    }
    return GRID_EMPTY;
}

// The textbook test, for the serial backend, given the darts of this round accepted so far: the
// state of d (rejected if one is closer than Rf; with two radii, also if d is outside T).
VRPD_FN uint serial_decision(Domain global, Grid grid, Darts darts, uint d) {
    uvec4 me = dart_at(darts, d);
    uvec2 p = uvec2(me.x, me.y);
    uvec2 cell = base_cell_of(global, p);
    Domain dom = local_domain(global, cell);
    if (two_radii(global)) return state_given_accepted(dom, grid, darts, d, p, cell);
    int reach = conflict_reach(dom);
    bool inner = inner_cell(dom, cell);
    for (int dy = -reach; dy <= reach; dy++) {
        int row = row_reach(dom, dy, reach, dom.radius2);
        for (int dx = -row; dx <= row; dx++) {
            uint nb = neighbour_index(dom, cell, inner, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 w = grid.word[nb];
            if (!grid_is_darts(w)) continue;
            uvec2 range = grid_darts(w);
            for (uint j = range.x; j < range.y; j++) {
                uvec4 other = dart_at(darts, j);
                if (j != d && other.w == DART_ACCEPTED && in_disk(dom, uvec2(other.x, other.y), p)) return DART_REJECTED;
            }
        }
    }
    return DART_ACCEPTED;
}

// The word of a base cell whose darts word is w after a round without a sample in it: empty,
// keeping the mask of its active sub-cells in mask mode.
VRPD_FN uvec2 empty_after_round(uvec2 w) {
    return uvec2(GRID_EMPTY, (w.x & GRID_PACKED) != 0u ? (w.y & GRID_MASK_BITS) : GRID_EMPTY);
}

// The word base cell b keeps after its round (its word is a darts word): the accepted dart, if
// any (at most one: the base cell's diagonal is shorter than r), else empty_after_round.
VRPD_FN uvec2 committed_word(Darts darts, uvec2 w) {
    uvec2 range = grid_darts(w);
    for (uint j = range.x; j < range.y; j++) {
        uvec4 dart = dart_at(darts, j);
        if (dart.w == DART_ACCEPTED) return uvec2(dart.x, dart.y);
    }
    return empty_after_round(w);
}

// Ends the round for the base cell of active cell e (called for the first active cell of each
// base cell): the grid word becomes committed_word's; flags[j] = 1 marks accepted darts for
// emission. (One loop with the flags, not a call of committed_word: each buffer read costs.)
// A dart left DART_TOO_COMPLEX sets counters[COUNTER_TOO_COMPLEX]: the engine fails the run.
VRPD_FN void commit_base_cell(Grid grid, Darts darts, Uints flags, Uints counters, uint b) {
    uvec2 w = grid.word[b];
    uvec2 result = empty_after_round(w);
    uvec2 range = grid_darts(w);
    for (uint j = range.x; j < range.y; j++) {
        uvec4 dart = dart_at(darts, j);
        if (dart.w == DART_TOO_COMPLEX) set_flag(counters, COUNTER_TOO_COMPLEX);
        bool accepted = dart.w == DART_ACCEPTED;
        flags.value[j] = accepted ? 1u : 0u;
        if (accepted) result = uvec2(dart.x, dart.y);
    }
    grid.word[b] = result;
}

// Two radii. The active cells track where U (points >= Rc from every sample) may remain; the darts
// go to base cells instead. For the first active cell e of a base cell: flags every base cell that
// holds no sample and lies within Rc of the base cell's active cells. Each point of T is free, so
// its base cell holds no sample, and within Rc of U, which lies in the active cells: the flagged
// cells cover T, and darts uniform over them, kept iff in T (exact test), are uniform over T.
VRPD_FN void flag_dart_cells(CellArgs a, Cells cells, Uints flags, Grid grid, uint e) {
    Domain dom = a.domain;
    uint end_cell = group_end(dom, cells, e, a.cell_count);
    uvec2 base = base_cell_of(dom, cells.cell[e]);
    int side = 1 << dom.cell_bits;
    uvec2 origin = uvec2(base.x << dom.cell_bits, base.y << dom.cell_bits);
    // The group's bounding box, in lattice units from the base cell's corner: [lo, hi].
    uvec2 lo = uvec2(uint(side), uint(side));
    uvec2 hi = uvec2(0u, 0u);
    for (uint i = e; i < end_cell; i++) {
        uvec2 c = cells.cell[i] - origin;
        lo = min(lo, c);
        hi = max(hi, c + uvec2(a.side, a.side));  // the closed square: surviving_children's cells
    }
    int reach = cover_reach(dom);
    bool inner = inner_cell(dom, base);
    for (int dy = -reach; dy <= reach; dy++) {
        int row = row_reach(dom, dy, reach, dom.cover2 + uint64_t(1));
        for (int dx = -row; dx <= row; dx++) {
            uint nb = neighbour_index(dom, base, inner, dx, dy);
            if (nb == GRID_EMPTY) continue;
            int64_t gx = dx > 0 ? int64_t(dx * side - int(hi.x)) : (dx < 0 ? int64_t(int(lo.x) - (dx + 1) * side + 1) : int64_t(0));
            int64_t gy = dy > 0 ? int64_t(dy * side - int(hi.y)) : (dy < 0 ? int64_t(int(lo.y) - (dy + 1) * side + 1) : int64_t(0));
            if (uint64_t(gx * gx + gy * gy) <= dom.cover2 && !grid_is_sample(grid.word[nb])) set_flag(flags, nb);
        }
    }
}

// Two radii, while U is still nearly everywhere: every base cell without a sample gets darts (a
// superset of the flagged cells, so still a superset of T, and cheaper to find).
VRPD_FN void flag_free_cell(Grid grid, Uints flags, uint b) { flags.value[b] = grid_is_sample(grid.word[b]) ? 0u : 1u; }

// Two radii, for base cell b: after the flags' exclusive scan, a flagged cell joins the list of
// cells that get darts (in base cell order, as the kernels from count_darts on require).
VRPD_FN void list_dart_cell(Domain dom, Uints ranks, Cells cells_out, uint b) {
    uint rank = ranks.value[b];
    if (ranks.value[b + 1u] != rank)
        cells_out.cell[rank] = uvec2((b % dom.cells_x) << dom.cell_bits, (b / dom.cells_x) << dom.cell_bits);
}

// Child c (0..3, or 0 for a cell kept whole) of an active cell; side is the child's side.
VRPD_FN uvec2 child_corner(uvec2 corner, uint side, uint c) {
    return uvec2(corner.x + (c & 1u) * side, corner.y + (c >> 1u) * side);
}


// Clamps the last lattice coordinate of an interval to a free boundary's last lattice point.
VRPD_FN uint clip_hi(uint hi, uint extent, uint periodic) { return periodic != 0u || hi < extent ? hi : extent - 1u; }

// The samples of earlier rounds in the cover neighbourhood of a base cell, gathered once for all
// of its active cells, as offsets from the base cell's corner: each cell's cover test then reads
// this short list, not the grid, and needs no torus arithmetic. The offset of a sample is taken
// through the neighbour cell it was found in. On a torus at least 2 reach + 1 cells wide, a
// sample whose offset is not the shortest one lies at least reach * side + 1 >= Rc from every
// point of the base cell along that axis, so it covers none of them either way: the tests below
// are exact. MAX_CELL_SAMPLES holds any one-radius neighbourhood (a base cell holds at most one
// sample and cover_reach <= MAX_REACH); a two-radii one that does not fit is scanned per cell.
const uint MAX_CELL_SAMPLES = (2u * MAX_REACH + 1u) * (2u * MAX_REACH + 1u);
VRPD_PRIVATE ivec2 cell_sample_at[MAX_CELL_SAMPLES];

// The offset from the corner of base cell `base` to sample p, found in the cell (dx, dy) from it.
VRPD_FN ivec2 sample_offset(Domain dom, int dx, int dy, uvec2 p) {
    int side = 1 << dom.cell_bits;
    uint low = uint(side) - 1u;
    return ivec2(dx * side + int(p.x & low), dy * side + int(p.y & low));
}

// |a - b| for offsets of points of the domain: less than 2^31 apart, so the magnitude fits 32
// bits and two squares sum below 2^63.
VRPD_FN uint gap(int a, int b) { return a > b ? uint(a) - uint(b) : uint(b) - uint(a); }

VRPD_FN uint64_t square_gap(int a, int b) {
    uint d = gap(a, b);
    return uint64_t(d) * uint64_t(d);
}

// The larger squared distance from coordinate c to the ends of [lo, hi]: the cell is convex, so
// its farthest corner pairs the farthest x with the farthest y.
VRPD_FN uint64_t far2(int c, int lo, int hi) {
    uint m = max(gap(c, lo), gap(c, hi));
    return uint64_t(m) * uint64_t(m);
}

// Fills cell_sample_at with the samples near base cell `base`, those of the 8 adjacent cells
// first (the likeliest to cover a cell wholly, so that cover tests stop early); returns their
// count, or MAX_CELL_SAMPLES + 1 if they do not fit.
VRPD_FN uint gather_cell_samples(Domain dom, Grid grid, uvec2 base) {
    uint near = 0u;
    uint far = 0u;  // stored from the end of the array down
    int side = 1 << dom.cell_bits;  // the base cell, closed: [0, side]^2 from its corner
    int reach = cover_reach(dom);
    bool inner = inner_cell(dom, base);
    for (int dy = -reach; dy <= reach; dy++) {
        int row = row_reach(dom, dy, reach, dom.cover2);
        for (int dx = -row; dx <= row; dx++) {
            uint nb = neighbour_index(dom, base, inner, dx, dy);
            if (nb == GRID_EMPTY) continue;
            uvec2 p = grid.word[nb];
            if (!grid_is_sample(p)) continue;
            if (near + far == MAX_CELL_SAMPLES) return MAX_CELL_SAMPLES + 1u;
            ivec2 o = sample_offset(dom, dx, dy, p);
            // A sample no nearer than Rc to every point of the base cell covers none of them.
            uint64_t gx = square_gap(clamp(o.x, 0, side), o.x);
            uint64_t gy = square_gap(clamp(o.y, 0, side), o.y);
            if (gx + gy >= dom.cover2) continue;
            if (dx >= -1 && dx <= 1 && dy >= -1 && dy <= 1) {
                cell_sample_at[near++] = o;
            } else {
                far++;
                cell_sample_at[MAX_CELL_SAMPLES - far] = o;
            }
        }
    }
    for (uint k = 0u; k < far; k++) cell_sample_at[near + k] = cell_sample_at[MAX_CELL_SAMPLES - 1u - k];
    return near + far;
}

// The children of one active cell as closed lattice intervals, as offsets from the base cell's
// corner: x in [lo0.x, hi0.x] or [lo1.x, hi1.x], the same in y. A second child off a free
// boundary (dropped already) repeats the first's intervals.
struct ChildBoxes {
    ivec2 lo0;
    ivec2 hi0;
    ivec2 lo1;
    ivec2 hi1;
};

// Clears from `mask` the children that the disk of the sample at offset o covers wholly (exact
// corner test), and from `open_corners` (two radii) the corners of the children it covers.
VRPD_FN void cover_children(Domain dom, ChildBoxes b, uint fanout, ivec2 o, VRPD_INOUT(uint) mask, VRPD_INOUT(uint) open_corners) {
    uint64_t fx0 = far2(o.x, b.lo0.x, b.hi0.x);
    uint64_t fy0 = far2(o.y, b.lo0.y, b.hi0.y);
    if (fx0 + fy0 < dom.cover2) mask &= ~1u;
    if (fanout == 4u) {
        uint64_t fx1 = far2(o.x, b.lo1.x, b.hi1.x);
        uint64_t fy1 = far2(o.y, b.lo1.y, b.hi1.y);
        if (fx1 + fy0 < dom.cover2) mask &= ~2u;
        if (fx0 + fy1 < dom.cover2) mask &= ~4u;
        if (fx1 + fy1 < dom.cover2) mask &= ~8u;
    }
#ifndef VRPD_ONE_RADIUS
    if (open_corners != 0u && two_radii(dom)) {
        uint64_t gx[3];
        uint64_t gy[3];
        gx[0] = square_gap(o.x, b.lo0.x);
        gx[1] = square_gap(o.x, b.hi0.x);
        gx[2] = square_gap(o.x, b.hi1.x);
        gy[0] = square_gap(o.y, b.lo0.y);
        gy[1] = square_gap(o.y, b.hi0.y);
        gy[2] = square_gap(o.y, b.hi1.y);
        for (uint k = 0u; k < 9u; k++)
            if (gx[k % 3u] + gy[k / 3u] < dom.cover2) open_corners &= ~(1u << k);
    }
#endif
}

// Does refinement into `fanout` children of side `side` test which of them disks cover? When
// cells split (fanout 4), and at the deepest level (side 1), where that test is what ends the
// run. Between the rounds of a coarser level (fanout 1), one radius keeps every cell whose base
// cell holds no sample, covered or not: the next round's darts in a covered cell are rejected at
// throw by the same sample scan that the cover test would have run for every cell, and only the
// darts are random, so the samples are the same. Measured at r = 0.001: level 0's cover test
// between its two rounds took 12 % of the run's time; without it the run throws 3 % more darts,
// each as cheap as a cell's test. Two radii test: their active cells also say which base cells
// get darts, and each T test costs far more than a scan.
VRPD_FN bool cover_tested(Domain dom, uint fanout, uint side) { return fanout == 4u || side == 1u || two_radii(dom); }

// Which of the `fanout` children (4, or 1: the cell itself) of the active cell at `corner` stay
// active, as a bit mask. A child is dropped if it lies off the domain or (cover_tested) one
// sample's disk covers it wholly (exact corner test, see far2). Children covered only by a union
// of disks stay, and are split until they are single lattice points, where the test is exact.
// A child's x and y intervals are shared in pairs: 2 + 2 far offsets per sample rather than 4
// corner tests.
// `samples` is gather_cell_samples's count for the base cell (past MAX_CELL_SAMPLES: scan the grid).
//
// Two radii: a cell is the closed square [corner, corner + side]^2 (continuous: T's test is), and
// a child that no single disk covers is tested exactly (coverage.h): it stays iff it still holds
// a point of U. So the cells track U exactly, and vanish as soon as U does. Should that test run
// past its bounds, the child stays; at the deepest level it then falls back to its lattice point.
VRPD_FN uint surviving_children(Domain dom, Grid grid, uvec2 base, uvec2 corner, uint side, uint fanout, uint samples) {
    uint mask = 0u;
    for (uint c = 0u; c < fanout; c++)
        if (in_domain(dom, child_corner(corner, side, c))) mask |= 1u << c;
    if (!cover_tested(dom, fanout, side)) return mask;
    uint pad = two_radii(dom) ? 0u : 1u;  // one radius: the cell's lattice points
    // The children's intervals, as offsets from the base cell's corner (clipped to a free boundary).
    uvec2 origin = uvec2(base.x << dom.cell_bits, base.y << dom.cell_bits);
    uint x1 = corner.x + side;
    uint y1 = corner.y + side;
    ChildBoxes b;
    b.lo0 = ivec2(corner - origin);
    b.hi0 = ivec2(uvec2(clip_hi(x1 - pad, dom.lattice_x, dom.periodic), clip_hi(y1 - pad, dom.lattice_y, dom.periodic)) - origin);
    bool x1_in = fanout == 4u && (dom.periodic != 0u || x1 < dom.lattice_x);
    bool y1_in = fanout == 4u && (dom.periodic != 0u || y1 < dom.lattice_y);
    b.lo1 = ivec2(x1_in ? int(x1 - origin.x) : b.lo0.x, y1_in ? int(y1 - origin.y) : b.lo0.y);
    b.hi1 = ivec2(x1_in ? int(clip_hi(x1 + side - pad, dom.lattice_x, dom.periodic) - origin.x) : b.hi0.x,
                  y1_in ? int(clip_hi(y1 + side - pad, dom.lattice_y, dom.periodic) - origin.y) : b.hi0.y);
    // Two radii: bit 3 j + i stays set while no sample covers the lattice point (x_i, y_j) of the
    // 3 x 3 corners of the children (x_0 = lo0.x, x_1 = hi0.x, x_2 = hi1.x): a child with an
    // uncovered corner holds a point of U and stays without the exact test.
    uint open_corners = 0x1FFu;
    if (samples <= MAX_CELL_SAMPLES) {
        for (uint k = 0u; k < samples && mask != 0u; k++) cover_children(dom, b, fanout, cell_sample_at[k], mask, open_corners);
    }
#ifndef VRPD_ONE_RADIUS  // one radius: MAX_CELL_SAMPLES holds any neighbourhood (gather_cell_samples)
    else {
        int reach = cover_reach(dom);
        bool inner = inner_cell(dom, base);
        for (int dy = -reach; dy <= reach && mask != 0u; dy++) {
            int row = row_reach(dom, dy, reach, dom.cover2);
            for (int dx = -row; dx <= row && mask != 0u; dx++) {
                uint nb = neighbour_index(dom, base, inner, dx, dy);
                if (nb == GRID_EMPTY) continue;
                uvec2 p = grid.word[nb];
                if (grid_is_sample(p)) cover_children(dom, b, fanout, sample_offset(dom, dx, dy, p), mask, open_corners);
            }
        }
    }
    for (uint c = 0u; c < fanout && two_radii(dom); c++) {
        if ((mask & (1u << c)) == 0u) continue;
        uint k = 3u * (c >> 1u) + (c & 1u);
        if ((open_corners & ((3u << k) | (3u << (k + 3u)))) != 0u) continue;
        uvec2 cc = child_corner(corner, side, c);
        ivec2 hi = ivec2(int(side), int(side));
        if (dom.periodic == 0u) hi = min(hi, ivec2(int(dom.lattice_x - 1u - cc.x), int(dom.lattice_y - 1u - cc.y)));
        uint n = gather_near_box(dom, grid, base, cc, hi);
        if (n > MAX_DISKS) continue;
        uint t = reaches_uncovered(n, dom.cover2, ivec2(0, 0), hi, false);
        if (t == T_UNKNOWN && side == 1u) t = near_sample(dom, grid, base, cc, dom.cover2, cover_reach(dom)) ? T_OUTSIDE : T_INSIDE;
        if (t == T_OUTSIDE) mask &= ~(1u << c);
    }
#endif
    return mask;
}

// For the active cells [first, end) of one base cell: masks[i] has bit c set for the children c
// of cell i that stay active (none if the base cell holds a sample), and counts[i] their number,
// for the scan that places them in the next active list. The samples near the base cell are
// gathered once for the range. The host passes each base cell's whole group (group_end), the
// Vulkan kernel one cell per invocation: with two radii a base cell may hold hundreds of active
// cells (driver.cpp, kCrowded), and llvmpipe ends a loop once 65 535 iterations have run in one
// SIMD batch, which a group's T tests in one invocation passed, leaving cells unrefined.
VRPD_FN void refine_cells_of_base(CellArgs a, Cells cells, Uints counts, Uints masks, Grid grid, uint first, uint end) {
    uvec2 base = base_cell_of(a.domain, cells.cell[first]);
    Domain dom = local_domain(a.domain, base);
    bool occupied = grid_is_sample(grid.word[base_index(dom, base)]);
    uint samples = occupied || !cover_tested(dom, a.param, a.side) ? 0u : gather_cell_samples(dom, grid, base);
    for (uint i = first; i < end; i++) {
        uint mask = occupied ? 0u : surviving_children(dom, grid, base, cells.cell[i], a.side, a.param, samples);
        masks.value[i] = mask;
        counts.value[i] = uint(bitCount(mask));
    }
}

// Writes the surviving children of active cell i to the next active list, from its rank on.
VRPD_FN void scatter_children(CellArgs a, Cells cells, Uints ranks, Uints masks, Cells cells_out, uint i) {
    uint mask = masks.value[i];
    uint rank = ranks.value[i];
    for (uint c = 0u; c < a.param; c++)
        if ((mask & (1u << c)) != 0u) cells_out.cell[rank++] = child_corner(cells.cell[i], a.side, c);
}

// Mask mode (one radius, levels 0 to MASK_LEVELS - 1): there is no list of active cells. The grid
// word of a base cell without a sample holds the mask of its active sub-cells at the current
// level (GRID_MASK_BITS: at most 16 sub-cells, level 2), and the kernels run over base cells.
// Bit k is the sub-cell the explicit list would hold at that place: k's base-4 digits, most
// significant first, are the child indices (child_corner) taken at each level, so the darts,
// their indices and the samples are the explicit mode's, bit for bit. (MASK_LEVELS: kernels.h.)

// Corner of sub-cell k of side `side` of the base cell at `corner` (of side base_side).
VRPD_FN uvec2 subcell_corner(uvec2 corner, uint k, uint side, uint base_side) {
    for (uint s = side; s < base_side; s *= 2u) {
        corner = child_corner(corner, s, k & 3u);
        k >>= 2u;
    }
    return corner;
}

VRPD_FN uvec2 base_corner(Domain dom, uint b) {
    return uvec2((b % dom.cells_x) << dom.cell_bits, (b / dom.cells_x) << dom.cell_bits);
}

VRPD_FN bool masked_active(uvec2 w) { return !grid_is_sample(w) && (w.y & GRID_MASK_BITS) != 0u; }

// The loops over a mask's set bits visit them in ascending order (findLSB, then clear the bit),
// each bit once: a loop over every bit position ran each SIMD batch of llvmpipe up to the
// highest bit of any of its lanes.

// Mask mode: the darts of base cell b (word w, active) this round (a.side: the sub-cells' side;
// a.param: exp(-lambda) as in count_darts).
VRPD_FN uint masked_dart_count(CellArgs a, uvec2 w, uint b) {
    uvec2 corner = base_corner(a.domain, b);
    uint base_side = 1u << a.domain.cell_bits;
    uint count = 0u;
    for (uint mask = w.y & GRID_MASK_BITS; mask != 0u; mask &= mask - 1u) {
        uvec2 cc = subcell_corner(corner, uint(findLSB(mask)), a.side, base_side);
        count += dart_count(cell_stream(a.domain.seed, a.round, cc), a.param);
    }
    return count;
}

// Mask mode: an active word with its round's dart count (< 2^16; the engines check), then with
// the index of its first dart: a packed darts word (domain.h).
VRPD_FN uvec2 counted_word(uvec2 w, uint count) { return uvec2(w.x, (count << 16u) | (w.y & GRID_MASK_BITS)); }
VRPD_FN uvec2 numbered_word(uvec2 w, uint first) { return uvec2(GRID_TAG | GRID_PACKED | first, w.y); }

// Mask mode: writes the darts of base cell b, from `first` on, in the order of its sub-cells, each
// rejected if it lies in the disk of a sample of an earlier round (as throw_base_cell; no_samples
// as throw_cell's). Returns how many are still undecided.
VRPD_FN uint throw_masked_base(CellArgs a, Darts darts, Grid grid, uint b, uint first, bool no_samples) {
    uvec2 w = grid.word[b];
    uvec2 base = uvec2(b % a.domain.cells_x, b / a.domain.cells_x);
    Domain dom = local_domain(a.domain, base);
    uvec2 corner = base_corner(a.domain, b);
    uint base_side = 1u << a.domain.cell_bits;
    uint j = first;
    uint end = grid_darts(w).y;
    uint undecided = 0u;
    StateBits states = no_state_bits(first);
    // The sub-cells' counts sum to the word's (masked_dart_count): the last sub-cell with darts
    // takes what is left, uncounted, and once none is left the rest have none. At level 0, where
    // a base cell is one sub-cell, no count is drawn twice.
    for (uint mask = w.y & GRID_MASK_BITS; mask != 0u && j < end; mask &= mask - 1u) {
        uvec2 cc = subcell_corner(corner, uint(findLSB(mask)), a.side, base_side);
        uint stream = cell_stream(a.domain.seed, a.round, cc);
        uint count = (mask & (mask - 1u)) == 0u ? end - j : dart_count(stream, a.param);
        throw_cell(dom, grid, base, darts, stream, cc, a.side, j, count, states, undecided, no_samples);
        j += count;
    }
    or_dart_states(darts, states.word, states.bits);
    return undecided;
}

// Mask mode: the surviving children of base cell b's active sub-cells (a.side: the children's
// side; a.param: 4 children, or 1: the cell itself), sub-cell k's as bits a.param * k + c, up to
// 16 sub-cells: bits 0-31 in .x and 32-63 in .y, so that level 2's sub-cells may split too.
VRPD_FN uvec2 refine_masked_base(CellArgs a, Grid grid, uint b) {
    uvec2 w = grid.word[b];
    uvec2 kept = uvec2(0u, 0u);
    if (grid_is_sample(w) || (w.y & GRID_MASK_BITS) == 0u) return kept;
    uvec2 base = uvec2(b % a.domain.cells_x, b / a.domain.cells_x);
    Domain dom = local_domain(a.domain, base);
    uint samples = cover_tested(dom, a.param, a.side) ? gather_cell_samples(dom, grid, base) : 0u;
    uvec2 corner = base_corner(a.domain, b);
    uint base_side = 1u << a.domain.cell_bits;
    uint parent_side = a.param == 4u ? 2u * a.side : a.side;
    for (uint mask = w.y & GRID_MASK_BITS; mask != 0u; mask &= mask - 1u) {
        uint k = uint(findLSB(mask));
        uvec2 cc = subcell_corner(corner, k, parent_side, base_side);
        uint children = surviving_children(dom, grid, base, cc, a.side, a.param, samples);
        uint bit = a.param * k;
        if (bit < 32u) kept.x |= children << bit;
        else kept.y |= children << (bit - 32u);
    }
    return kept;
}

// The number of sub-cells in a mask of refine_masked_base.
VRPD_FN uint subcell_count(uvec2 kept) { return uint(bitCount(kept.x) + bitCount(kept.y)); }

// A base cell's word with its new mask of active sub-cells (a sample's word stays).
VRPD_FN uvec2 masked_word(uvec2 w, uint mask) { return grid_is_sample(w) ? w : uvec2(GRID_EMPTY, mask); }

// Writes the children in `kept` (refine_masked_base, children of side `side`) of base cell b to
// an explicit active list, from `rank` on, in the explicit list's order.
VRPD_FN void scatter_subcells(Domain dom, Cells cells_out, uint rank, uvec2 kept, uint b, uint side) {
    uvec2 corner = base_corner(dom, b);
    for (uint bits = kept.x; bits != 0u; bits &= bits - 1u)
        cells_out.cell[rank++] = subcell_corner(corner, uint(findLSB(bits)), side, 1u << dom.cell_bits);
    for (uint bits = kept.y; bits != 0u; bits &= bits - 1u)
        cells_out.cell[rank++] = subcell_corner(corner, uint(findLSB(bits)) + 32u, side, 1u << dom.cell_bits);
}

VRPD_END
#endif
