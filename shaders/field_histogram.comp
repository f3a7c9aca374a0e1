#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// The active list's cells per exponent of their weighted area, added into the counters.
void main() {
    uint i = field_item();
    if (i >= a.count) return;
    uint e = field_exponent(field_cell(field_run(), a.cells, i));
    atomicAdd(FieldWords(a.counters).value[FIELD_COUNTER_EXPONENTS + e], 1u);
}
