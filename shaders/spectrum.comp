#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "shared/spectrum.h"
// The periodogram (vrpd/analysis.h): one frequency of the half plane per invocation, an exact sum
// over all points. The points pass through shared memory a tile at a time, read once per
// workgroup with coalesced loads.
const uint TILE = 64u;
layout(local_size_x = 64) in;
layout(push_constant) uniform Push { SpectrumArgs a; };
shared uvec2 tile[TILE];

// cos and sin of 2 pi phase / 2^32. The quarter turn is taken from the phase's integer bits, the
// rest (at most an eighth of a turn) by Taylor polynomials whose truncation error is below 2e-10,
// so the result is as good on every device, whatever its built-in sin and cos.
vec2 turn(uint phase) {
    uint quarter = (phase + 0x20000000u) >> 30;
    float x = float(int(phase - (quarter << 30))) * (6.28318530717958647692 / 4294967296.0);
    float x2 = x * x;
    float s = x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0))));
    float c = 1.0 - x2 / 2.0 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0 * (1.0 - x2 / 56.0 * (1.0 - x2 / 90.0))));
    if (quarter == 1u) return vec2(-s, c);
    if (quarter == 2u) return vec2(-c, -s);
    if (quarter == 3u) return vec2(s, -c);
    return vec2(c, s);
}

void main() {
    uint f = gl_GlobalInvocationID.x;
    ivec2 k = spectrum_frequency(a.half_width, min(f, a.frequencies - 1u));
    vec2 sum = vec2(0.0);
    for (uint first = 0u; first < a.count; first += TILE) {
        uint i = first + gl_LocalInvocationID.x;
        if (i < a.count) tile[gl_LocalInvocationID.x] = a.points.point[i];
        barrier();
        // Partial sums per tile keep the float error near that of a sum of TILE terms.
        vec2 part = vec2(0.0);
        uint n = min(TILE, a.count - first);
        for (uint j = 0u; j < n; j++) part += turn(spectrum_phase(k, tile[j]));
        sum += part;
        barrier();
    }
    if (f < a.frequencies) a.power.value[f] = dot(sum, sum) / float(a.count);
}
