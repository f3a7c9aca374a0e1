#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
#include "field_exponents.glsl"
// The active list's cells per exponent of their weighted area, added into the counters.
void main() {
    field_exponents_begin();
    barrier();
    uint i = field_item();
    if (i < a.count) field_exponents_count(field_exponent(field_cell(field_run(), a.cells, i)));
    barrier();
    field_exponents_end();
}
