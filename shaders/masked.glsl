// Included by mask mode's kernels after shared/sampler.h. They run over the base cells, or at
// the last mask-mode level over the list of the active ones, where about three in four base
// cells are idle and a kernel over all of them runs most SIMD batches for one or two working
// lanes. Target i is base cell masked_base(a, i); the arrays
// a target owns (its dart count, mask, rank) are indexed by i.

// The list (base cell indices, in base cell order, so the darts keep their indices) is passed in
// CellArgs::cells, which mask mode does not otherwise use; 0 for none.
uint masked_base(CellArgs a, uint i) {
    uint64_t list = uint64_t(a.cells);
    return list == 0ul ? i : Uints(list).value[i];
}

// Whether a refinement scatters the samples' covers (scatter_box: into 4 or 16 sub-cells) rather
// than each base cell gathering its samples: over every base cell, not a list, whose indices
// the masks then share with the grid.
bool scattered_refinement(CellArgs a) {
    return uint64_t(a.cells) == 0ul && box_any(scatter_box(a.domain, a.side, a.param));
}

// A workgroup's count of active sub-cells (refine_masked, apply_masks), added once to
// COUNTER_ACTIVE: a global atomic an invocation contends on llvmpipe. Every invocation calls
// begin and end with the same `counting`, as they hold barriers.
shared uint group_active;
void group_active_begin(bool counting) {
    if (!counting) return;
    if (gl_LocalInvocationIndex == 0u) group_active = 0u;
    barrier();
}
void group_active_add(uint mask) {
    if (mask != 0u) atomicAdd(group_active, uint(bitCount(mask)));
}
void group_active_end(CellArgs a, bool counting) {
    if (!counting) return;
    barrier();
    if (gl_LocalInvocationIndex == 0u && group_active != 0u) atomicAdd(a.counters.value[COUNTER_ACTIVE], group_active);
}
