// A round decided in arrival order, for the cpu backend on few threads. A base cell's diagonal is
// shorter than Rf, so it holds at most one sample, and once a dart of the round is accepted its
// point can stand in the base cell's word for the rest of the round: a later dart in that base
// cell lies within Rf of it, and one elsewhere meets it in the same scans of nearby samples that
// judge a dart against earlier rounds (two radii: its T test sees it as the textbook's list of
// accepted darts would, in the same place). The parallel resolution instead reads every dart of
// the round near each undecided one (resolve.h). Arrival order is random in space, so the loop
// fetches the record of the dart 16 ahead and the grid rows around the dart 8 ahead.
#include "arrival_order.h"

#include <algorithm>

#include "../engine.h"
#include "shared/cover.h"
#include "shared/resolve_two_radii.h"

namespace vrpd::detail {

using namespace shared;

void sort_by_key(std::vector<std::uint64_t>& values) {
    constexpr int kBits = 11;
    constexpr std::size_t kBuckets = std::size_t(1) << kBits;
    std::vector<std::uint64_t> other(values.size());
    for (int shift = 32; shift < 64; shift += kBits) {
        std::vector<std::size_t> start(kBuckets + 1, 0);
        for (std::uint64_t v : values) ++start[((v >> shift) & (kBuckets - 1)) + 1];
        for (std::size_t b = 1; b <= kBuckets; ++b) start[b] += start[b - 1];
        for (std::uint64_t v : values) other[start[(v >> shift) & (kBuckets - 1)]++] = v;
        values.swap(other);
    }
}

namespace {

// Two radii: the state of a dart at p (base cell `cell`, dom its local domain) given the samples,
// the round's accepted darts among them (state_given_accepted's answer, whose disks it lists in
// the same order): rejected if one is closer than Rf; accepted if none is closer than Rc (the
// dart is in U, so in T); else by the dart's T test over the samples within 2 Rc.
uint state_given_samples(const Domain& dom, Grid grid, uvec2 p, uvec2 cell) {
    if (near_sample(dom, grid, cell, p, INHIBITION)) return DART_REJECTED;
    if (!near_sample(dom, grid, cell, p, COVERAGE)) return DART_ACCEPTED;
    uint n = 0u;
    const uint64_t limit2 = influence2(dom.radii);
    VRPD_FOR_EACH_NEIGHBOUR(dom, cell, int(influence_reach(dom.radii)), limit2, dx, dy, nb) {
        const uvec2 w = grid.word[nb];
        if (!grid_is_sample(w) || distance2(dom.lattice, p, w) >= limit2) continue;
        if (n == MAX_DISKS) return DART_TOO_COMPLEX;
        disk_at[n++] = offset_to(dom.lattice, p, w);
    }
    return state_of_t(reaches_uncovered_at(dom, p, n));
}

}  // namespace

std::uint64_t decide_in_arrival_order(const Domain& dom, Grid grid, Darts darts, uint count, std::vector<uvec2>& out) {
    const int reach = conflict_reach(dom.radii);
    auto fetch_rows = [&](uint j) {
        const uint r = dart_record(j);
        const uvec2 c = base_cell_of(dom, uvec2(darts.word[r], darts.word[r + 1u]));
        const int last_x = int(dom.cells_x) - 1;
        for (int y = std::max(int(c.y) - reach, 0); y <= std::min(int(c.y) + reach, int(dom.cells_y) - 1); ++y) {
            const std::size_t row = std::size_t(y) * dom.cells_x;
            __builtin_prefetch(&grid.word[row + std::size_t(std::max(int(c.x) - reach, 0))]);
            __builtin_prefetch(&grid.word[row + std::size_t(std::min(int(c.x) + reach, last_x))]);
        }
    };
    // The keys' quarters one after another: the sort's two lists then hold a quarter of the
    // undecided darts, 4 bytes a dart, where the parallel resolution's emission holds 8 bytes an
    // accepted dart; each quarter costs a pass over the darts' keys and states.
    std::vector<std::uint64_t> order;
    std::uint64_t held = 0;
    for (uint quarter = 0; quarter < 4u; ++quarter) {
        order.clear();
        for (uint block = 0; block < count; block += 16u) {  // darts.h: 16 records, then their states
            const uint states = load_state_word(darts, dart_state_word(block));
            const uint* key = &darts.word[dart_record(block) + 2u];
            for (uint j = block; j < std::min(block + 16u, count); ++j, key += 3)
                if ((states >> dart_state_shift(j) & 3u) == DART_UNDECIDED && *key >> 30 == quarter)
                    order.push_back(std::uint64_t(*key) << 32 | j);
        }
        sort_by_key(order);
        held = std::max<std::uint64_t>(held, 2 * order.capacity() * sizeof(std::uint64_t));
        const std::size_t n = order.size();
        for (std::size_t k = 0; k < n; ++k) {
            if (k + 16 < n) __builtin_prefetch(&darts.word[dart_record(uint(order[k + 16]))]);
            if (k + 8 < n) fetch_rows(uint(order[k + 8]));
            const uint d = uint(order[k]);
            const uint r = dart_record(d);
            const uvec2 p(darts.word[r], darts.word[r + 1u]);
            const uvec2 cell = base_cell_of(dom, p);
            const Domain local = local_domain(dom, cell);
            const uint state = two_radii(dom.radii) ? state_given_samples(local, grid, p, cell)
                               : near_sample(local, grid, cell, p, INHIBITION) ? DART_REJECTED
                                                                               : DART_ACCEPTED;
            if (state == DART_TOO_COMPLEX) throw Error(kTooComplex);
            set_dart_state(darts, d, state);
            if (state == DART_REJECTED) continue;
            grid.word[base_index(dom, cell)] = p;
            out.push_back(p);
        }
    }
    return held;
}

}  // namespace vrpd::detail
