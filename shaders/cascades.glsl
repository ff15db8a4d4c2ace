#version 430 core
// Cascaded LPV in the final gather (docs/MODEL.md "Cascades"); explorer/lpv/cascades.py
// holds the same weights in numpy (blend_weights) and sets these uniforms
// (cascade_uniforms). Every cascade has u_grid_cells cells along x, y, z. Light vectors
// are ShVec: L1, or L2 with the texel layout of sh_grid.glsl (SH_ORDER of the includer).
#ifndef CASCADES_GLSL
#define CASCADES_GLSL 1

#include "sh.glsl"
#include "grid.glsl"
#include "sh_grid.glsl"

#define MAX_CASCADES 4

uniform int u_cascade_count;
uniform vec3 u_cascade_origin[MAX_CASCADES];
uniform float u_cascade_cell_size[MAX_CASCADES];
uniform float u_cascade_edge;    // outer shell with weight 0 [cells]
uniform float u_cascade_band;    // width of the smoothstep ramp inside it [cells]
uniform sampler3D u_cascade_r[MAX_CASCADES];
uniform sampler3D u_cascade_g[MAX_CASCADES];
uniform sampler3D u_cascade_b[MAX_CASCADES];

// w_k: 0 in the outer u_cascade_edge cells of cascade k (and outside it), a smoothstep
// over the next u_cascade_band cells, 1 further inside; d = distance to the nearest face.
float cascade_own_weight(int k, vec3 world) {
    vec3 g = (world - u_cascade_origin[k]) / u_cascade_cell_size[k];
    vec3 to_face = min(g, vec3(u_grid_cells) - g);
    float depth = min(min(to_face.x, to_face.y), to_face.z);
    float t = clamp((depth - u_cascade_edge) / u_cascade_band, 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Irradiance <s_k, lobe(-n)>/c_k² (clamped at 0) of cascade k at `world` (MODEL.md
// "Final gather", with cascade k's cell size); `per_area` false leaves out the 1/c_k² (the
// DX11 gather, which reads an intensity: irradiance_gather off).
vec3 cascade_irradiance_of(int k, vec3 world, ShVec lobe, bool per_area) {
    vec3 g = (world - u_cascade_origin[k]) / u_cascade_cell_size[k];
    vec3 intensity = vec3(sh_dot(sh_sample_cells(u_cascade_r[k], g), lobe),
                          sh_dot(sh_sample_cells(u_cascade_g[k], g), lobe),
                          sh_dot(sh_sample_cells(u_cascade_b[k], g), lobe));
    float cell = u_cascade_cell_size[k];
    return max(intensity, vec3(0.0)) / (per_area ? cell * cell : 1.0);
}

// Directional-derivative damping factor (docs/MODEL.md "Final gather") from the irradiance
// half a cell in front of and behind the surface: clamp(front/back, 0, 1) per channel, 1
// where nothing arrives from behind. Shared by the single grid and the cascades.
vec3 damping_ratio(vec3 front, vec3 back) {
    vec3 ratio = vec3(1.0);
    for (int c = 0; c < 3; ++c) {
        if (back[c] > 0.0) {
            ratio[c] = clamp(front[c] / back[c], 0.0, 1.0);
        }
    }
    return ratio;
}

// One cascade's irradiance, damped over half of that cascade's cell when asked.
vec3 cascade_damped_irradiance_of(int k, vec3 world, vec3 n, ShVec lobe, bool damping,
                                  bool per_area) {
    vec3 irradiance = cascade_irradiance_of(k, world, lobe, per_area);
    if (!damping) {
        return irradiance;
    }
    vec3 half_cell = 0.5 * u_cascade_cell_size[k] * n;
    return irradiance * damping_ratio(
        cascade_irradiance_of(k, world + half_cell, lobe, per_area),
        cascade_irradiance_of(k, world - half_cell, lobe, per_area));
}

// Blended lookup Σ_k W_k·clamp+(<s_k, kernel>)/c_k² (damped along n when asked): finest
// first, W_k = w_k·Π_{j<k}(1 − w_j), the coarsest takes the rest Π_{j<K−1}(1 − w_j), so
// Σ W_k = 1 (a partition of unity: a VPL injected into several cascades is counted once).
// Cascades with W_k = 0 are not sampled. With the cosine lobe around −n as the kernel it is
// the irradiance; with Y(ω) filtered by a lobe's SH factors, the radiance arriving from a
// lobe around −ω (docs/MODEL.md "Fog", "Glossy reflections").
vec3 cascade_blend(vec3 world, ShVec lobe, vec3 n, bool damping, bool per_area) {
    vec3 irradiance = vec3(0.0);
    float remaining = 1.0;
    for (int k = 0; k < u_cascade_count && k < MAX_CASCADES; ++k) {
        float w = k == u_cascade_count - 1 ? 1.0 : cascade_own_weight(k, world);
        float weight = w * remaining;
        if (weight > 0.0) {
            irradiance += weight * cascade_damped_irradiance_of(k, world, n, lobe, damping,
                                                                per_area);
        }
        remaining *= 1.0 - w;
        if (remaining <= 0.0) break;
    }
    return irradiance;
}

// The gather's blended irradiance; `model` false: the DX11 gather, <s_k, Y(-n)> with no
// 1/c_k² (irradiance_gather off, docs/MODEL.md "Final gather").
vec3 cascade_irradiance(vec3 world, vec3 n, bool damping, bool model) {
    return cascade_blend(world, model ? shv_cosine_lobe(-n) : shv_eval(-n), n, damping, model);
}

vec3 cascade_radiance(vec3 world, ShVec kernel) {
    return cascade_blend(world, kernel, vec3(0.0), false, true);
}

#endif
