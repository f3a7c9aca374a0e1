// Included by the kernels that count cells per exponent of their weighted area (field_exponent)
// into the counters: a workgroup counts its cells in shared memory, then adds each exponent it
// met into the counters once. A list's cells have few exponents (under the uniform weighting one
// or two sides), so an atomic per cell on the counters' words would queue the whole device's
// invocations on a few addresses.
const uint FIELD_EXPONENT_WORDS = FIELD_COUNTER_WORDS - FIELD_COUNTER_EXPONENTS;
shared uint field_exponent_counts[FIELD_EXPONENT_WORDS];

// Zeroes the workgroup's counts; every invocation calls it, then the kernel's barrier().
void field_exponents_begin() {
    for (uint e = gl_LocalInvocationIndex; e < FIELD_EXPONENT_WORDS; e += gl_WorkGroupSize.x)
        field_exponent_counts[e] = 0u;
}

void field_exponents_count(uint e) { atomicAdd(field_exponent_counts[e], 1u); }

// Adds the workgroup's counts into the counters; every invocation calls it after a barrier().
void field_exponents_end() {
    for (uint e = gl_LocalInvocationIndex; e < FIELD_EXPONENT_WORDS; e += gl_WorkGroupSize.x) {
        uint n = field_exponent_counts[e];
        if (n != 0u) atomicAdd(FieldWords(a.counters).value[FIELD_COUNTER_EXPONENTS + e], n);
    }
}
