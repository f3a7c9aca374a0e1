#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// The darts of each active cell with any (words2 lists those cells, a.count of them, from
// field_count_darts.comp; words0: the p3 cells' dart counts' offsets, scanned, their total in p2),
// written at their slots in `target` as (point, key, leaf), each with a flag in words1: 1 if it
// stays, 0 if it falls outside the lattice, is thinned by Eq. 12, lands in a leaf with a
// sample or conflicts with one: the leaf's hint first (FieldRun::leaf_first, a sample where it
// is below p1, the samples' count), then by a search, whose find becomes the hint. p0: the
// round's key. The cells without darts, most of them at 0.3 darts a cell, take no invocation
// (llvmpipe runs the whole kernel for each SIMD batch).
void main() {
    uint item = field_item();
    if (item >= a.count) return;
    uint i = FieldWords(a.words2).value[item];
    FieldRun run = field_run();
    uvec4 cell = field_cell(run, a.cells, i);
    FieldWords offsets = FieldWords(a.words0);
    uint first = offsets.value[i];
    uint end = i + 1u < a.p3 ? offsets.value[i + 1u] : a.p2;
    uint stream = cell_stream(a.p0, cell.xy);
    uint leaf = field_leaf_at(run.tree, cell.xy).x;
    bool taken = run.leaf_sample.value[leaf] != FIELD_NO_SAMPLE;
    // No sample can conflict with a point of a leaf none has touched.
    bool untouched = run.touched.value[leaf] == 0u;
    uint bound = uint(min(uint64_t(run.r_lo) << cell.w, uint64_t(0xFFFFFFFFu)));
    FieldBudget budget = FieldBudget(run.budget, 0u);
    for (uint j = 0u; j < end - first; j++) {
        uvec4 d = make_dart(stream, j, cell.xy, 1u << cell.z);
        uvec2 p = d.xy;
        uint stays = 0u;
        if (!taken && in_lattice(run.lattice, p)) {
            uint r = field_radius(run.table, p);
            if (!FIELD_DENSITY || keep_weighted(hash_mix(hash_mix(stream, 0xD1B54A35u), j), bound, r)) {
                stays = 1u;
                if (!untouched) {
                    uint hint = field_load(run.leaf_first, leaf);
                    if (hint < a.p1 && field_conflicts_with(run, hint, p, r)) {
                        stays = 0u;
                    } else {
                        uint x = field_conflicting(run, p, r, budget);
                        if (x != FIELD_NO_SAMPLE) {
                            stays = 0u;
                            field_store(run.leaf_first, leaf, x);
                        }
                    }
                }
            }
        }
        FieldCells(a.target).value[first + j] = uvec4(p, d.z, leaf);
        FieldWords(a.words1).value[first + j] = stays;
    }
    field_note_budget(budget);
}
