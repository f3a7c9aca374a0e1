#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per active cell: writes its darts (those covered by earlier samples already rejected), its base
// cell's dart range, and appends its undecided darts to work list 0. The list's order depends on
// scheduling, which is harmless: resolution's result does not depend on the visiting order.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = gl_GlobalInvocationID.x;
    if (e >= a.cell_count) return;
    uint undecided = throw_cell(a, a.cells, a.scan, a.darts, a.grid, e);
    if (undecided == 0u) return;
    uint slot = atomicAdd(a.counters.value[COUNTER_WORK0 + 3u], undecided);
    for (uint j = a.scan.value[e]; j < a.scan.value[e + 1u]; j++)
        if (a.darts.dart[j].w == DART_UNDECIDED) a.work.value[slot++] = j;
}
