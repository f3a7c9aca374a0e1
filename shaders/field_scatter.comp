#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
#include "field_exponents.glsl"
// Writes each active cell's fate (words1) into the next list (target) from its offset (words0,
// scanned): itself, or its open children in order. Counts the written cells per exponent and
// keeps their least side's bits, a workgroup's first in shared memory (field_exponents.glsl).
shared uint least_bits;

void main() {
    field_exponents_begin();
    if (gl_LocalInvocationIndex == 0u) least_bits = 0xFFFFFFFFu;
    barrier();
    uint i = field_item();
    uint fate = i < a.count ? FieldWords(a.words1).value[i] : 0u;
    if (fate != 0u) {
        FieldRun run = field_run();
        uvec4 cell = field_cell(run, a.cells, i);
        uint at = FieldWords(a.words0).value[i];
        if ((fate & FIELD_SPLIT) == 0u) {
            field_put_cell(a.target, at, cell);
            field_exponents_count(field_exponent(cell));
            atomicMin(least_bits, cell.z);
        } else {
            uint side = 1u << (cell.z - 1u);
            for (uint k = 0u; k < 4u; k++) {
                if ((fate >> k & 1u) == 0u) continue;
                uvec2 corner = uvec2(cell.x + (k & 1u) * side, cell.y + (k >> 1u) * side);
                uvec4 child = uvec4(corner, cell.z - 1u, field_weight(run, corner, cell.z - 1u));
                field_put_cell(a.target, at++, child);
                field_exponents_count(field_exponent(child));
            }
            if ((fate & 0xFu) != 0u) atomicMin(least_bits, cell.z - 1u);
        }
    }
    barrier();
    field_exponents_end();
    if (gl_LocalInvocationIndex == 0u && least_bits != 0xFFFFFFFFu)
        atomicMin(FieldWords(a.counters).value[FIELD_COUNTER_LEAST_BITS], least_bits);
}
