#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/field_table.h"
layout(local_size_x = 64) in;
// Test kernel: the lookups of shared/field_table.h on the device for a batch of blocks [a, b]
// (uvec4 a.x, a.y, b.x, b.y), so a test can compare them with the host's: r at a and at b, then
// the least and greatest r over the block, alone and together.
const uint PROBE_RESULTS = 6u;
layout(buffer_reference, std430, buffer_reference_align = 16) buffer Blocks { uvec4 block[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Results { uint value[]; };
layout(push_constant) uniform Push { FieldTableView table; Blocks blocks; Results results; uint count; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    uvec2 a = blocks.block[i].xy;
    uvec2 b = blocks.block[i].zw;
    uvec2 both = field_extremes_over(table, a, b);
    uint at = i * PROBE_RESULTS;
    results.value[at] = field_radius(table, a);
    results.value[at + 1u] = field_radius(table, b);
    results.value[at + 2u] = field_min_over(table, a, b);
    results.value[at + 3u] = field_max_over(table, a, b);
    results.value[at + 4u] = both.x;
    results.value[at + 5u] = both.y;
}
