#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per active cell: its Poisson number of darts this round. Invocation cell_count writes the
// trailing 0 that makes the exclusive scan end in the total.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = work_item();
    // A list written at its worst-case size (VulkanEngine::refine_listed) ends in unused entries,
    // (GRID_EMPTY, GRID_EMPTY): no darts.
    if (e < a.cell_count) {
        uvec2 corner = a.cells.cell[e];
        a.scan.value[e] = corner.x == GRID_EMPTY ? 0u : dart_count(cell_stream(a.round_key, corner), a.param);
    } else if (e == a.cell_count) {
        a.scan.value[e] = 0u;
    }
}
