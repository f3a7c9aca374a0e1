#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// Clears the fresh marks: p0 = 0, on the paths to the leaves of the round's darts (cells: point,
// key, leaf; the first of each leaf); p0 = 1, on the paths to samples [first, count) of the run.
void main() {
    uint i = field_item();
    if (i >= field_value(a.count)) return;
    FieldRun run = field_run();
    if (a.p0 == 1u) {
        field_mark(run, run.points.value[i], FIELD_FRESH, false);
        return;
    }
    uvec4 d = FieldCells(a.cells).value[i];
    if (i > 0u && FieldCells(a.cells).value[i - 1u].w == d.w) return;
    field_mark(run, d.xy, FIELD_FRESH, false);
}
