#version 430 core
// L1 real spherical harmonics in the annotations' order and signs (docs/MODEL.md
// "Notation and storage"). One colour channel is one vec4 (c0, c1, c2, c3).
// Also the L2 option (docs/MODEL.md "L2 option"): 9 coefficients held as three vec4
// (struct ShL2), and the order-generic names ShVec, shv_eval, shv_cosine_lobe selected by
// SH_ORDER (1 or 2; a shader that wants L2 defines SH_ORDER before including this file).
// Every number comes from generated/constants.glsl; include this file (not the constants
// file) so the constants are defined once per program.
#ifndef SH_GLSL
#define SH_GLSL 1

#ifndef SH_ORDER
#define SH_ORDER 1
#endif

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

// ---- L2: coefficients 0..3 in g0 (exactly the L1 vector), 4..7 in g1, 8 in g2.x
// (g2.yzw stay 0). Each group is one RGBA texel of the grid's storage.
struct ShL2 {
    vec4 g0;
    vec4 g1;
    vec4 g2;
};

// Y(ω) up to band 2: band 2 = (c2·xy, −c2·yz, c3·(3z² − 1), −c2·xz, c4·(x² − y²)).
ShL2 sh2_eval(vec3 dir) {
    return ShL2(sh_eval(dir),
                vec4(SH_L2_C2 * dir.x * dir.y, -SH_L2_C2 * dir.y * dir.z,
                     SH_L2_C3 * (3.0 * dir.z * dir.z - 1.0), -SH_L2_C2 * dir.x * dir.z),
                vec4(SH_L2_C4 * (dir.x * dir.x - dir.y * dir.y), 0.0, 0.0, 0.0));
}

// L2 projection of clamp+(<n, ω>): the L1 lobe, then π/4 times band 2 of Y(n).
ShL2 sh2_cosine_lobe(vec3 n) {
    return ShL2(sh_cosine_lobe(n),
                vec4(SH_L2_LOBE_C2 * n.x * n.y, -SH_L2_LOBE_C2 * n.y * n.z,
                     SH_L2_LOBE_C3 * (3.0 * n.z * n.z - 1.0), -SH_L2_LOBE_C2 * n.x * n.z),
                vec4(SH_L2_LOBE_C4 * (n.x * n.x - n.y * n.y), 0.0, 0.0, 0.0));
}

// Band 1 and 2 integrate to zero: the flux is still 2·sqrt(pi)·f0.
float sh_flux(ShL2 f) {
    return SH_FLUX_FACTOR * f.g0.x;
}

// Order-generic arithmetic (the vec4 versions are the plain vector operations).
float sh_dot(vec4 a, vec4 b) { return dot(a, b); }
float sh_dot(ShL2 a, ShL2 b) { return dot(a.g0, b.g0) + dot(a.g1, b.g1) + dot(a.g2, b.g2); }
vec4 sh_scale(vec4 a, float s) { return a * s; }
ShL2 sh_scale(ShL2 a, float s) { return ShL2(a.g0 * s, a.g1 * s, a.g2 * s); }
vec4 sh_divide(vec4 a, float s) { return a / s; }
ShL2 sh_divide(ShL2 a, float s) { return ShL2(a.g0 / s, a.g1 / s, a.g2 / s); }
vec4 sh_add(vec4 a, vec4 b) { return a + b; }
ShL2 sh_add(ShL2 a, ShL2 b) { return ShL2(a.g0 + b.g0, a.g1 + b.g1, a.g2 + b.g2); }
// Group k (0-based) of a vector: the RGBA texel it is stored in.
vec4 sh_group(vec4 f, int k) { return f; }
vec4 sh_group(ShL2 f, int k) { return k == 0 ? f.g0 : (k == 1 ? f.g1 : f.g2); }

#if SH_ORDER == 1
#define ShVec vec4
#define SH_GROUPS 1
#define shv_eval sh_eval
#define shv_cosine_lobe sh_cosine_lobe
#define SHV_ZERO vec4(0.0)
#elif SH_ORDER == 2
#define ShVec ShL2
#define SH_GROUPS 3
#define shv_eval sh2_eval
#define shv_cosine_lobe sh2_cosine_lobe
#define SHV_ZERO ShL2(vec4(0.0), vec4(0.0), vec4(0.0))
#else
#error SH_ORDER must be 1 or 2
#endif

#endif
