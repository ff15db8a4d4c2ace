#version 430 core
// Fog: single scattering in a homogeneous medium that fills the scene's box, ray-marched
// per pixel (docs/MODEL.md "Fog"). The view ray from the eye through the pixel runs to the
// surface the G-buffer shows (or out of the box); its part inside the box, [t0, t1] of
// length ℓ, is split into u_fog_steps equal segments [a, b] sampled at their midpoints x:
//     transmittance   T = exp(−σ_t·ℓ)                      (to the surface, from t0)
//     in-scattered    Σ α·(T(a) − T(b))·L_p(x)              (exact for L_p constant on [a, b])
// with T(s) = exp(−σ_t·(s − t0)), α the single-scattering albedo and L_p the radiance the
// phase function p scatters towards the eye (ω_o = −ray direction):
//     LPV     L_p = clamp+(<s(x) ⊙ a, Y(ω_o)>)/c²        (lpv_lobe.glsl; a_l = g^l for HG,
//                                                        band 0 only when isotropic)
//     direct  L_p = Σ_v κ_v·p(<ω_v, ω_o>)·E⊥_v(x)·V_v(x)  (over every RSM view v, as the
//             gather's direct light: ω_v its light's direction of travel, E⊥ = I·f/r²
//             (spot), I/r² (the point light's face that holds x) or E (directional), κ_v
//             its colour, V_v its own shadow map's test in its tile of the RSM atlas)
// Targets: 0 = (direct in-scattering rgb, T), 1 = (LPV in-scattering rgb, 0). The display
// composes T·surface + in-scattering (display.glsl). Neither the light on its way to the
// medium or the surfaces nor the propagation is attenuated by the medium.
// Numpy twin: explorer/lpv/twin/media.py (march_fog).
#define SH_ORDER 1
#define SH_SHADER_FILTER 0

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
#include "sh.glsl"
#include "lpv_lobe.glsl"
#include "light_map.glsl"

uniform sampler2D u_gbuffer_position;   // w = 1 where a surface was seen
uniform mat4 u_inverse_view_projection; // camera clip -> world (rays of background pixels)
uniform vec3 u_camera_position;
uniform vec3 u_medium_min;               // the box the medium fills (the scene's bounds)
uniform vec3 u_medium_max;
uniform float u_fog_density;             // σ_t [1/m]
uniform float u_fog_albedo;              // α = σ_s/σ_t
uniform float u_fog_g;                   // HG asymmetry; 0 with the isotropic phase function
uniform int u_fog_steps;

layout(location = 0) out vec4 out_fog_direct;
layout(location = 1) out vec4 out_fog_lpv;

// Henyey–Greenstein phase function at the scattering cosine (1/(4π) at g = 0), normalised
// over the sphere (derivation media.hg_normalisation).
float phase(float cos_theta) {
    float g = u_fog_g;
    float denominator = 1.0 + g * g - 2.0 * g * cos_theta;
    return INV_FOUR_PI * (1.0 - g * g) / (denominator * sqrt(denominator));
}

// The direct light's in-scattered radiance Σ_v κ_v·p·E⊥_v·V_v towards `to_eye` at `x`.
vec3 direct_inscattering(vec3 x, vec3 to_eye) {
    vec3 total = vec3(0.0);
    for (int light = 0; light < u_light_count; ++light) {
        vec3 to_light;
        float irradiance = light_arrival(light, x, to_light);
        if (irradiance > 0.0 && light_map_reaches(light, x, 1.0)) {
            total += u_lights[light].colour_texel.rgb
                   * (phase(dot(-to_light, to_eye)) * irradiance);
        }
    }
    return total;
}

// The ray's parameter interval inside the box (slab method); empty when t1 <= t0.
void ray_box(vec3 origin, vec3 direction, out float t0, out float t1) {
    vec3 inverse = 1.0 / direction;    // ±inf on an axis the ray is parallel to
    vec3 a = (u_medium_min - origin) * inverse;
    vec3 b = (u_medium_max - origin) * inverse;
    vec3 near = min(a, b);
    vec3 far = max(a, b);
    t0 = max(max(near.x, near.y), near.z);
    t1 = min(min(far.x, far.y), far.z);
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(u_gbuffer_position, pixel, 0);
    vec3 direction;
    float surface;
    if (position.w > 0.5) {
        vec3 offset = position.xyz - u_camera_position;
        surface = length(offset);
        direction = offset / surface;
    } else {
        vec2 ndc = gl_FragCoord.xy / vec2(textureSize(u_gbuffer_position, 0)) * 2.0 - 1.0;
        vec4 far = u_inverse_view_projection * vec4(ndc, 1.0, 1.0);
        direction = normalize(far.xyz / far.w - u_camera_position);
        surface = 3.0e38;
    }
    float t0, t1;
    ray_box(u_camera_position, direction, t0, t1);
    t0 = max(t0, 0.0);
    t1 = min(t1, surface);
    float path = max(t1 - t0, 0.0);
    float step = path / float(u_fog_steps);
    vec3 to_eye = -direction;
    vec3 direct = vec3(0.0);
    vec3 lpv = vec3(0.0);
    for (int i = 0; i < u_fog_steps && path > 0.0; ++i) {
        float weight = u_fog_albedo * (exp(-u_fog_density * step * float(i))
                                       - exp(-u_fog_density * step * float(i + 1)));
        if (weight <= 0.0) {
            continue;
        }
        vec3 x = u_camera_position + (t0 + (float(i) + 0.5) * step) * direction;
        direct += weight * direct_inscattering(x, to_eye);
        lpv += weight * lpv_lobe_radiance(x, to_eye, u_fog_g);
    }
    out_fog_direct = vec4(direct, exp(-u_fog_density * path));
    out_fog_lpv = vec4(lpv, 0.0);
}
#endif
