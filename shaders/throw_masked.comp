#version 460
#extension GL_GOOGLE_include_directive : require
// Throws mask mode's darts (throw_masked_pass.glsl); throw_masked_empty.comp serves a grid without samples.
#include "throw_masked_pass.glsl"
