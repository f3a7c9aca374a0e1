#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// Writes each active cell's fate (words1) into the next list (target) from its offset (words0,
// scanned): itself, or its open children in order. Counts the written cells per exponent and
// keeps their least side's bits.
void main() {
    uint i = field_item();
    if (i >= a.count) return;
    uint fate = FieldWords(a.words1).value[i];
    if (fate == 0u) return;
    FieldRun run = field_run();
    uvec4 cell = field_cell(run, a.cells, i);
    uint at = FieldWords(a.words0).value[i];
    FieldWords counters = FieldWords(a.counters);
    if ((fate & FIELD_SPLIT) == 0u) {
        field_put_cell(a.target, at, cell);
        atomicAdd(counters.value[FIELD_COUNTER_EXPONENTS + field_exponent(cell)], 1u);
        atomicMin(counters.value[FIELD_COUNTER_LEAST_BITS], cell.z);
        return;
    }
    uint side = 1u << (cell.z - 1u);
    for (uint k = 0u; k < 4u; k++) {
        if ((fate >> k & 1u) == 0u) continue;
        uvec2 corner = uvec2(cell.x + (k & 1u) * side, cell.y + (k >> 1u) * side);
        uvec4 child = uvec4(corner, cell.z - 1u, field_weight(run, corner, cell.z - 1u));
        field_put_cell(a.target, at++, child);
        atomicAdd(counters.value[FIELD_COUNTER_EXPONENTS + field_exponent(child)], 1u);
    }
    if ((fate & 0xFu) != 0u) atomicMin(counters.value[FIELD_COUNTER_LEAST_BITS], cell.z - 1u);
}
