// Dart generation: a counter-based hash RNG keyed by (seed, round, cell, dart), so every device
// throws the same darts. Each active cell receives a Poisson number of darts per round, each with
// a uniform lattice position in the cell and a random arrival key. A Poisson process over the
// active cells, read in arrival order, is a sequence of i.i.d. uniform darts over the active area:
// the random sequential adsorption of the paper's Eq. 4.
#ifndef VRPD_DARTS_H
#define VRPD_DARTS_H
#include "bridge.h"

VRPD_BEGIN

// lowbias32 (C. Wellons' hash prospector): a 32-bit integer hash with low avalanche bias.
VRPD_FN uint hash32(uint x) {
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

VRPD_FN uint hash_mix(uint h, uint v) { return hash32(h ^ (v * 0x9e3779b9u + 0x7f4a7c15u)); }

// The random key of one round of a run: every cell's stream that round starts from it. Rounds
// are numbered globally, so no two rounds of a run share a key. The engines compute it on the
// host and pass it to the kernels (CellArgs::round_key): the seed is not part of the domain.
VRPD_FN uint round_key(uint seed, uint round) { return hash_mix(hash32(seed), round); }

// The random stream of one cell in one round. A cell is unique in a round (by its corner).
VRPD_FN uint cell_stream(uint round_key, uvec2 corner) { return hash_mix(hash_mix(round_key, corner.x), corner.y); }

// Poisson(lambda) by Knuth's product of uniforms, in 32-bit fixed point so that every device
// counts alike: exp_neg_lambda = floor(exp(-lambda) * 2^32). Expected lambda + 1 hashes.
VRPD_FN uint dart_count(uint stream, uint exp_neg_lambda) {
    uint64_t product = uint64_t(0xFFFFFFFFu);
    uint k = 0u;
    for (;;) {
        product = (product * uint64_t(hash_mix(stream, 0xA5A5A5A5u + k))) >> 32;
        if (product <= uint64_t(exp_neg_lambda)) break;
        k++;
    }
    return k;
}

#ifdef __cplusplus
#ifdef VRPD_HOST_AVX2
// The host's body of cell_dart_counts on processors with AVX2: eight cells a step, the hashes in
// 32-bit lanes and each lane's product of uniforms in 64 (even and odd lanes apart), the step's
// uniforms drawn while some lane's product stays above exp_neg_lambda.
[[gnu::target("avx2")]] inline __m256i hash32_x8(__m256i x) {
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
    x = _mm256_mullo_epi32(x, _mm256_set1_epi32(int(0x7feb352du)));
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 15));
    x = _mm256_mullo_epi32(x, _mm256_set1_epi32(int(0x846ca68bu)));
    return _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
}
[[gnu::target("avx2")]] inline __m256i hash_mix_x8(__m256i h, __m256i v) {
    const __m256i m = _mm256_mullo_epi32(v, _mm256_set1_epi32(int(0x9e3779b9u)));
    return hash32_x8(_mm256_xor_si256(h, _mm256_add_epi32(m, _mm256_set1_epi32(0x7f4a7c15))));
}
[[gnu::target("avx2")]] inline void cell_dart_counts_avx2(uint round_key, const uvec2* corners, uint n,
                                                          uint exp_neg_lambda, uint* counts) {
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i split = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);  // x of 4 corners, then their y
    const __m256i key = _mm256_set1_epi32(int(round_key));
    const __m256i limit = _mm256_set1_epi32(int(exp_neg_lambda));
    for (uint k = 0u; k < n; k += 8u) {
        const __m256i valid = _mm256_cmpgt_epi32(_mm256_set1_epi32(int(n - k)), lane);
        const auto* at = reinterpret_cast<const long long*>(corners + k);
        const __m256i a = _mm256_permutevar8x32_epi32(
            _mm256_maskload_epi64(at, _mm256_cvtepi32_epi64(_mm256_castsi256_si128(valid))), split);
        const __m256i b = _mm256_permutevar8x32_epi32(
            _mm256_maskload_epi64(at + 4, _mm256_cvtepi32_epi64(_mm256_extracti128_si256(valid, 1))), split);
        const __m256i x = _mm256_permute2x128_si256(a, b, 0x20), y = _mm256_permute2x128_si256(a, b, 0x31);
        const __m256i stream = hash_mix_x8(hash_mix_x8(key, x), y);
        __m256i product = _mm256_set1_epi32(-1);
        __m256i count = _mm256_setzero_si256();
        __m256i live = valid;
        for (uint step = 0u; !_mm256_testz_si256(live, live); step++) {
            const __m256i u = hash_mix_x8(stream, _mm256_set1_epi32(int(0xA5A5A5A5u + step)));
            const __m256i even = _mm256_srli_epi64(_mm256_mul_epu32(product, u), 32);
            const __m256i odd = _mm256_mul_epu32(_mm256_srli_epi64(product, 32), _mm256_srli_epi64(u, 32));
            product = _mm256_blend_epi32(even, odd, 0xAA);
            live = _mm256_andnot_si256(_mm256_cmpeq_epi32(_mm256_min_epu32(product, limit), product), live);
            count = _mm256_sub_epi32(count, live);  // a live lane is -1: one more dart
        }
        _mm256_maskstore_epi32(reinterpret_cast<int*>(counts + k), valid, count);
    }
}
#endif

// The host's dart counts of n cells: counts[k] = dart_count(cell_stream(round_key, corners[k]),
// exp_neg_lambda).
inline void cell_dart_counts(uint round_key, const uvec2* corners, uint n, uint exp_neg_lambda, uint* counts) {
#ifdef VRPD_HOST_AVX2
    if (host_has_avx2()) return cell_dart_counts_avx2(round_key, corners, n, exp_neg_lambda, counts);
#endif
    for (uint k = 0u; k < n; k++) counts[k] = dart_count(cell_stream(round_key, corners[k]), exp_neg_lambda);
}
#endif

// Dart j of a cell: .xy its lattice position (uniform over the cell's side x side points, side a
// power of two), .z its arrival key. Ties in the key are broken by the dart's index in the round.
VRPD_FN uvec4 make_dart(uint stream, uint j, uvec2 corner, uint side) {
    uint mask = side - 1u;
    uint x = corner.x + (hash_mix(stream, 3u * j) & mask);
    uint y = corner.y + (hash_mix(stream, 3u * j + 1u) & mask);
    uint key = hash_mix(stream, 3u * j + 2u);
    return uvec4(x, y, key, 0u);
}

// Arrival order: dart (key_a, index_a) arrives before (key_b, index_b).
VRPD_FN bool arrives_before(uint key_a, uint index_a, uint key_b, uint index_b) {
    return key_a < key_b || (key_a == key_b && index_a < index_b);
}

// Storage of a round's darts (kernels.h reads and writes them as uvec4 (x, y, key, state)): in
// blocks of 16, 16 records of three words (x, y, key), then one word of their 2-bit states, 12.25
// bytes a dart. States only change from undecided (0) to final, so they are set by an atomic or.
const uint DART_BLOCK_WORDS = 49u;
VRPD_FN uint dart_record(uint j) { return (j >> 4u) * DART_BLOCK_WORDS + (j & 15u) * 3u; }
VRPD_FN uint dart_state_word(uint j) { return (j >> 4u) * DART_BLOCK_WORDS + 48u; }
VRPD_FN uint dart_state_shift(uint j) { return (j & 15u) * 2u; }
// Words that hold n darts (n < 2^30, so indices stay below 2^32).
VRPD_FN uint64_t dart_words(uint64_t n) { return (n + 15u) / 16u * uint64_t(DART_BLOCK_WORDS); }

// Dart states (the .w of a dart record).
const uint DART_UNDECIDED = 0u;
const uint DART_ACCEPTED = 1u;
const uint DART_REJECTED = 2u;
// Two radii: the dart's T test went past its bounds (t_membership.h); the run fails with an error.
const uint DART_TOO_COMPLEX = 3u;

// Is dart j (`other`, state in .w) one that dart d (arrival key `key`) must reckon with: another
// dart, not rejected, arriving before d?
VRPD_FN bool live_before(uvec4 other, uint j, uint key, uint d) {
    return j != d && other.w != DART_REJECTED && arrives_before(other.z, j, key, d);
}

VRPD_END
#endif
