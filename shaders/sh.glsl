#version 430 core
// L1 real spherical harmonics in the annotations' order and signs (docs/MODEL.md
// "Notation and storage"). One colour channel is one vec4 (c0, c1, c2, c3).
// Every number comes from generated/constants.glsl; include this file (not the constants
// file) so the constants are defined once per program.
#ifndef SH_GLSL
#define SH_GLSL 1

#include "generated/constants.glsl"

// Basis functions at the unit direction `dir`: Y(ω) = (c0, −c1·ω.y, c1·ω.z, −c1·ω.x).
// Evaluating a stored function f at `dir` is dot(f, sh_eval(dir)).
vec4 sh_eval(vec3 dir) {
    return vec4(SH_C0, -SH_C1 * dir.y, SH_C1 * dir.z, -SH_C1 * dir.x);
}

// SH projection of the clamped cosine lobe clamp+(<n, ω>) around the unit normal `n`.
vec4 sh_cosine_lobe(vec3 n) {
    return vec4(SH_COSLOBE_C0, -SH_COSLOBE_C1 * n.y, SH_COSLOBE_C1 * n.z,
                -SH_COSLOBE_C1 * n.x);
}

// Flux [W] held by an intensity SH vector: the integral of f over the sphere, 2·sqrt(pi)·f0
// (band 1 integrates to zero).
float sh_flux(vec4 f) {
    return SH_FLUX_FACTOR * f.x;
}

#endif
