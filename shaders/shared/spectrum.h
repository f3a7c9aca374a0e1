// The periodogram kernel's arguments and its exact phase, one definition for GLSL and C++.
#ifndef VRPD_SPECTRUM_H
#define VRPD_SPECTRUM_H
#include "bridge.h"

#ifndef __cplusplus
layout(buffer_reference, std430, buffer_reference_align = 8) buffer FixedPoints { uvec2 point[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Floats { float value[]; };
#endif

VRPD_BEGIN

// Frequencies summed by one invocation of the kernel (spectrum.comp's RUN).
const uint SPECTRUM_RUN = 8u;

// The frequencies of one half plane (ky > 0, or ky = 0 and kx > 0), numbered f = 0.. in the order
// of the full (2 half_width + 1)^2 grid after its centre; P(-k) = P(k) gives the other half.
struct SpectrumArgs {
    VRPD_BUFFER(FixedPoints) points;  // each coordinate as a 32-bit fraction of its side
    VRPD_BUFFER(Floats) power;        // P at each frequency f of the half plane
    uint count;                       // points
    uint half_width;                  // frequencies in [-half_width, half_width]^2
    uint frequencies;                 // ((2 half_width + 1)^2 - 1) / 2
    uint pad;
};
#ifdef __cplusplus
static_assert(sizeof(SpectrumArgs) == 32 && offsetof(SpectrumArgs, count) == 16);
#endif

// Frequency f of the half plane, as (kx, ky).
VRPD_FN ivec2 spectrum_frequency(uint half_width, uint f) {
    uint w = 2u * half_width + 1u;
    uint l = (w * w - 1u) / 2u + 1u + f;
    return ivec2(int(l % w) - int(half_width), int(l / w) - int(half_width));
}

// k . x in turns as a 32-bit fraction: exact, since integer products wrap modulo 2^32.
VRPD_FN uint spectrum_phase(ivec2 k, uvec2 fixed_point) {
    return uint(k.x) * fixed_point.x + uint(k.y) * fixed_point.y;
}

VRPD_END
#endif
