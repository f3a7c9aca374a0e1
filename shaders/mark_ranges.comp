#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Per active cell: the sites of its darts for throw_sited (shared/throw.h), and from the first
// active cell of each base cell, the base cell's grid word becomes this round's dart range.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = work_item();
    if (e >= a.cell_count) return;
    if (first_in_base_cell(a.domain, a.cells, e))
        mark_dart_range(a, a.cells, a.scan, a.grid, e, group_end(a.domain, a.cells, e, a.cell_count));
    site_cell_darts(a.cells, a.scan, a.darts, e);
}
