#version 460
#extension GL_GOOGLE_include_directive : require
// Throws mask mode's darts (throw_masked_pass.glsl) while the grid holds no sample: a run's first
// round, whose darts need no scan of the grid.
#define VRPD_NO_SAMPLES
#include "throw_masked_pass.glsl"
