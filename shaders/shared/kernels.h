// Push-constant blocks of the sampler's kernels, one definition for GLSL and C++. Buffers are
// passed by device address (GL_EXT_buffer_reference); the host static_asserts every offset.
#ifndef VRPD_KERNELS_H
#define VRPD_KERNELS_H
#include "bridge.h"
#include "darts.h"
#include "domain.h"
#include "grid.h"
#include "neighbourhood.h"

#ifndef __cplusplus
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Cells { uvec2 cell[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Grid { uvec2 word[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Darts { uint word[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Uints { uint value[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Points { uvec2 point[]; };
// Sets flag i to 1. Invocations may write it concurrently: an atomic store (relaxed) keeps that
// race-free, as on the host.
void set_flag(Uints flags, uint i) {
    atomicStore(flags.value[i], 1u, VRPD_RELAXED);
}
// A resolution pass sets states while other invocations read them: both are atomic, as on the host.
uint load_state_word(Darts darts, uint w) {
    return atomicLoad(darts.word[w], VRPD_RELAXED);
}
void or_state_word(Darts darts, uint w, uint bits) { atomicOr(darts.word[w], bits); }
// Clears bits of mask i: many invocations may clear bits of one mask at once.
void and_mask(Uints masks, uint i, uint bits) { atomicAnd(masks.value[i], bits); }
#else
#include <atomic>
namespace vrpd::shared {
// Host views of the same buffers, so the kernel bodies compile unchanged in C++.
struct Cells { uvec2* cell; };
struct Grid { uvec2* word; };
struct Darts { uint* word; };
struct Uints { uint* value; };
struct Points { uvec2* point; };
// Host threads may write one flag concurrently (all write 1): an atomic store keeps that defined.
inline void set_flag(Uints flags, uint i) {
    std::atomic_ref<uint>(flags.value[i]).store(1u, std::memory_order_relaxed);
}
// The cpu backend's resolution decides darts while other threads read their states (see
// HostEngine::resolve), and a block's state word is shared by darts that different threads
// write: state words are read and or-ed atomically.
inline uint load_state_word(Darts darts, uint w) {
    return std::atomic_ref<uint>(darts.word[w]).load(std::memory_order_relaxed);
}
inline void or_state_word(Darts darts, uint w, uint bits) {
    std::atomic_ref<uint>(darts.word[w]).fetch_or(bits, std::memory_order_relaxed);
}
// The host's scattered refinement gives each thread bands of rows that no other thread's
// samples reach (cover_scatter.cpp), so a mask has one writer at a time.
inline void and_mask(Uints masks, uint i, uint bits) { masks.value[i] &= bits; }
}  // namespace vrpd::shared
#endif

VRPD_BEGIN

// Dart j (.xy position, .z arrival key, .w state; storage in darts.h). States only change from
// undecided to final, so a reader sees either; position and key do not change in a round.
VRPD_FN uvec4 dart_at(Darts darts, uint j) {
    uint r = dart_record(j);
    uvec4 dart = uvec4(darts.word[r], darts.word[r + 1u], darts.word[r + 2u], 0u);
    dart.w = (load_state_word(darts, dart_state_word(j)) >> dart_state_shift(j)) & 3u;
    return dart;
}
// Ors state bits into state word w (dart_state_word), for the darts whose states they set.
VRPD_FN void or_dart_states(Darts darts, uint w, uint bits) {
    if (bits != 0u) or_state_word(darts, w, bits);
}
VRPD_FN void set_dart_state(Darts darts, uint j, uint state) {
    or_dart_states(darts, dart_state_word(j), state << dart_state_shift(j));
}
// Writes dart j's position and key; its state stays as it is (undecided in a zeroed buffer).
VRPD_FN void store_dart_record(Darts darts, uint j, uvec4 dart) {
    uint r = dart_record(j);
    darts.word[r] = dart.x;
    darts.word[r + 1u] = dart.y;
    darts.word[r + 2u] = dart.z;
}
// Where dart d lies: the dart (dart_at), its lattice point, its base cell, and the domain as seen
// from that cell (local_domain), which every scan around the dart uses.
struct DartSite {
    uvec4 dart;
    uvec2 p;
    uvec2 cell;
    Domain dom;
};
VRPD_FN DartSite dart_site(Domain global, Darts darts, uint d) {
    DartSite s;
    s.dart = dart_at(darts, d);
    s.p = uvec2(s.dart.x, s.dart.y);
    s.cell = base_cell_of(global, s.p);
    s.dom = local_domain(global, s.cell);
    return s;
}

// Writes dart j whole, its state (.w) included.
VRPD_FN void store_dart(Darts darts, uint j, uvec4 dart) {
    store_dart_record(darts, j, dart);
    set_dart_state(darts, j, dart.w);
}

VRPD_END

VRPD_BEGIN

const uint WORKGROUP_SIZE = 64u;  // default of specialization constant 0
const uint SCAN_BLOCK = 512u;     // elements scanned per workgroup (8 per invocation)

// Counters in one small host-visible buffer. Two work lists of undecided darts alternate as
// input and output of the resolution passes; each has an indirect dispatch command and a count.
const uint COUNTER_WORK0 = 0u;     // uvec3 dispatch + count of work list 0
const uint COUNTER_WORK1 = 4u;     // the same for work list 1
const uint COUNTER_DARTS = 8u;     // scan totals: darts thrown this round,
const uint COUNTER_ACCEPTED = 9u;  // darts accepted this round,
const uint COUNTER_ACTIVE = 10u;   // cells active for the next round,
const uint COUNTER_SORT = 11u;     // the sort's histogram
const uint COUNTER_DART_CELLS = 12u;  // two radii: base cells that get darts this round
const uint COUNTER_TOO_COMPLEX = 13u; // two radii: 1 if a dart's T test went past its bounds
const uint COUNTER_CROWDED = 14u;     // mask mode: 1 if a base cell got 2^16 darts or more in a round
const uint COUNTER_LISTED = 15u;      // mask mode: base cells listed for the last mask-mode level
const uint COUNTER_WORDS = 16u;

// Kernels over the active cells: init_cells, count_darts, mark_ranges, commit_cells,
// refine_cells, scatter_cells; with two radii flag_dart_cells and list_dart_cells, which make the
// list of base cells the darts go to (the kernels from count_darts to commit_cells run over it).
// In mask mode (sampler.h) their counterparts run over all base cells: count_masked, mark_masked,
// commit_masked, refine_masked, apply_masks, scatter_masked. throw_sited runs over the darts
// (cell_count: their number).
struct CellArgs {
    Domain domain;
    VRPD_BUFFER(Cells) cells;      // active cells (lattice corners), ordered by base cell; in mask
                                   // mode the list of base cells to run over, or 0 (masked.glsl)
    VRPD_BUFFER(Cells) cells_out;  // the next round's active cells
    VRPD_BUFFER(Darts) darts;
    VRPD_BUFFER(Uints) scan;       // per-cell dart (or surviving child) counts, then their prefix sums
    VRPD_BUFFER(Grid) grid;
    // throw_sited appends the undecided darts to `work` (work list 0); list_masked writes the
    // list of active base cells to it.
    VRPD_BUFFER(Uints) work;
    VRPD_BUFFER(Uints) counters;
    VRPD_BUFFER(Uints) masks;      // refine/scatter: which children of each cell stay active
    uint cell_count;
    uint round_key;                // the round's RNG key (darts.h, round_key)
    uint side;                     // side of the active cells (of the children in refine/scatter)
    uint param;                    // count_darts: exp(-lambda) in 2^-32 units; commit_cells: darts
                                   // thrown; refine/scatter: 1 or 4 children
};
#ifdef __cplusplus
// Push constants: 128 bytes is what every Vulkan device guarantees.
static_assert(sizeof(CellArgs) == 128 && offsetof(CellArgs, cells) == 48 && offsetof(CellArgs, cell_count) == 112);
#endif

// Mask mode (sampler.h) runs levels 0 to MASK_LEVELS - 1 and ends at children of level
// MASK_LEVELS: is the refinement into `fanout` children of side `side` that one?
const uint MASK_LEVELS = 3u;
VRPD_FN bool masked_leaves(Domain dom, uint side, uint fanout) {
    return fanout == 4u && (side << MASK_LEVELS) == (1u << dom.cell_bits);
}

// Kernels over darts: resolve_darts, emit_samples. A round holds < 2^30 darts (darts.h: their
// words' indices stay below 2^32).
const uint MAX_ROUND_DARTS = 0x40000000u;
struct DartArgs {
    Domain domain;
    VRPD_BUFFER(Darts) darts;
    VRPD_BUFFER(Grid) grid;
    VRPD_BUFFER(Uints) work_in;
    VRPD_BUFFER(Uints) work_out;
    VRPD_BUFFER(Uints) counters;
    VRPD_BUFFER(Uints) scan;        // emit_samples: prefix sums of the accepted flags
    VRPD_BUFFER(Points) samples;    // emit_samples: positions, in emission order
    VRPD_BUFFER(Uints) sample_keys; // emit_samples: this round's arrival keys, to order its samples
    uint dart_count;
    uint work_in_slot;             // COUNTER_WORK0 or COUNTER_WORK1
    uint work_out_slot;
    uint param;                    // emit_samples: samples already emitted in earlier rounds;
                                   // resolve_darts: 1 on a round's first pass (resolve_dart)
};
#ifdef __cplusplus
static_assert(sizeof(DartArgs) == 128 && offsetof(DartArgs, darts) == 48 && offsetof(DartArgs, dart_count) == 112);
#endif

// Exclusive prefix sum over `count` uints in three passes: scan_blocks, scan_sums, scan_add.
struct ScanArgs {
    VRPD_BUFFER(Uints) data;
    VRPD_BUFFER(Uints) block_sums;
    VRPD_BUFFER(Uints) counters;   // scan_sums writes the total to counters[total_slot]
    uint count;
    uint block_count;
    uint total_slot;
    uint pad;
};
#ifdef __cplusplus
static_assert(sizeof(ScanArgs) == 40 && offsetof(ScanArgs, count) == 24);
#endif

// Stable LSD radix sort of one round's samples by arrival key, 8 bits a pass:
// sort_histogram (digit counts per tile of SCAN_BLOCK), a scan of the digit-major histogram,
// sort_scatter (each tile's elements to their ranks, in tile order, so the sort is stable). A few
// elements are ranked by sort_small instead, to the same order.
const uint SORT_BUCKETS = 256u;
// Up to SORT_SMALL elements, sort_small ranks them in one workgroup and one dispatch instead.
const uint SORT_SMALL = 512u;
struct SortArgs {
    VRPD_BUFFER(Points) src_points;
    VRPD_BUFFER(Uints) src_keys;
    VRPD_BUFFER(Points) dst_points;
    VRPD_BUFFER(Uints) dst_keys;
    VRPD_BUFFER(Uints) histogram;  // SORT_BUCKETS x tile_count, digit-major
    uint count;
    uint shift;                     // 0, 8, 16, 24
    uint tile_count;
    uint pad;
};
#ifdef __cplusplus
static_assert(sizeof(SortArgs) == 56 && offsetof(SortArgs, count) == 40);
#endif

// work_args: turns a work list's count into its indirect dispatch, rows of at most max_groups
// workgroups (the device's limit; work_item() numbers the invocations), and empties the other
// list (none where other_slot is slot).
struct WorkArgs {
    VRPD_BUFFER(Uints) counters;
    uint slot;
    uint other_slot;
    uint max_groups;
};
#ifdef __cplusplus
static_assert(sizeof(WorkArgs) == 24 && offsetof(WorkArgs, slot) == 8 && offsetof(WorkArgs, max_groups) == 16);
#else
// This workgroup's number and this invocation's item in a dispatch of rows of workgroups
// (VulkanContext::dispatch, or a pass that work_args dispatched): a dispatch longer than a row
// takes several, and its last row may hold workgroups past its items, which return.
uint workgroup_index() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }
uint work_item() { return workgroup_index() * WORKGROUP_SIZE + gl_LocalInvocationID.x; }
#endif

// gate: zeroes the group counts of the `count` indirect dispatch commands at `table` (3 words
// each) if counters[slot] is not 0, so that the dispatches recorded through them do no work.
struct GateArgs {
    VRPD_BUFFER(Uints) counters;
    VRPD_BUFFER(Uints) table;
    uint slot;
    uint count;
};
#ifdef __cplusplus
static_assert(sizeof(GateArgs) == 24 && offsetof(GateArgs, slot) == 16);
#endif

VRPD_END
#endif
