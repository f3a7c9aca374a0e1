#version 460
#extension GL_GOOGLE_include_directive : require
// Refinement of the active cells (refine_pass.glsl) for two radii; refine_cells.comp is the one-radius variant.
#include "refine_pass.glsl"
