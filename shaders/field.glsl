// Included by the field sampler's kernels (shaders/field_*.comp) after common.glsl: their push
// constants (shared/field_run.h's FieldArgs), the buffers they address, and the steps every
// kernel shares.

// The run's rule, boundary and weighting, as constants of the pipeline (FieldVulkan makes one per
// variant, shared/field_run.h's field_variant), equal to the run's own: the branches on them fold
// away where the driver builds the kernel, and llvmpipe would run both sides of each
// (shared/radii.h). Whether the table lookups read kinked cells is the build's (FIELD_KINKS, 1
// in each kernel's `_kinks` build, CMakeLists.txt): the kernels for tables without them carry no
// code for them at all, which llvmpipe would translate on every run, specialized away or not.
layout(constant_id = 1) const uint FIELD_VARIANT = 0u;
#ifndef FIELD_KINKS
#define FIELD_KINKS 0
#endif
#include "shared/darts.h"
#include "shared/field_run.h"
#include "shared/kernels.h"
layout(local_size_x_id = 0) in;
layout(push_constant) uniform Push { FieldArgs a; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer FieldRunRef { FieldRun value; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer FieldCells { uvec4 value[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer FieldCellWords { uvec2 value[]; };
// The accepted darts as (dart index, 0), sorted into arrival order by key.
layout(buffer_reference, std430, buffer_reference_align = 8) buffer FieldPairs { uvec2 value[]; };

// A word that invocations of one dispatch write while others read or write it (a dart's state, a
// leaf's accepted dart or hint): loaded and stored atomically (relaxed), so there is no data race.
uint field_load(FieldWords w, uint i) {
    return atomicLoad(w.value[i], VRPD_RELAXED);
}
void field_store(FieldWords w, uint i, uint v) {
    atomicStore(w.value[i], v, VRPD_RELAXED);
}

// This invocation's item, or a value >= a.count past the list.
uint field_item() { return a.first + work_item(); }

// A count or parameter: v, or with FIELD_COUNTED set the counter it names (FieldArgs).
uint field_value(uint v) {
    return (v & FIELD_COUNTED) == 0u ? v : FieldWords(a.counters).value[v & ~FIELD_COUNTED];
}

const bool FIELD_DENSITY = (FIELD_VARIANT & FIELD_VARIANT_DENSITY) != 0u;  // Eq. 12's weighting
FieldRun field_run() {
    FieldRun run = FieldRunRef(a.run).value;
    run.rule = FIELD_VARIANT & 3u;
    run.lattice.periodic = (FIELD_VARIANT & FIELD_VARIANT_TORUS) != 0u ? 1u : 0u;
    return run;
}

// The exponent of a cell's weighted area, biased: 2 bits, less 2 weight under Eq. 12.
uint field_exponent(uvec4 cell) { return FIELD_EXPONENT_BIAS + 2u * cell.z - (FIELD_DENSITY ? 2u * cell.w : 0u); }

// Eq. 12's weight of the cell of side 2^bits at `corner` (shared/field.h; 0 without the weighting).
uint field_weight(FieldRun run, uvec2 corner, uint bits) {
    if (!FIELD_DENSITY) return 0u;
    uvec2 far = field_far_corner(run.lattice, corner, bits);
    return field_cell_weight(run.r_lo, field_min_over(run.table, corner, far));
}

// An active list holds a cell in 8 bytes, as the host's does: its corner's y, and its x with the
// side as 2 x + 2^bits, whose lowest set bit is bit `bits`. Its weight is found again from the
// table. Cell i of `list` as (corner, side's bits), and as (corner, side's bits, weight):
uvec3 field_cell_block(uint64_t list, uint i) {
    uvec2 word = FieldCellWords(list).value[i];
    return uvec3((word.x & (word.x - 1u)) >> 1u, word.y, uint(findLSB(word.x)));
}
uvec4 field_cell(FieldRun run, uint64_t list, uint i) {
    uvec3 block = field_cell_block(list, i);
    return uvec4(block, field_weight(run, block.xy, block.z));
}
void field_put_cell(uint64_t list, uint i, uvec4 cell) {
    FieldCellWords(list).value[i] = uvec2(2u * cell.x + (1u << cell.z), cell.y);
}

// The end of item i's range in an exclusive prefix sum `scan` of `count` items whose total is
// `total`: the next item's start, or the total after the last.
uint field_scan_end(FieldWords scan, uint i, uint count, uint total) {
    return i + 1u < count ? scan.value[i + 1u] : total;
}

// Refinement: whether active cell i (of `count`) splits if it stays open: it took darts (its
// range in the round's scanned dart counts `darts`, of total `total`, is not empty), or `flags`
// holds FIELD_SPLIT_EVERY.
bool field_splits(uint flags, FieldWords darts, uint i, uint count, uint total) {
    return (flags & FIELD_SPLIT_EVERY) != 0u || field_scan_end(darts, i, count, total) > darts.value[i];
}

// A leaf's word in FieldRun::touched for round stamp k: 2 k + 1 where one of the round's samples
// covers the whole leaf, else 2 k (field_touch.comp writes the larger one, by atomicMax).
uint field_touch_word(uint k, bool whole) { return 2u * k + (whole ? 1u : 0u); }
bool field_touched_in(uint word, uint k) { return word >> 1u == k; }

// Item k of the refinement's work list `list` (field_triage.comp), of `cells` slots: list 0 (the
// cells that search for a cover) from the front, list 1 (those that only split) from the back.
uint field_search_slot(uint list, uint k, uint cells) { return list == 0u ? k : cells - 1u - k; }

// Each dart's r during a resolution, after its summaries and work lists in the array `raw` of
// the round's `thrown` darts (field_first_darts.comp writes it, field_resolve.comp reads it).
FieldWords field_dart_radii(uint64_t raw, uint thrown) { return FieldWords(raw + uint64_t(6u * thrown) * 4u); }

// Sets (on) or clears `flag` on the node words from the tile's root down to the leaf holding p.
void field_mark(FieldRun run, uvec2 p, uint flag, bool on) {
    FieldTreeView t = run.tree;
    uint at = field_tile_of(t, p);
    uint w = on ? atomicOr(t.roots.value[at], flag) : atomicAnd(t.roots.value[at], ~flag);
    uint bits = t.tile_bits;
    while ((w & FIELD_LEAF) == 0u) {
        at = (w & FIELD_INDEX) + field_child_of(p, bits);
        w = on ? atomicOr(t.nodes.value[at], flag) : atomicAnd(t.nodes.value[at], ~flag);
        bits--;
    }
}

// Lowers the least key (FieldRun::keys) of the inner nodes on the path to the leaf holding p to
// `key`.
void field_note_key(FieldRun run, uvec2 p, uint key) {
    FieldTreeView t = run.tree;
    uint w = t.roots.value[field_tile_of(t, p)];
    uint bits = t.tile_bits;
    while ((w & FIELD_LEAF) == 0u) {
        uint children = w & FIELD_INDEX;
        if (run.keys.value[children >> 2u] > key) atomicMin(run.keys.value[children >> 2u], key);
        w = t.nodes.value[children + field_child_of(p, bits)];
        bits--;
    }
}

// Records a search past its budget for the host.
void field_note_budget(FieldBudget budget) {
    if (budget.overflow != 0u) atomicOr(FieldWords(a.counters).value[FIELD_COUNTER_OVERFLOW], 1u);
}
