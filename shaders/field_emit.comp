#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// The accepted darts in arrival order (target: uvec2 (dart index, 0), sorted by key) become samples
// p0 + rank: point, r, the leaf's sample, and the path marked occupied and fresh.
void main() {
    uint q = field_item();
    if (q >= a.count) return;
    FieldRun run = field_run();
    uvec4 d = FieldCells(a.cells).value[FieldPairs(a.target).value[q].x];
    uint s = a.p0 + q;
    run.points.value[s] = d.xy;
    run.radii.value[s] = field_radius(run.table, d.xy);
    run.leaf_sample.value[d.w] = s;
    field_mark(run, d.xy, FIELD_OCCUPIED | FIELD_FRESH, true);
}
