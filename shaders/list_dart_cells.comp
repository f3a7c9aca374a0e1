#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
layout(local_size_x_id = 0) in;
// Two radii, per base cell: a flagged cell joins the list of cells that get darts, at its rank.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint b = work_item();
    if (b < a.cell_count) list_dart_cell(a.domain, a.scan, a.cells_out, b);
}
