#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/kernels.h"
#include "shared/spectrum.h"
// The periodogram (vrpd/analysis.h): a run of frequencies of the half plane per invocation, an
// exact sum over all points.
const uint BLOCK = 64u;
const uint RUN = 8u;  // frequencies per invocation (shared/spectrum.h: SPECTRUM_RUN)
layout(local_size_x = 64) in;
layout(push_constant) uniform Push { SpectrumArgs a; };

// cos and sin of 2 pi phase / 2^32. The quarter turn is taken from the phase's integer bits, the
// rest (at most an eighth of a turn) by Taylor polynomials whose truncation error is below 2e-10,
// so the result is as good on every device, whatever its built-in sin and cos.
vec2 turn(uint phase) {
    uint quarter = (phase + 0x20000000u) >> 30;
    float x = float(int(phase - (quarter << 30))) * (6.28318530717958647692 / 4294967296.0);
    float x2 = x * x;
    // Horner's form with the reciprocals as constants: a division costs many multiplications.
    float s = x * (1.0 - x2 * (1.0 / 6.0) * (1.0 - x2 * (1.0 / 20.0) * (1.0 - x2 * (1.0 / 42.0) *
                                                                           (1.0 - x2 * (1.0 / 72.0)))));
    float c = 1.0 - x2 * 0.5 * (1.0 - x2 * (1.0 / 12.0) * (1.0 - x2 * (1.0 / 30.0) *
                                                             (1.0 - x2 * (1.0 / 56.0) * (1.0 - x2 * (1.0 / 90.0)))));
    if (quarter == 1u) return vec2(-s, c);
    if (quarter == 2u) return vec2(-c, -s);
    if (quarter == 3u) return vec2(s, -c);
    return vec2(c, s);
}

void main() {
    // Each invocation sums RUN consecutive frequencies of the half plane; along a row, k + (1, 0)
    // is k's phasor turned once more by the point's x phasor: a complex product instead of a sine
    // and a cosine. Every invocation reads the same point at once (a broadcast load, no barrier).
    uint f0 = work_item() * RUN;
    ivec2 k[RUN];
    bool along[RUN];
    for (uint q = 0u; q < RUN; q++) {
        k[q] = spectrum_frequency(a.half_width, min(f0 + q, a.frequencies - 1u));
        along[q] = q > 0u && k[q] == k[q - 1u] + ivec2(1, 0);
    }
    vec2 sum[RUN];
    for (uint q = 0u; q < RUN; q++) sum[q] = vec2(0.0);
    for (uint first = 0u; first < a.count; first += BLOCK) {
        // Partial sums per block keep the float error near that of a sum of BLOCK terms.
        vec2 part[RUN];
        for (uint q = 0u; q < RUN; q++) part[q] = vec2(0.0);
        uint end = min(a.count, first + BLOCK);
        for (uint j = first; j < end; j++) {
            uvec2 u = a.points.point[j];
            vec2 e = turn(spectrum_phase(k[0], u));
            vec2 s = turn(u.x);
            part[0] += e;
            for (uint q = 1u; q < RUN; q++) {
                if (along[q])
                    e = vec2(e.x * s.x - e.y * s.y, e.x * s.y + e.y * s.x);
                else
                    e = turn(spectrum_phase(k[q], u));
                part[q] += e;
            }
        }
        for (uint q = 0u; q < RUN; q++) sum[q] += part[q];
    }
    for (uint q = 0u; q < RUN; q++)
        if (f0 + q < a.frequencies) a.power.value[f0 + q] = dot(sum[q], sum[q]) / float(a.count);
}
