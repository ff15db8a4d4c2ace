#version 430 core
// The LPV's radiance through a lobe, at any point (docs/MODEL.md "Fog", "Glossy
// reflections"): the fog's in-scattering of the propagated light and the glossy march
// both ask "how much light travels in direction ω here, weighted by a lobe around ω?".
// The grid stores intensity per cell; like the final gather, the radiance of a cell of
// size c in direction ω is L(ω) = <s, Y(ω)> / c². A Henyey–Greenstein lobe of asymmetry g
// is zonal, so by Funk–Hecke it multiplies SH band l by g^l (derivation
// media.hg_band_factors): ∫ p_g(<ω', ω>) L(ω') dω' = <s ⊙ (g^l), Y(ω)> / c², clamped at 0
// like the irradiance. g = 0 is the mean radiance over the sphere (isotropic), g = 1 the
// plain SH evaluation. Cascades blend with the final gather's weights (cascades.glsl).
// Numpy twin: explorer/lpv/twin/media.py (lobe_radiance).
#ifndef LPV_LOBE_GLSL
#define LPV_LOBE_GLSL 1

#include "sh.glsl"
#include "cascades.glsl"

// Y(ω) with band l scaled by g^l.
ShVec lpv_lobe_kernel(vec3 omega, float g) {
#if SH_ORDER == 1
    vec4 kernel = sh_eval(omega);
    kernel.yzw *= g;
    return kernel;
#else
    ShL2 kernel = sh2_eval(omega);
    kernel.g0.yzw *= g;
    kernel.g1 *= g * g;
    kernel.g2 *= g * g;
    return kernel;
#endif
}

// Radiance travelling in direction `omega` at `world`, through an HG lobe of asymmetry g.
vec3 lpv_lobe_radiance(vec3 world, vec3 omega, float g) {
    return cascade_radiance(world, lpv_lobe_kernel(omega, g));
}

#endif
