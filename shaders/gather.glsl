#version 430 core
// Final gather + direct light (docs/MODEL.md "Final gather"), linear: exposure and display
// encoding are display.glsl's, so changing them re-runs no gather.
// Full-screen pass over the G-buffer. Targets:
//   0 direct radiance (shadowed Lambertian from the light, times the spot cone's falloff),
//   1 indirect radiance (LPV; with glossy reflections their radiance too, glossy.glsl),
//   2 indirect irradiance × the pixel's world area = flux [W] the pixel's surface receives
//     from the LPV (summed by the energy audit).
// SH_ORDER 2 gathers an L2 grid (layout of sh_grid.glsl) with the L2 lobe. SH_SHADER_FILTER:
// the grid lookup's interpolation (sh_grid.glsl).
#define SH_ORDER 1
#define SH_SHADER_FILTER 0

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
#include "sh.glsl"
#include "grid.glsl"
#include "sh_grid.glsl"
#include "cascades.glsl"
#include "spot.glsl"
#include "glossy.glsl"

uniform sampler2D u_gbuffer_position;
uniform sampler2D u_gbuffer_normal;
uniform sampler2D u_gbuffer_albedo;
uniform sampler3D u_lpv_r;
uniform sampler3D u_lpv_g;
uniform sampler3D u_lpv_b;
uniform sampler2D u_shadow_position;   // RSM position (w = 1 where the light saw a surface)
uniform sampler2D u_shadow_normal;     // RSM normal (w = view depth from the light)

uniform mat4 u_light_view;
uniform mat4 u_light_projection;
uniform int u_orthographic;
uniform vec3 u_light_position;
uniform vec3 u_light_direction;
uniform float u_light_intensity;       // spot: Φ_L/(4π)
uniform float u_light_irradiance;      // directional: E
uniform float u_shadow_texel;          // texel edge at depth 1 (spot) or in world units
uniform int u_shadow_kernel;           // PCF box width in shadow-map texels; 1 = hard
uniform int u_has_grid;

layout(location = 0) out vec4 out_direct;
layout(location = 1) out vec4 out_indirect;
layout(location = 2) out vec4 out_received;

// 1 where shadow-map texel `at` (clamped to the map) does not hide a point at light-view
// depth `depth`, else 0.
float shadow_test(ivec2 at, ivec2 size, float depth, float bias) {
    at = clamp(at, ivec2(0), size - 1);
    bool seen = texelFetch(u_shadow_position, at, 0).w > 0.5;
    float stored = texelFetch(u_shadow_normal, at, 0).w;
    return (!seen || depth <= stored + bias) ? 1.0 : 0.0;
}

// Fraction of a box k = u_shadow_kernel shadow-map texels wide, centred on `world`'s
// projection, that does not hide `world` (percentage-closer filtering, docs/MODEL.md
// "Final gather"). Each texel counts with the part of it the box covers, so the
// visibility varies continuously with the point and a shadow edge becomes a linear ramp k
// texels wide; k = 1 tests the one texel under the point (a hard, stair-stepped edge).
// The bias grows with the texel's footprint and with the slope of the surface seen from
// the light, since texels up to k/2 + 1/2 away store the depth of the same surface a
// little nearer or farther.
float shadow_visibility(vec3 world, float cos_light) {
    vec4 view_position = u_light_view * vec4(world, 1.0);
    vec4 clip = u_light_projection * view_position;
    if (clip.w <= 0.0) return 0.0;
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) return 0.0;   // outside the light's frustum
    float depth = -view_position.z;
    float texel = u_orthographic == 1 ? u_shadow_texel : u_shadow_texel * depth;
    float tangent = sqrt(max(1.0 - cos_light * cos_light, 0.0)) / max(cos_light, 0.1);
    int kernel = max(u_shadow_kernel, 1);
    float width = float(kernel);
    float bias = texel * (1.0 + (0.5 * width + 0.5) * tangent);
    ivec2 size = textureSize(u_shadow_normal, 0);
    vec2 point = (ndc.xy * 0.5 + 0.5) * vec2(size);   // texel i spans [i, i + 1)
    if (kernel == 1) {
        return shadow_test(ivec2(floor(point)), size, depth, bias);
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
                lit += weight * shadow_test(first + ivec2(i, j), size, depth, bias);
                total += weight;
            }
        }
    }
    return lit / total;
}

// LPV irradiance for normal n at world point x: E = clamp+(<s(x), lobe(-n)>) / cell²
// (trilinear sample of the accumulated grid).
vec3 lpv_irradiance(vec3 x, vec3 n) {
    ShVec lobe = shv_cosine_lobe(-n);   // L1 or L2 after SH_ORDER
    vec3 intensity = vec3(sh_dot(sh_sample_grid(u_lpv_r, x), lobe),
                          sh_dot(sh_sample_grid(u_lpv_g, x), lobe),
                          sh_dot(sh_sample_grid(u_lpv_b, x), lobe));
    return max(intensity, vec3(0.0)) / (u_grid_cell_size * u_grid_cell_size);
}

// Directional-derivative damping (docs/MODEL.md "Final gather"): light that grows towards
// the back of the surface leaked through it. The central difference over one cell along n
// gives the factor clamp(E(p + h/2 n) / E(p - h/2 n), 0, 1) per channel (1 where nothing
// arrives from behind).
uniform int u_gather_damping;

vec3 lpv_derivative_damping(vec3 p, vec3 n) {
    if (u_gather_damping == 0) {
        return vec3(1.0);
    }
    vec3 half_cell = 0.5 * u_grid_cell_size * n;
    vec3 front = lpv_irradiance(p + half_cell, n);
    vec3 back = lpv_irradiance(p - half_cell, n);
    return damping_ratio(front, back);   // cascades.glsl
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(u_gbuffer_position, pixel, 0);
    if (position.w < 0.5) {   // background
        out_direct = out_indirect = out_received = vec4(0.0);
        return;
    }
    vec4 normal_area = texelFetch(u_gbuffer_normal, pixel, 0);
    vec3 n = normal_area.xyz;
    vec3 albedo = texelFetch(u_gbuffer_albedo, pixel, 0).rgb;

    // Direct light: irradiance I·f·cos θ/r² (spot, f the cone's falloff at the angle from
    // its axis) or E·cos θ (directional), the same radiometry as the RSM flux, times the
    // shadow map's visibility.
    vec3 to_light;
    float irradiance;
    if (u_orthographic == 1) {
        to_light = -u_light_direction;
        irradiance = u_light_irradiance;
    } else {
        vec3 offset = u_light_position - position.xyz;
        float distance_squared = max(dot(offset, offset), 1e-12);
        to_light = offset * inversesqrt(distance_squared);
        irradiance = u_light_intensity / distance_squared
                   * spot_falloff(dot(-to_light, u_light_direction));
    }
    float cos_light = dot(n, to_light);
    vec3 direct = vec3(0.0);
    if (cos_light > 0.0) {
        direct = albedo * INV_PI * irradiance * cos_light
               * shadow_visibility(position.xyz, cos_light);
    }

    // Indirect light: trilinear sample of the accumulated grid at the surface; light
    // arriving at the surface travels against n, so E = <s, lobe(-n)> / cell², clamped.
    vec3 indirect_irradiance = vec3(0.0);
    if (u_has_grid == 1 && u_cascade_count > 1) {
        indirect_irradiance = cascade_irradiance(position.xyz, n, u_gather_damping == 1);
    } else if (u_has_grid == 1) {
        indirect_irradiance = lpv_irradiance(position.xyz, n)
                            * lpv_derivative_damping(position.xyz, n);
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
