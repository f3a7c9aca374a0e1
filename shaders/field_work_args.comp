#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "field.glsl"
// One invocation: the indirect dispatch of a resolution pass over work list p0 (field_resolve.comp)
// in its counter slots, as workgroups of p2 invocations, at most p1 of them (the device's limit;
// the pass's invocations stride over the rest), and work list p0 ^ 1 emptied for the pass to fill.
void main() {
    FieldWords counters = FieldWords(a.counters);
    uint slot = FIELD_COUNTER_WORK + 4u * a.p0;
    uint listed = counters.value[slot + 3u];
    counters.value[slot] = min(listed / a.p2 + (listed % a.p2 != 0u ? 1u : 0u), a.p1);
    counters.value[slot + 1u] = 1u;
    counters.value[slot + 2u] = 1u;
    counters.value[FIELD_COUNTER_WORK + 4u * (a.p0 ^ 1u) + 3u] = 0u;
}
