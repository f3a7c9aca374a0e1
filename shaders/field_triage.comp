#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// The fates field_fates.comp would give the active cells that need no search, from their leaf's
// sample and stamp (FieldRun::touched) and their darts, written as field_fates writes them (words1,
// and words0 for the scan); the others listed in `target` for field_fates. A cell whose leaf one
// of this round's samples covers whole is covered; a cell that is its whole leaf, stamped but not
// so, is covered by none of them. So only a smaller cell near this round's samples searches for a
// cover (list 0, its length in counter slot FIELD_COUNTER_WORK + 3), and only a
// cell that took darts (any, with FIELD_SPLIT_EVERY in p0) and stays open searches for its
// children's covers to split (list 1, its length in slot FIELD_COUNTER_WORK + 7;
// field_search_slot places both). Kept apart from
// field_fates, and the two kinds apart from each other, since llvmpipe runs a search's code for
// every SIMD batch of 8 cells that one of them reaches. words2: the round's dart counts, scanned
// (their total in p2); p3: the round's stamp.
void main() {
    uint i = field_item();
    if (i >= a.count) return;
    FieldRun run = field_run();
    uvec3 cell = field_cell_block(a.cells, i);
    bool splits = field_splits(a.p0, FieldWords(a.words2), i, a.count, a.p2);
    uvec2 leaf = field_leaf_at(run.tree, cell.xy);
    uint stamp = run.touched.value[leaf.x];
    bool near = field_touched_in(stamp, a.p3);
    uint fate = FIELD_KEEP;
    if (near || splits) {
        if (run.leaf_sample.value[leaf.x] != FIELD_NO_SAMPLE || stamp == field_touch_word(a.p3, true)) {
            fate = 0u;
        } else if ((near && cell.z < leaf.y) || (splits && cell.z > 0u)) {
            uint list = near && cell.z < leaf.y ? 0u : 1u;
            uint k = atomicAdd(FieldWords(a.counters).value[FIELD_COUNTER_WORK + 4u * list + 3u], 1u);
            FieldWords(a.target).value[field_search_slot(list, k, a.count)] = i;
            return;
        }
    }
    FieldWords(a.words1).value[i] = fate;
    FieldWords(a.words0).value[i] = fate == FIELD_KEEP ? 1u : 0u;
}
