#version 460
#extension GL_GOOGLE_include_directive : require
// A resolution pass (resolve_pass.glsl) for two radii; resolve_darts.comp is the one-radius variant.
#include "resolve_pass.glsl"
