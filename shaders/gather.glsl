#version 430 core
// Final gather + direct light (docs/MODEL.md "Final gather"), linear: exposure and display
// encoding are display.glsl's, so changing them re-runs no gather.
// Full-screen pass over the G-buffer. Targets:
//   0 direct radiance (shadowed Lambertian from every light view, times a spot's falloff),
//   1 indirect radiance (LPV; with glossy reflections their radiance too, glossy.glsl),
//   2 indirect irradiance × the pixel's world area = flux [W] the pixel's surface receives
//     from the LPV (summed by the energy audit).
// SH_ORDER 2 gathers an L2 grid (layout of sh_grid.glsl) with the L2 lobe. SH_SHADER_FILTER:
// the grid lookup's interpolation (sh_grid.glsl).
// GATHER_CASCADES (more than one cascade) and GATHER_DAMPING (the directional-derivative
// damping) are chosen when the program is compiled (explorer/lpv/passes/gather.py
// `program_defines`): llvmpipe runs both sides of a branch on a uniform under a lane mask,
// so as uniforms the single grid paid for the cascade blend's lookups and the undamped
// gather for the damping's two extra grid samples. GATHER_NET_FLUX (the net-flux gather,
// single grid only: Settings refuses it with cascades) likewise.
#define SH_ORDER 1
#define SH_SHADER_FILTER 0
#define GATHER_CASCADES 0
#define GATHER_DAMPING 0
#define GATHER_NET_FLUX 0

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
#include "sh.glsl"
#include "grid.glsl"
#include "sh_grid.glsl"
#include "cascades.glsl"
#include "generated/corrections.glsl"
#include "light_map.glsl"
#include "glossy.glsl"

uniform sampler2D u_gbuffer_position;
uniform sampler2D u_gbuffer_normal;
uniform sampler2D u_gbuffer_albedo;
uniform sampler3D u_lpv_r;
uniform sampler3D u_lpv_g;
uniform sampler3D u_lpv_b;
// The shadow maps of every RSM view, side by side (the RSM atlas, explorer/lpv/passes/atlas.py;
// one view: its RSM), and one record per view: light_map.glsl, light_records.glsl.

uniform int u_shadow_kernel;           // PCF box width in shadow-map texels; 1 = hard
uniform int u_has_grid;
uniform ivec2 u_target_size;          // the targets' size: the G-buffer's, or less for a
                                      // reduced preview (each pixel reads the texel below
                                      // it, as view_snapshot.glsl maps its sources)

layout(location = 0) out vec4 out_direct;
layout(location = 1) out vec4 out_indirect;
layout(location = 2) out vec4 out_received;

// Fraction of a box k = u_shadow_kernel shadow-map texels wide, centred on `world`'s
// projection into view `light`, that does not hide `world` (percentage-closer filtering,
// docs/MODEL.md "Final gather"). Each texel counts with the part of it the box covers, so
// the visibility varies continuously with the point and a shadow edge becomes a linear
// ramp k texels wide; k = 1 tests the one texel under the point (a hard, stair-stepped
// edge). The bias grows with the texel's footprint and with the slope of the surface seen
// from the light, since texels up to k/2 + 1/2 away store the depth of the same surface a
// little nearer or farther.
float shadow_visibility(int light, vec3 world, float cos_light) {
    vec2 point;    // texel i spans [i, i + 1)
    float depth, texel;
    if (!light_map_project(light, world, point, depth, texel)) {
        return 0.0;   // outside the light's frustum
    }
    float tangent = sqrt(max(1.0 - cos_light * cos_light, 0.0)) / max(cos_light, 0.1);
    int kernel = max(u_shadow_kernel, 1);
    float width = float(kernel);
    float bias = texel * (1.0 + (0.5 * width + 0.5) * tangent);
    ivec4 tile = u_lights[light].tile;
    if (kernel == 1) {
        return light_map_test(ivec2(floor(point)), tile, depth, bias);
    }
    vec2 lo = point - 0.5 * width;
    vec2 hi = point + 0.5 * width;
    ivec2 first = ivec2(floor(lo));
    float lit = 0.0;
    float total = 0.0;
    for (int j = 0; j <= kernel; ++j) {           // a box k wide touches k + 1 texels
        float y = float(first.y + j);
        float wy = max(min(y + 1.0, hi.y) - max(y, lo.y), 0.0);
        for (int i = 0; i <= kernel; ++i) {
            float x = float(first.x + i);
            float weight = wy * max(min(x + 1.0, hi.x) - max(x, lo.x), 0.0);
            if (weight > 0.0) {
                lit += weight * light_map_test(first + ivec2(i, j), tile, depth, bias);
                total += weight;
            }
        }
    }
    return lit / total;
}

// Direct irradiance at p (normal n) summed over every light's views: I·f·cos θ/r² (spot,
// f its cone's falloff at the angle from its axis), I·cos θ/r² (point light, from the one
// face whose directions hold p) or E·cos θ (directional) (light_arrival, light_records.glsl),
// each times its colour and its own shadow map's visibility: the radiometry of the RSM flux.
vec3 direct_irradiance(vec3 p, vec3 n) {
    vec3 total = vec3(0.0);
    for (int light = 0; light < u_light_count; ++light) {
        vec3 to_light;
        float irradiance = light_arrival(light, p, to_light);
        float cos_light = dot(n, to_light);
        if (irradiance > 0.0 && cos_light > 0.0) {
            total += u_lights[light].colour_texel.rgb * (irradiance * cos_light
                     * shadow_visibility(light, p, cos_light));
        }
    }
    return total;
}

// LPV irradiance for normal n at world point x: E = clamp+(<s(x), lobe(-n)>) / cell²
// (trilinear sample of the accumulated grid); with irradiance_gather off the DX11 shader's
// clamp+(<s(x), Y(-n)>), the intensity toward -n, with no cell area.
vec3 lpv_irradiance(vec3 x, vec3 n) {
    ShVec lobe = u_irradiance_gather ? shv_cosine_lobe(-n) : shv_eval(-n);  // L1 or L2
    vec3 intensity = vec3(sh_dot(sh_sample_grid(u_lpv_r, x), lobe),
                          sh_dot(sh_sample_grid(u_lpv_g, x), lobe),
                          sh_dot(sh_sample_grid(u_lpv_b, x), lobe));
    float area = u_irradiance_gather ? u_grid_cell_size * u_grid_cell_size : 1.0;
    return max(intensity, vec3(0.0)) / area;
}

// Directional-derivative damping (docs/MODEL.md "Final gather"): light that grows towards
// the back of the surface leaked through it. The central difference over one cell along n
// gives the factor clamp(E(p + h/2 n) / E(p - h/2 n), 0, 1) per channel (1 where nothing
// arrives from behind).
vec3 lpv_derivative_damping(vec3 p, vec3 n) {
    vec3 half_cell = 0.5 * u_grid_cell_size * n;
    vec3 front = lpv_irradiance(p + half_cell, n);
    vec3 back = lpv_irradiance(p - half_cell, n);
    return damping_ratio(front, back);   // cascades.glsl
}

// Net-flux gather (docs/MODEL.md "Net-flux gather"): at a surface the irradiance is
// E_in = −<n, F> + M_out (Gershun's light vector F = ∫ L ω dω, exact in band 1 of an L1 or
// L2 grid; M_out the light leaving the surface, here its own exitance a·E_direct), so light
// running along the surface counts 0 and the surface's own outgoing light, which the grid
// holds as a flux away from it, is replaced by its true value instead of being gathered.
vec3 lpv_net_flux_irradiance(vec3 x, vec3 n, vec3 exitance) {
    vec3 d = -n;   // <n, F> = -<d, F>: the kernel of <d, ω> is band 1 only
    ShVec kernel = SHV_ZERO;
#if SH_ORDER == 1
    kernel = vec4(0.0, -SH_NET_FLUX_C1 * d.y, SH_NET_FLUX_C1 * d.z, -SH_NET_FLUX_C1 * d.x);
#else
    kernel.g0 = vec4(0.0, -SH_NET_FLUX_C1 * d.y, SH_NET_FLUX_C1 * d.z,
                     -SH_NET_FLUX_C1 * d.x);
#endif
    ShVec r = sh_sample_grid(u_lpv_r, x);
    ShVec g = sh_sample_grid(u_lpv_g, x);
    ShVec b = sh_sample_grid(u_lpv_b, x);
    if (!u_irradiance_gather) {   // the DX11 intensity gather, which has no light vector
        ShVec dx11 = shv_eval(-n);  // (Settings refuses the pair; the pass can be driven)
        return max(vec3(sh_dot(r, dx11), sh_dot(g, dx11), sh_dot(b, dx11)), vec3(0.0));
    }
    vec3 net = vec3(sh_dot(r, kernel), sh_dot(g, kernel), sh_dot(b, kernel));
    return max(net / (u_grid_cell_size * u_grid_cell_size) + exitance, vec3(0.0));
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy) * textureSize(u_gbuffer_position, 0) / u_target_size;
    vec4 position = texelFetch(u_gbuffer_position, pixel, 0);
    if (position.w < 0.5) {   // background
        out_direct = out_indirect = out_received = vec4(0.0);
        return;
    }
    vec4 normal_area = texelFetch(u_gbuffer_normal, pixel, 0);
    vec3 n = normal_area.xyz;
    vec3 albedo = texelFetch(u_gbuffer_albedo, pixel, 0).rgb;

    // Direct light: the shadowed Lambertian of every light (direct_irradiance above).
    vec3 direct_e = direct_irradiance(position.xyz, n);
    vec3 direct = albedo * INV_PI * direct_e;

    // Indirect light: trilinear sample of the accumulated grid at the surface; light
    // arriving at the surface travels against n, so E = <s, lobe(-n)> / cell², clamped.
    vec3 indirect_irradiance = vec3(0.0);
    if (u_has_grid == 1) {
#if GATHER_CASCADES
        indirect_irradiance = cascade_irradiance(position.xyz, n, GATHER_DAMPING == 1,
                                                 u_irradiance_gather);
#elif GATHER_NET_FLUX
        indirect_irradiance = lpv_net_flux_irradiance(position.xyz, n, albedo * direct_e);
#if GATHER_DAMPING
        indirect_irradiance *= lpv_derivative_damping(position.xyz, n);
#endif
#elif GATHER_DAMPING
        indirect_irradiance = lpv_irradiance(position.xyz, n)
                            * lpv_derivative_damping(position.xyz, n);
#else
        indirect_irradiance = lpv_irradiance(position.xyz, n);
#endif
    }
    vec3 indirect = albedo * INV_PI * indirect_irradiance;
    if (u_has_grid == 1) {
        indirect += glossy_reflection(position.xyz, n);   // glossy.glsl (off: 0)
    }

    out_direct = vec4(direct, 1.0);
    out_indirect = vec4(indirect, 1.0);
    out_received = vec4(indirect_irradiance * normal_area.w, 0.0);
}
#endif
