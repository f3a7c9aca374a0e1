#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/field_tree.h"
layout(local_size_x = 64) in;
// Test kernel: the leaf of shared/field_tree.h's descent for a batch of lattice points, its index
// and side's bits, so a test can compare them with the host's.
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Points { uvec2 point[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Leaves { uvec2 leaf[]; };
layout(push_constant) uniform Push { FieldTreeView tree; Points points; Leaves leaves; uint count; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    leaves.leaf[i] = field_leaf_at(tree, points.point[i]);
}
