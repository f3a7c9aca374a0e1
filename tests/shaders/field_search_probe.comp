#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/darts.h"
#include "shared/field_search.h"
layout(local_size_x = 64) in;
// Test kernel: shared/field_search.h's search for a batch of queries, each answered by the
// number of leaves it meets, two sums and a xor of hashes of their indices (a multiset's
// fingerprint), so a test can compare them with the host's searches; a search past its budget
// by FIELD_SEARCH_OVERFLOW and the leaves met before.
struct Query {
    uvec2 a;
    uvec2 b;
    uint reach;
    uint need;
};
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Queries { Query query[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer Results { uvec4 result[]; };
layout(push_constant) uniform Push {
    FieldTreeView tree;
    Lattice lattice;
    Queries queries;
    Results results;
    uint count;
    uint budget;
};

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    Query q = queries.query[i];
    FieldSearch s = field_search_begin(tree, lattice, q.a, q.b, uint64_t(q.reach), q.need, budget);
    uvec4 r = uvec4(0u);
    for (uint leaf = field_search_next(tree, s); leaf != FIELD_SEARCH_DONE; leaf = field_search_next(tree, s)) {
        if (leaf == FIELD_SEARCH_OVERFLOW) {
            r = uvec4(FIELD_SEARCH_OVERFLOW, r.x, 0u, 0u);
            break;
        }
        r.x++;
        r.y += hash32(leaf);
        r.z += hash_mix(leaf, 0x5bd1e995u);
        r.w ^= hash32(leaf + 1u);
    }
    results.result[i] = r;
}
