#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// Each active cell's darts this round (words0, scanned next): a Poisson count at its weighted
// area's rate, from its stream; the cells with darts listed in words2, in any order (their
// number in counter slot FIELD_COUNTER_DART_CELLS), for the throw. p0: the round's key; words1:
// e^-lambda per biased exponent, in 2^-32 units.
void main() {
    uint i = field_item();
    if (i >= a.count) return;
    uvec4 cell = field_cell(field_run(), a.cells, i);
    uint stream = cell_stream(a.p0, cell.xy);
    uint darts = dart_count(stream, FieldWords(a.words1).value[field_exponent(cell)]);
    FieldWords(a.words0).value[i] = darts;
    if (darts != 0u)
        FieldWords(a.words2).value[atomicAdd(FieldWords(a.counters).value[FIELD_COUNTER_DART_CELLS], 1u)] = i;
}
