#version 430 core
// Shadow-map lookups in the RSM views' tiles of the RSM atlas (position target: w = 1
// where the view saw a surface; normal target: w = view depth from the light): the
// gather's PCF (gather.glsl shadow_visibility), the fog's shadow test of points in the
// medium and the camera occluders' test "does a light view already hold this G-buffer
// surfel?" (docs/MODEL.md "Final gather", "Fog", "Camera occluders"). The views are the
// records of light_records.glsl. Numpy twin: explorer/lpv/twin/media.py (LightMap).
#ifndef LIGHT_MAP_GLSL
#define LIGHT_MAP_GLSL 1

#include "light_records.glsl"

uniform sampler2D u_shadow_position;   // RSM (atlas) position
uniform sampler2D u_shadow_normal;     // RSM (atlas) normal

// `world` projected into view `light`: `point` in the view's tile texel units (texel i
// spans [i, i + 1)), its light-view depth and the edge of a shadow-map texel there. False
// outside the view's frustum.
bool light_map_project(int light, vec3 world, out vec2 point, out float depth,
                       out float footprint) {
    vec4 view_position = u_lights[light].view * vec4(world, 1.0);
    vec4 clip = u_lights[light].projection * view_position;
    depth = -view_position.z;
    float texel_edge = u_lights[light].colour_texel.w;
    footprint = light_is_orthographic(light) ? texel_edge : texel_edge * depth;
    point = vec2(0.0);
    if (clip.w <= 0.0) return false;
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) return false;
    point = (ndc.xy * 0.5 + 0.5) * vec2(u_lights[light].tile.zw);
    return true;
}

// 1 where texel `at` of the shadow map `tile` (clamped to it) does not hide a point at
// light-view depth `depth`, else 0; a texel that saw nothing hides nothing.
float light_map_test(ivec2 at, ivec4 tile, float depth, float bias) {
    at = clamp(at, ivec2(0), tile.zw - 1) + tile.xy;
    bool seen = texelFetch(u_shadow_position, at, 0).w > 0.5;
    float stored = texelFetch(u_shadow_normal, at, 0).w;
    return (!seen || depth <= stored + bias) ? 1.0 : 0.0;
}

// True when the point is inside view `light`'s frustum and no surface its map stores
// under the point (one texel, no filtering) lies more than `bias_texels` texel footprints
// (plus 10⁻⁴ of the depth, for float rounding) in front of it.
bool light_map_reaches(int light, vec3 world, float bias_texels) {
    vec2 point;
    float depth, footprint;
    if (!light_map_project(light, world, point, depth, footprint)) return false;
    return light_map_test(ivec2(floor(point)), u_lights[light].tile, depth,
                          footprint * bias_texels + 1e-4 * depth) > 0.5;
}

#endif
