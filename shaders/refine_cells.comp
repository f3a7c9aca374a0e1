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

#ifdef VRPD_ONE_RADIUS
void main() {
    uint e = work_item();
    if (e < a.cell_count) {
        refine_cells_of_base(a, a.cells, a.scan, a.masks, a.grid, e, e + 1u);
    } else if (e == a.cell_count) {
        a.scan.value[e] = 0u;
    }
}
#else
// Two radii: most cells lie in spent base cells (base_spent), which a few reads tell, and the
// rest run T tests, a workgroup's together (workgroup_list.glsl).
#include "workgroup_list.glsl"

void main() {
    uint e = work_item();
    list_begin();
    if (e < a.cell_count) {
        uvec2 base = base_cell_of(a.domain, a.cells.cell[e]);
        if (base_spent(local_domain(a.domain, base), a.grid, base)) {
            a.masks.value[e] = 0u;
            a.scan.value[e] = 0u;
        } else {
            list_add(e);
        }
    } else if (e == a.cell_count) {
        a.scan.value[e] = 0u;
    }
    uint p;
    if (list_take(p)) refine_unspent_cell(a, a.cells, a.scan, a.masks, a.grid, p);
}
#endif
