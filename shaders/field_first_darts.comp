#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// Each dart's r, for the resolution's passes (in target after its summaries and work lists, at
// word 6 p2; p2: the darts thrown). The darts (cells: point, key, leaf) come in cell order, so a
// leaf's darts are consecutive: each leaf's first dart is recorded in words0 (per leaf) and its
// path marked fresh, so that the resolution's searches meet only the leaves with darts; the
// leaf's slot in words2 (its accepted dart, field_resolve.comp) starts empty.
void main() {
    uint j = field_item();
    if (j >= field_value(a.count)) return;
    uvec4 d = FieldCells(a.cells).value[j];
    field_dart_radii(a.target, a.p2).value[j] = field_radius(field_run().table, d.xy);
    if (j > 0u && FieldCells(a.cells).value[j - 1u].w == d.w) return;
    FieldWords(a.words0).value[d.w] = j;
    FieldWords(a.words2).value[j] = 0u;
    field_mark(field_run(), d.xy, FIELD_FRESH, true);
}
