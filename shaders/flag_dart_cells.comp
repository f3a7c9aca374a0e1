#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Two radii, per active cell that is the first of its base cell: flags the base cells near it
// that get darts this round (see flag_dart_cells). Invocation cell_count clears the flag after the
// last base cell, which makes the exclusive scan end in the total.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = work_item();
    if (e < a.cell_count) {
        if (first_in_base_cell(a.domain, a.cells, e))
            flag_dart_cells(a, a.cells, a.scan, a.grid, e, group_end(a.domain, a.cells, e, a.cell_count));
    } else if (e == a.cell_count) {
        a.scan.value[a.domain.cells_x * a.domain.cells_y] = 0u;
    }
}
