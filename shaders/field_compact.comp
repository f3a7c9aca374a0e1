#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// Moves the flagged entries of a uvec4 list (cells) to `target` in order: words0 holds the flags'
// exclusive prefix sums, their total in p0 (a value, or FIELD_COUNTED and its counter).
void main() {
    uint i = field_item();
    if (i >= a.count) return;
    FieldWords ranks = FieldWords(a.words0);
    uint at = ranks.value[i];
    uint next = field_scan_end(ranks, i, a.count, field_value(a.p0));
    if (next > at) FieldCells(a.target).value[at] = FieldCells(a.cells).value[i];
}
