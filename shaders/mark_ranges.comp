#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per base cell (run by its first active cell): the grid word becomes this round's dart range.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = work_item();
    if (e < a.cell_count && first_in_base_cell(a.domain, a.cells, e)) mark_dart_range(a, a.cells, a.scan, a.grid, e);
}
