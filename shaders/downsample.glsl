#version 430 core
// RSM downsample: each output VPL stands for a block of u_factor × u_factor RSM texels.
// mode 1 "average": mean position / normal / depth of the valid texels and the SUM of
//   their flux (a VPL that replaces k texels must carry the flux of all k: flux is
//   conserved exactly).
// mode 2 "brightest" (the DX11 article's kernel): pick the texel with the largest
//   luminance(flux) + max(0, <n, -light direction>), keep the texels whose grid cell
//   lies within squared distance < 10 cells of its cell, average their position and
//   normal and SUM their flux (the article divides the flux by the count, which drops
//   the flux of all but one texel; here the kept texels' flux is conserved and the
//   flux of the rejected ones is lost, as the energy audit shows).

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
#include "grid.glsl"

uniform sampler2D u_rsm_position;
uniform sampler2D u_rsm_normal;
uniform sampler2D u_rsm_flux;
uniform int u_factor;
uniform int u_mode;
uniform vec3 u_light_direction;

layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_flux;

const vec3 LUMA = vec3(0.299, 0.587, 0.114);   // the article's luminance weights
const float NEAR_CELLS_SQUARED = 10.0;          // the article's cell proximity test

void main() {
    ivec2 size = textureSize(u_rsm_position, 0);
    ivec2 first = ivec2(gl_FragCoord.xy) * u_factor;
    ivec2 last = min(first + ivec2(u_factor), size);

    vec3 brightest_cell = vec3(0.0);
    if (u_mode == 2) {
        float best = -1.0;
        for (int y = first.y; y < last.y; ++y) {
            for (int x = first.x; x < last.x; ++x) {
                vec4 position = texelFetch(u_rsm_position, ivec2(x, y), 0);
                if (position.w < 0.5) continue;
                vec3 normal = texelFetch(u_rsm_normal, ivec2(x, y), 0).xyz;
                vec3 flux = texelFetch(u_rsm_flux, ivec2(x, y), 0).rgb;
                float score = dot(flux, LUMA) + max(0.0, dot(normal, -u_light_direction));
                if (score > best) {
                    best = score;
                    brightest_cell = vec3(grid_cell(position.xyz));
                }
            }
        }
    }

    vec3 position_sum = vec3(0.0), normal_sum = vec3(0.0), flux_sum = vec3(0.0);
    vec3 first_normal = vec3(0.0);
    float depth_sum = 0.0, count = 0.0;
    for (int y = first.y; y < last.y; ++y) {
        for (int x = first.x; x < last.x; ++x) {
            vec4 position = texelFetch(u_rsm_position, ivec2(x, y), 0);
            if (position.w < 0.5) continue;
            if (u_mode == 2) {
                vec3 delta = vec3(grid_cell(position.xyz)) - brightest_cell;
                if (dot(delta, delta) >= NEAR_CELLS_SQUARED) continue;
            }
            vec4 normal = texelFetch(u_rsm_normal, ivec2(x, y), 0);
            if (count == 0.0) first_normal = normal.xyz;
            position_sum += position.xyz;
            normal_sum += normal.xyz;
            depth_sum += normal.w;
            flux_sum += texelFetch(u_rsm_flux, ivec2(x, y), 0).rgb;
            count += 1.0;
        }
    }
    if (count == 0.0) {
        out_position = vec4(0.0);
        out_normal = vec4(0.0);
        out_flux = vec4(0.0);
        return;
    }
    // opposite normals can cancel; then keep one of them rather than divide by zero
    float length_sum = length(normal_sum);
    vec3 normal = length_sum > 1e-6 * count ? normal_sum / length_sum : first_normal;
    out_position = vec4(position_sum / count, 1.0);
    out_normal = vec4(normal, depth_sum / count);
    out_flux = vec4(flux_sum, 0.0);
}
#endif
