#version 460
#extension GL_GOOGLE_include_directive : require
#define FIELD_SEARCH_GATED
#include "common.glsl"
#include "field.glsl"
// Stamps round p0 on every leaf that sample i (of [first, count)) may cover part of, or conflict
// with a point of: the leaves that meet the square of its cover reach.
void main() {
    uint i = field_item();
    if (i >= a.count) return;
    FieldRun run = field_run();
    uvec2 p = run.points.value[i];
    uint r = run.radii.value[i];
    FieldBudget budget = FieldBudget(run.budget, 0u);
    FieldSearch s = field_run_search(run, p, p, uint64_t(field_cover_reach(run, p, r)), 0u, budget);
    // Only the leaves with a point that r may cover or conflict with (the gate's reach).
    field_run_gate(run, s, p, r, 1u);
    for (uint leaf = field_search_next(run.tree, s); leaf < FIELD_SEARCH_OVERFLOW;
         leaf = field_search_next(run.tree, s))
        run.touched.value[leaf] = a.p0;
    field_run_spend(s, budget);
    field_note_budget(budget);
}
