// A workgroup's list, in shared memory, of its invocations' items that take a kernel's costly
// part, so that its first invocations run that part together: a SIMD batch of lanes (llvmpipe's
// 8, a GPU's warp) then runs it for the items it holds, not whenever one of its lanes' items
// needs it. Every invocation calls list_begin and list_take, as they hold barriers.
shared uint listed[WORKGROUP_SIZE];
shared uint listed_count;

void list_begin() {
    if (gl_LocalInvocationIndex == 0u) listed_count = 0u;
    barrier();
}

void list_add(uint item) { listed[atomicAdd(listed_count, 1u)] = item; }

// Once every invocation has added its items: whether this invocation takes one, and which.
bool list_take(out uint item) {
    barrier();
    bool mine = gl_LocalInvocationIndex < listed_count;
    item = mine ? listed[gl_LocalInvocationIndex] : 0u;
    return mine;
}
