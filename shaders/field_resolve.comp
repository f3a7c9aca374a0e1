#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// One resolution pass over the round's darts (cells: point, key, leaf; words1: their states,
// DART_*; words0: each fresh leaf's first dart). An undecided dart is rejected if an earlier one
// (by key, then index) in conflict is accepted, accepted if every earlier one in conflict is
// rejected, else left undecided and counted. Two darts of one leaf conflict under every rule.
// States only go from undecided to final, so a pass may read states this pass has set.
void main() {
    uint j = field_item();
    uint count = field_value(a.count);
    if (j >= count) return;
    FieldWords states = FieldWords(a.words1);
    if (states.value[j] != DART_UNDECIDED) return;
    FieldRun run = field_run();
    FieldCells darts = FieldCells(a.cells);
    FieldWords first = FieldWords(a.words0);
    uvec4 d = darts.value[j];
    uint r = field_radius(run.table, d.xy);
    FieldBudget budget = FieldBudget(run.budget, 0u);
    FieldSearch s = field_run_search(run, d.xy, d.xy, uint64_t(field_reach(run, d.xy, d.xy, r)), FIELD_FRESH, budget);
    bool rejected = false;
    bool wait = false;
    for (uint leaf = field_search_next(run.tree, s); leaf < FIELD_SEARCH_OVERFLOW && !rejected;
         leaf = field_search_next(run.tree, s)) {
        for (uint k = first.value[leaf]; k < count; k++) {
            uvec4 o = darts.value[k];
            if (o.w != leaf) break;
            if (s.steps++ >= s.budget) break;
            if (!arrives_before(o.z, k, d.z, j)) continue;
            uint state = states.value[k];
            if (state == DART_REJECTED) continue;
            if (leaf != d.w &&
                !field_conflict(rule_f(run.rule, field_radius(run.table, o.xy), r), distance2(run.lattice, o.xy, d.xy)))
                continue;
            if (state == DART_ACCEPTED) {
                rejected = true;
                break;
            }
            wait = true;
        }
    }
    field_run_spend(s, budget);
    field_note_budget(budget);
    if (budget.overflow != 0u) return;
    if (rejected)
        states.value[j] = DART_REJECTED;
    else if (!wait)
        states.value[j] = DART_ACCEPTED;
    else
        atomicAdd(FieldWords(a.counters).value[FIELD_COUNTER_UNDECIDED], 1u);
}
