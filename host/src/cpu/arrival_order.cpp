// A round decided in arrival order, for the cpu backend on few threads. A base cell's diagonal is
// shorter than Rf, so it holds at most one sample, and once a dart of the round is accepted its
// point can stand in the base cell's word for the rest of the round: a later dart in that base
// cell lies within Rf of it, and one elsewhere meets it in the same scans of nearby samples that
// judge a dart against earlier rounds (two radii: its T test sees it as the textbook's list of
// accepted darts would, in the same place). The parallel resolution instead reads every dart of
// the round near each undecided one (resolve.h). The decisions live in the grid words and the
// emission alone: nothing after the round reads the darts' states, so none is written (each
// would be a locked or at a random place, into a word that 15 other darts share). Arrival order
// is random in space, so the loop fetches the record of the dart 16 ahead and the grid rows
// around the dart 8 ahead (with two radii, the rows of its T test's window). On several threads
// each takes a strip of base-cell rows, a dart near a border waiting for the neighbouring strip's
// earlier darts near that border (decide_strip), and the strips' accepted darts are merged by
// arrival.
#include "arrival_order.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <thread>

#include "../engine.h"
#include "shared/cover.h"
#include "shared/resolve_two_radii.h"

namespace vrpd::detail {

using namespace shared;

void sort_by_key(Keys& values) {
    constexpr int kBits = 11;
    constexpr std::size_t kBuckets = std::size_t(1) << kBits;
    Keys other(values.size());
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
    if (vector_window(dom, cell)) {
        n = window_gather_within<false>(grid.word + base_index(dom, cell), int(dom.cells_x),
                                        int(influence_reach(dom.radii)), p, limit2, disk_at, MAX_DISKS);
        return n > MAX_DISKS ? DART_TOO_COMPLEX : state_of_t(reaches_uncovered_at(dom, p, n));
    }
    VRPD_FOR_EACH_NEIGHBOUR(dom, cell, int(influence_reach(dom.radii)), limit2, dx, dy, nb) {
        const uvec2 w = grid.word[nb];
        if (!grid_is_sample(w) || distance2(dom.lattice, p, w) >= limit2) continue;
        if (n == MAX_DISKS) return DART_TOO_COMPLEX;
        disk_at[n++] = offset_to(dom.lattice, p, w);
    }
    return state_of_t(reaches_uncovered_at(dom, p, n));
}

// The strips of base-cell rows the threads take, and how far a dart's judgement reads. A strip's
// bottom zone is its rows within reach of the strip below (none at a free box's edge), its top
// zone those within reach of the strip above; a dart's scans read another strip's rows only from
// a zone, and then only the neighbour's facing zone.
struct Strips {
    uint parts = 1;  // strip w holds rows [rows * w / parts, rows * (w + 1) / parts)
    uint rows = 0;
    int reach = 0;  // rows a dart's scans read either side of its own
    bool periodic = false;
    uint first_row(uint w) const { return uint(std::uint64_t(rows) * w / parts); }
    uint below(uint w) const { return w > 0u ? w - 1u : periodic ? parts - 1u : parts; }  // parts: none
    uint above(uint w) const { return w + 1u < parts ? w + 1u : periodic ? 0u : parts; }
    // Each row's strip (the low bits) and zones (kBottom, kTop).
    static constexpr uint kBottom = 1u << 30, kTop = 1u << 31;
    std::vector<uint> row_strip;
    void place_rows() {
        row_strip.resize(rows);
        for (uint w = 0; w < parts; ++w) {
            const uint lo = first_row(w), hi = first_row(w + 1u);
            for (uint y = lo; y < hi; ++y)
                row_strip[y] = w | (below(w) < parts && int(y) < int(lo) + reach ? kBottom : 0u) |
                               (above(w) < parts && int(y) + reach >= int(hi) ? kTop : 0u);
        }
    }
};

// Progress of one strip's thread through one zone's darts of a quarter of the round: below it,
// every dart of the zone is decided. Apart so the threads' stores do not share a cache line.
struct alignas(64) Progress {
    std::atomic<std::uint64_t> next{0};
};

constexpr std::uint64_t kQuarterDone = UINT64_MAX;

// One step of a short busy wait: the processor's hint where it has one.
inline void spin_pause() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

}  // namespace

std::uint64_t decide_in_arrival_order(const Domain& dom, Grid grid, Darts darts, uint count, std::vector<uvec2>& out,
                                      ThreadPool& pool, uint strip_darts) {
    const int conflict = conflict_reach(dom.radii);
#ifdef VRPD_HOST_AVX2
    // One radius: a dart in an inner base cell is judged by near_sample's vector body directly,
    // without the local domain and the choice of body for each dart, where inner cells' local
    // domains are straight (vector_window's condition).
    const bool vector_darts =
        !two_radii(dom.radii) && conflict <= int(MAX_REACH) && host_has_avx2() && straight_inner_cells(dom);
#endif
    Strips strips;
    strips.rows = dom.cells_y;
    strips.periodic = dom.lattice.periodic != 0u;
    strips.reach =
        two_radii(dom.radii) ? std::max({conflict, cover_reach(dom.radii), int(influence_reach(dom.radii))}) : conflict;
    // A strip at least 2 reach + 1 rows high: a dart reads at most one neighbouring strip on each
    // side, and of it only rows within reach of their border; and strip_darts darts a thread.
    const uint tall = uint(2 * strips.reach + 1);
    strips.parts = std::max(1u, std::min({pool.size(), dom.cells_y / tall, strip_darts ? count / strip_darts : count}));
    if (strips.parts > 1u) strips.place_rows();
    // The window a dart's judgement reads: Rf's with one radius; with two radii the 2 Rc window
    // that the T test gathers, which about half the darts past the Rf and Rc scans take.
    const int fetched = two_radii(dom.radii) ? int(influence_reach(dom.radii)) : conflict;
    const bool wide = 2 * fetched > int(64 / sizeof(uvec2));  // a row's window may span three lines
    // Inlined by force: GCC counts a prefetch as no effect, and deletes the calls of a function
    // that only prefetches (its interprocedural analysis finds it pure before inlining).
    auto fetch_rows = [&](uint j) __attribute__((always_inline)) {
        constexpr int kLineWords = 64 / sizeof(uvec2);
        const uint r = dart_record(j);
        const int cx = int(darts.word[r] >> dom.cell_bits), cy = int(darts.word[r + 1u] >> dom.cell_bits);
        const int first_x = std::max(cx - fetched, 0), last_x = std::min(cx + fetched, int(dom.cells_x) - 1);
        const int first_y = std::max(cy - fetched, 0), last_y = std::min(cy + fetched, int(dom.cells_y) - 1);
        const uvec2* row = &grid.word[std::size_t(first_y) * dom.cells_x];
        for (int y = first_y; y <= last_y; ++y, row += dom.cells_x) {
            __builtin_prefetch(row + first_x);
            if (wide)
                for (int x = first_x + kLineWords; x < last_x; x += kLineWords) __builtin_prefetch(row + x);
            __builtin_prefetch(row + last_x);
        }
    };
    // A dart accepted in a strip, by (key, index), for the merge of the strips' emissions.
    struct Accepted {
        std::uint64_t order;
        uvec2 p;
    };
    const uint parts = strips.parts;
    const bool whole = parts == 1u;
    // progress[2 w]: strip w's bottom zone; progress[2 w + 1]: its top zone.
    std::vector<Progress> progress(2 * parts);
    // listed[v][w]: the quarter's undecided darts of strip w among chunk v of the dart indices;
    // zoned[v][2 w + z]: those of them in the strip's bottom (z = 0) or top (z = 1) zone.
    std::vector<std::vector<Keys>> listed(parts, std::vector<Keys>(parts));
    std::vector<std::vector<Keys>> zoned(parts, std::vector<Keys>(2 * parts));
    std::vector<std::vector<Accepted, Uninitialised<Accepted, true>>> accepted(parts);
    std::vector<std::uint64_t> held(parts, 0);
    std::atomic<bool> failed = false;
    auto list_quarter = [&](uint v, uint quarter) {
        const uint begin = uint(std::uint64_t(count) * v / parts) & ~15u,
                   end = v + 1u == parts ? count : uint(std::uint64_t(count) * (v + 1u) / parts) & ~15u;
        std::vector<Keys>& lists = listed[v];
        std::vector<Keys>& zones = zoned[v];
        for (uint block = begin; block < end; block += 16u) {  // darts.h: 16 records, then their states
            // Bit 2 i: dart block + i is undecided (state 0); the block's records past `end` are not.
            const uint states = load_state_word(darts, dart_state_word(block));
            uint open = ~(states | states >> 1u) & 0x55555555u;
            if (end - block < 16u) open &= (1u << (2u * (end - block))) - 1u;
            const uint* record = &darts.word[dart_record(block)];
            for (; open != 0u; open &= open - 1u) {
                const uint i = uint(std::countr_zero(open)) / 2u;
                const uint* word = record + 3u * i;
                if (word[2] >> 30 != quarter) continue;
                const std::uint64_t entry = std::uint64_t(word[2]) << 32 | (block + i);
                if (whole) {
                    lists[0].push_back(entry);
                    continue;
                }
                const uint row = strips.row_strip[word[1] >> dom.cell_bits],
                           w = row & ~(Strips::kBottom | Strips::kTop);
                lists[w].push_back(entry);
                if (row & Strips::kBottom) zones[2u * w].push_back(entry);
                if (row & Strips::kTop) zones[2u * w + 1u].push_back(entry);
            }
        }
    };
    // The chunks' lists in slot `slot` of `lists` (listed or zoned) joined and sorted into
    // arrival order, each freed once copied; `held` gains the capacity they held beside the join.
    auto join_sorted = [&](std::vector<std::vector<Keys>>& lists, uint slot, std::size_t& held) {
        Keys order;
        std::size_t n = 0;
        for (uint v = 0; v < parts; ++v) n += lists[v][slot].size(), held += lists[v][slot].capacity();
        order.reserve(n);
        for (uint v = 0; v < parts; ++v) {  // chunks in index order, as the sort needs
            order.insert(order.end(), lists[v][slot].begin(), lists[v][slot].end());
            Keys().swap(lists[v][slot]);
        }
        sort_by_key(order);
        return order;
    };
    // Strip w's darts of the quarter, in arrival order. A dart in a zone first waits until the
    // neighbouring strip's thread has decided every earlier dart of its facing zone, the only
    // darts of that strip the dart's scans can meet; that thread's later darts there wait in
    // turn for this one. So a dart's scans see the earlier darts accepted near it and no later
    // one, as on one thread: the same states. A zone's progress is the arrival key of its next
    // undecided dart, which never arrived before its thread's current dart: so a dart waits only
    // on a thread whose current dart arrived earlier, the thread whose current dart arrived first
    // never waits, and the waits end.
    auto decide_strip = [&](uint w) {
        Keys order;
        std::size_t lists = 0;  // the chunks' lists' capacity, held beside the joined lists while copied
        if (whole) {
            order.swap(listed[0][0]);
            sort_by_key(order);
        } else {
            order = join_sorted(listed, w, lists);
        }
        const std::size_t n = order.size();
        Keys zone[2];
        std::size_t next_in_zone[2] = {0, 0};
        if (!whole)
            for (uint z = 0; z < 2u; ++z) {
                zone[z] = join_sorted(zoned, 2u * w + z, lists);
                progress[2u * w + z].next.store(zone[z].empty() ? kQuarterDone : zone[z][0], std::memory_order_release);
            }
        // After a dart of zone z: the zone's progress moves to its next dart.
        auto passed = [&](uint z) {
            const std::size_t i = ++next_in_zone[z];
            progress[2u * w + z].next.store(i < zone[z].size() ? zone[z][i] : kQuarterDone, std::memory_order_release);
        };
        const uint below = strips.below(w), above = strips.above(w);
        auto wait_for = [&](uint u, std::uint64_t o) {
            for (uint spins = 0; progress[u].next.load(std::memory_order_acquire) <= o;) {
                if (failed.load(std::memory_order_relaxed)) return false;
                if (++spins < 256u)
                    spin_pause();
                else
                    std::this_thread::yield();
            }
            return true;
        };
        for (std::size_t k = 0; k < n; ++k) {
            if (k + 16 < n) __builtin_prefetch(&darts.word[dart_record(uint(order[k + 16]))]);
            if (k + 8 < n) fetch_rows(uint(order[k + 8]));
            const uint r = dart_record(uint(order[k]));
            const uvec2 p(darts.word[r], darts.word[r + 1u]);
            const uvec2 cell = base_cell_of(dom, p);
            const uint row = whole ? 0u : strips.row_strip[cell.y];
            if ((row & Strips::kBottom) && !wait_for(2u * below + 1u, order[k])) return;
            if ((row & Strips::kTop) && !wait_for(2u * above, order[k])) return;
            uint state;
#ifdef VRPD_HOST_AVX2
            if (vector_darts && inner_cell(dom, cell))
                state = window_holds_within<false>(grid.word + base_index(dom, cell), int(dom.cells_x), conflict, p,
                                                   dom.radii.inhibition2)
                            ? DART_REJECTED
                            : DART_ACCEPTED;
            else
#endif
            {
                const Domain local = local_domain(dom, cell);
                state = two_radii(dom.radii)                            ? state_given_samples(local, grid, p, cell)
                        : near_sample(local, grid, cell, p, INHIBITION) ? DART_REJECTED
                                                                        : DART_ACCEPTED;
            }
            if (state == DART_TOO_COMPLEX) throw Error(kTooComplex);
            if (state != DART_REJECTED) {
                grid.word[base_index(dom, cell)] = p;
                if (whole)
                    out.push_back(p);
                else
                    accepted[w].push_back({order[k], p});
            }
            if (row & Strips::kBottom) passed(0u);
            if (row & Strips::kTop) passed(1u);
        }
        const std::size_t lists_held =
            std::max(lists + order.capacity(), 2 * order.capacity()) + zone[0].capacity() + zone[1].capacity();
        held[w] = std::max<std::uint64_t>(
            held[w], lists_held * sizeof(std::uint64_t) + accepted[w].capacity() * sizeof(Accepted));
    };
    // Strip w's accepted darts written to their places among all strips' in arrival order.
    auto place_strip = [&](uint w, std::size_t base) {
        std::vector<std::size_t> at(parts, 0);
        const auto& mine = accepted[w];
        for (std::size_t i = 0; i < mine.size(); ++i) {
            std::size_t before = i;
            for (uint u = 0; u < parts; ++u) {
                if (u == w) continue;
                while (at[u] < accepted[u].size() && accepted[u][at[u]].order < mine[i].order) ++at[u];
                before += at[u];
            }
            out[base + before] = mine[i].p;
        }
    };
    // The keys' quarters one after another: the sort's two lists then hold a quarter of the
    // undecided darts, 4 bytes a dart, where the parallel resolution's emission holds 8 bytes an
    // accepted dart; each quarter costs a pass over the darts' keys and states. On several
    // threads each lists a share of the darts, decides its strip's, then places its accepted ones.
    for (uint quarter = 0; quarter < 4u; ++quarter) {
        if (whole) {
            list_quarter(0u, quarter);
            decide_strip(0u);
            continue;
        }
        pool.each_worker([&](uint w) {
            if (w < parts) list_quarter(w, quarter);
        });
        for (Progress& p : progress) p.next.store(0, std::memory_order_relaxed);
        pool.each_worker([&](uint w) {
            if (w >= parts) return;
            try {
                decide_strip(w);
            } catch (...) {
                failed = true;
                throw;
            }
            for (uint z = 0; z < 2u; ++z) progress[2u * w + z].next.store(kQuarterDone, std::memory_order_release);
        });
        const std::size_t base = out.size();
        std::size_t total = 0;
        for (const auto& a : accepted) total += a.size();
        out.resize(base + total);
        pool.each_worker([&](uint w) {
            if (w < parts) place_strip(w, base);
        });
        for (auto& a : accepted) a.clear();
    }
    std::uint64_t total = strips.row_strip.capacity() * sizeof(uint);
    for (std::uint64_t h : held) total += h;
    return total;
}

}  // namespace vrpd::detail
