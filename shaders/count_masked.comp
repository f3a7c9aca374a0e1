#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/sampler.h"
#include "masked.glsl"
layout(local_size_x_id = 0) in;
// Mask mode, per base cell: its darts this round, into its grid word (counted_word) and the scan
// input. Invocation cell_count writes the trailing 0 that makes the exclusive scan end in the total.
layout(push_constant) uniform Push { CellArgs a; };

void main() {
    uint i = work_item();
    if (i < a.cell_count) {
        uint b = masked_base(a, i);
        uvec2 w = a.grid.word[b];
        uint count = 0u;
        if (masked_active(w)) {
            count = masked_dart_count(a, w, b);
            if (count > GRID_MASK_BITS) set_flag(a.counters, COUNTER_CROWDED);
            a.grid.word[b] = counted_word(w, count);
        }
        a.scan.value[i] = count;
    } else if (i == a.cell_count) {
        a.scan.value[i] = 0u;
    }
}
