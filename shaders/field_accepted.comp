#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// p0 = 0: flags the accepted darts (words1: states) in words0, for their ranks. p0 = 1: writes
// each accepted dart's key (words2) and index (target, as uvec2) at its rank (words0, scanned;
// total in p1), for the sort into arrival order.
void main() {
    uint j = field_item();
    if (j >= a.count) return;
    if (a.p0 == 0u) {
        FieldWords(a.words0).value[j] = FieldWords(a.words1).value[j] == DART_ACCEPTED ? 1u : 0u;
        return;
    }
    FieldWords ranks = FieldWords(a.words0);
    uint at = ranks.value[j];
    uint next = field_scan_end(ranks, j, a.count, a.p1);
    if (next == at) return;
    FieldWords(a.words2).value[at] = FieldCells(a.cells).value[j].z;
    FieldPairs(a.target).value[at] = uvec2(j, 0u);
}
