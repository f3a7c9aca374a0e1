#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Mask mode, per base cell: after the flags' exclusive scan, a flagged base cell joins the list
// of active base cells (masked.glsl) at its rank, in base cell order.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint b = work_item();
    if (b >= a.cell_count) return;
    uint rank = a.scan.value[b];
    if (a.scan.value[b + 1u] != rank) a.work.value[rank] = b;
}
