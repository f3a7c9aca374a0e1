#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// Places the given samples (conflict-free under the rule; their points already in the run's
// points, in their order): r at each, its leaf's sample, and the path marked occupied and fresh.
void main() {
    uint i = field_item();
    if (i >= a.count) return;
    FieldRun run = field_run();
    uvec2 p = run.points.value[i];
    run.radii.value[i] = field_radius(run.table, p);
    run.leaf_sample.value[field_leaf_at(run.tree, p).x] = i;
    field_mark(run, p, FIELD_OCCUPIED | FIELD_FRESH, true);
}
