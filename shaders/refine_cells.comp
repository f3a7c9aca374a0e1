#version 460
#extension GL_GOOGLE_include_directive : require
// Per active cell: which of its param (4 children, or 1: the cell itself) slots stay active, and
// how many (see refine_cells_of_base for why one cell an invocation). Invocation cell_count writes
// the trailing 0 that makes the scan end in the total. Variant refine_cells_one (CMakeLists.txt):
// one radius only.
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint e = work_item();
    if (e < a.cell_count) {
        refine_cells_of_base(a, a.cells, a.scan, a.masks, a.grid, e, e + 1u);
    } else if (e == a.cell_count) {
        a.scan.value[e] = 0u;
    }
}
