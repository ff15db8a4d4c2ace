#version 430 core
// Approximate glossy reflection of the LPV's light (docs/MODEL.md "Glossy reflections"),
// included by the final gather. At a surface point p with normal n seen along the view
// direction v, the reflected direction is r = v − 2<v, n>n; the light that a mirror would
// show arrives from r, travelling along −r. The grid is sampled at M points
// x_j = p + (j + ½)·c·r (c the finest cell), each through a Henyey–Greenstein lobe of
// asymmetry g = 1 − roughness around −r (lpv_lobe.glsl), and the glossy radiance is
//     L_glossy = k_s · (1/M) Σ_j clamp+(<s(x_j) ⊙ (g^l), Y(−r)>)/c²
// added to the diffuse indirect radiance. Nothing occludes the march (only the geometry
// volume, during the propagation, did), and the lobe cannot be narrower than the grid's
// SH order allows. Numpy twin: explorer/lpv/twin/media.py (glossy).
#ifndef GLOSSY_GLSL
#define GLOSSY_GLSL 1

#include "lpv_lobe.glsl"

uniform int u_glossy;                 // 0: no glossy term
uniform float u_glossy_g;             // 1 − roughness
uniform float u_glossy_strength;      // k_s
uniform int u_glossy_samples;         // M
uniform vec3 u_camera_position;

vec3 glossy_reflection(vec3 p, vec3 n) {
    if (u_glossy == 0) {
        return vec3(0.0);
    }
    vec3 r = reflect(normalize(p - u_camera_position), n);
    float step = u_cascade_cell_size[0];
    vec3 sum = vec3(0.0);
    for (int j = 0; j < u_glossy_samples; ++j) {
        sum += lpv_lobe_radiance(p + (float(j) + 0.5) * step * r, -r, u_glossy_g);
    }
    return u_glossy_strength * sum / float(max(u_glossy_samples, 1));
}

#endif
