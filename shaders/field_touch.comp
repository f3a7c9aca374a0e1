#version 460
#extension GL_GOOGLE_include_directive : require
#define FIELD_SEARCH_GATED
#include "common.glsl"
#include "field.glsl"
// Stamps every leaf that sample i (of [first, count)) may cover part of, or conflict with a point
// of (the leaves that meet the square of its cover reach), with round stamp p0: 2 p0 + 1 where it
// covers the whole leaf under the rule, else 2 p0 (FieldRun::touched). The larger stamp stays, so
// a leaf any of the round's samples covers whole reads 2 p0 + 1 (field_triage.comp).
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
         leaf = field_search_next(run.tree, s)) {
        // The leaf is the search's node: its corner in the lattice, and its side.
        uvec2 corner = uvec2(s.origin_x + s.x, s.origin_y + s.y);
        uvec2 far = field_far_corner(run.lattice, corner, run.tree.tile_bits - s.depth);
        uint lo = run.rule == RULE_PRIOR ? 0u : field_min_over(run.table, corner, far);
        atomicMax(run.touched.value[leaf], field_touch_word(a.p0, field_covers(run, i, lo, corner, far)));
        field_store(run.leaf_first, leaf, i);  // a hint for the throw: a sample near the leaf
    }
    field_run_spend(s, budget);
    field_note_budget(budget);
}
