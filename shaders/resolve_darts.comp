#version 460
#extension GL_GOOGLE_include_directive : require
// A resolution pass (resolve_pass.glsl) for one radius: the two-radii code is left out (shared/domain.h).
#define VRPD_ONE_RADIUS
#include "resolve_pass.glsl"
