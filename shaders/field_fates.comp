#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// Each active cell's fate (words1) and the cells it leaves in the next list (words0, scanned
// next): dropped (0), kept whole (FIELD_KEEP), or split (FIELD_SPLIT | the mask of its open
// children). Compiled with FIELD_BALANCE (the kernel field_balance) it balances the list; without,
// it refines it after a round. Each holds only its own half: llvmpipe builds and runs code a
// constant leaves dead as if it were live.
// Balancing splits the cells whose biased exponent is p2 or more (and whose side is above one
// lattice unit); the children a sample covers drop. Refining takes one of the lists
// field_triage.comp made (in target, dispatched by work_args.comp; p0's list 0 the cells that
// search for a cover, list 1 the others, with FIELD_SPLIT_EVERY beside it; p1 cells in all): it
// drops a cell that a sample of this round covers, keeps one of one lattice unit or, unless
// every cell splits, one that took no dart, and splits the others
// (words2: the round's dart counts, scanned; their total in p2; p3: the round's stamp in
// FieldRun::touched).

void main() {
#ifdef FIELD_BALANCE
    uint i = field_item();
    if (i >= a.count) return;
#else
    uint list = a.p0 & 1u;
    uint k = work_item();
    if (k >= FieldWords(a.counters).value[FIELD_COUNTER_WORK + 4u * list + 3u]) return;
    uint i = FieldWords(a.target).value[field_search_slot(list, k, a.p1)];
#endif
    FieldRun run = field_run();
    uvec4 cell = field_cell(run, a.cells, i);
    FieldBudget budget = FieldBudget(run.budget, 0u);
    uint fate = FIELD_KEEP;
#ifdef FIELD_BALANCE
    if (cell.z > 0u && field_exponent(cell) >= a.p2)
        fate = FIELD_SPLIT | field_open_children(run, cell.xy, cell.z, budget);
#else
    bool splits = field_splits(a.p0, FieldWords(a.words2), i, a.p1, a.p2);
    uvec2 leaf = field_leaf_at(run.tree, cell.xy);
    // Only a cell smaller than its leaf searches for a cover by this round's samples (touched
    // this round, p3); field_triage.comp settled the others, and the cells whose leaf holds a
    // sample.
    bool near = field_touched_in(run.touched.value[leaf.x], a.p3) && cell.z < leaf.y;
    uvec2 far = field_far_corner(run.lattice, cell.xy, cell.z);
    if (near && field_covered(run, cell.xy, far, FIELD_FRESH, budget))
        fate = 0u;
    else if (splits && cell.z > 0u)
        fate = FIELD_SPLIT | field_open_children(run, cell.xy, cell.z, budget);
#endif
    field_note_budget(budget);
    if ((fate & FIELD_SPLIT) != 0u) atomicAdd(FieldWords(a.counters).value[FIELD_COUNTER_SPLITS], 1u);
    FieldWords(a.words1).value[i] = fate;
    FieldWords(a.words0).value[i] = fate == FIELD_KEEP ? 1u : uint(bitCount(fate & 0xFu));
}
