// Dart throwing (paper Eq. 4): each active cell's darts of a round, made from the counter-based
// RNG (darts.h), written in index order, each rejected at once if it lies off the domain or in
// the disk of a sample of an earlier round.
#ifndef VRPD_THROW_H
#define VRPD_THROW_H
#include "bridge.h"
#include "active_cells.h"
#include "cover.h"
#include "darts.h"
#include "kernels.h"

VRPD_BEGIN

// For the active cells [e, end_cell) of one base cell (group_end): the grid word of the base cell
// becomes the range of this round's darts in it (the exclusive prefix sums of the counts). A pass
// of its own, so that throwing, which reads the neighbours' words, never races with this write.
VRPD_FN void mark_dart_range(CellArgs a, Cells cells, Uints scan, Grid grid, uint e, uint end_cell) {
    grid.word[base_of_point(a.domain, cells.cell[e])] = uvec2(GRID_TAG | scan.value[e], scan.value[end_cell]);
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
// the grid holds no sample yet (a run's first round), so only the domain is tested, not an empty
// grid (docs/performance.md).
VRPD_FN void throw_cell(Domain dom, Grid grid, uvec2 base, Darts darts, uint stream, uvec2 corner, uint side,
                        uint first, uint count, VRPD_INOUT(StateBits) states, VRPD_INOUT(uint) undecided,
                        bool no_samples) {
    for (uint i = 0u; i < count; i++) {
        uvec4 dart = make_dart(stream, i, corner, side);
        uvec2 p = uvec2(dart.x, dart.y);
        bool rejected = no_samples ? !in_lattice(dom.lattice, p) : inhibited(dom, grid, base, p);
        undecided += rejected ? 0u : 1u;
        store_dart_record(darts, first + i, dart);
        states = add_state(darts, states, first + i, rejected ? DART_REJECTED : DART_UNDECIDED);
    }
}

// The device's throw takes two steps, so that each lane throws one dart: most cells get no dart
// or one, and with a lane per cell (or base cell) a SIMD batch would run the conflict scan as
// many times as its lane with the most darts. First each dart's record gets its site, its cell's
// corner and its index in the cell (with the marking of the darts' ranges: site_cell_darts,
// mask_mode.h's site_masked_darts); then a lane per dart makes it there (throw_sited). The host
// throws a base cell's darts in one loop (throw_base_cell, throw_masked_base), the same darts.
VRPD_FN void write_site(Darts darts, uint j, uvec2 corner, uint i) {
    store_dart_record(darts, j, uvec4(corner, i, 0u));
}

// The sites of active cell e's darts.
VRPD_FN void site_cell_darts(Cells cells, Uints scan, Darts darts, uint e) {
    uint first = scan.value[e];
    uint end = scan.value[e + 1u];
    for (uint j = first; j < end; j++) write_site(darts, j, cells.cell[e], j - first);
}

// Makes dart j at the site its record holds (cells of side a.side) and writes it; returns its
// state, rejected if it lies off the domain or in the disk of a sample of an earlier round, or
// with `no_samples` (a grid that holds none yet) off the domain alone (throw_cell's test).
VRPD_FN uint throw_sited(CellArgs a, Darts darts, Grid grid, uint j, bool no_samples) {
    uint r = dart_record(j);
    uvec2 corner = uvec2(darts.word[r], darts.word[r + 1u]);
    uvec4 dart = make_dart(cell_stream(a.round_key, corner), darts.word[r + 2u], corner, a.side);
    uvec2 p = uvec2(dart.x, dart.y);
    uvec2 base = base_cell_of(a.domain, corner);
    bool rejected =
        no_samples ? !in_lattice(a.domain.lattice, p) : inhibited(local_domain(a.domain, base), grid, base, p);
    store_dart_record(darts, j, dart);
    return rejected ? DART_REJECTED : DART_UNDECIDED;
}

// For the active cells [e, end_cell) of one base cell (group_end): writes their darts (cell i's at
// scan[i] .. scan[i+1]), each rejected if it lies off the domain or in the disk
// of a sample of an earlier round (with two radii, membership in T is left to the resolution,
// which sees this round's earlier darts as well): the host's throw. Each dart is made, tested and
// written once. Returns how many are still undecided.
VRPD_FN uint throw_base_cell(VRPD_IN(CellArgs) a, Cells cells, Uints scan, Darts darts, Grid grid, uint e,
                             uint end_cell) {
    uvec2 base = base_cell_of(a.domain, cells.cell[e]);
    Domain dom = local_domain(a.domain, base);
    uint undecided = 0u;
    StateBits states = no_state_bits(scan.value[e]);
    for (uint i = e; i < end_cell; i++) {
        uint cell_first = scan.value[i];
        uint cell_end = scan.value[i + 1u];
        if (cell_first == cell_end) continue;
        uvec2 corner = cells.cell[i];
        uint stream = cell_stream(a.round_key, corner);
        throw_cell(dom, grid, base, darts, stream, corner, a.side, cell_first, cell_end - cell_first, states, undecided,
                   false);
    }
    or_dart_states(darts, states.word, states.bits);
    return undecided;
}

VRPD_END
#endif
