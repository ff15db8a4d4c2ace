#version 430 core
// Whether the light reaches a world point, from its shadow map (the RSM's position target,
// w = 1 where it saw a surface, and its normal target, w = view depth from the light):
// the camera occluders' test "is this G-buffer surfel already in the RSM?" and the fog's
// shadow test of points in the medium (docs/MODEL.md "Camera occluders", "Fog"). One
// texel, no filtering: the point is compared with the surface the texel under it stores.
// Numpy twin: explorer/lpv/reference_media.py (light_map_reaches).
#ifndef LIGHT_MAP_GLSL
#define LIGHT_MAP_GLSL 1

uniform sampler2D u_shadow_position;   // RSM position (w = 1 where the light saw a surface)
uniform sampler2D u_shadow_normal;     // RSM normal (w = view depth from the light)
uniform mat4 u_light_view;
uniform mat4 u_light_projection;
uniform int u_orthographic;            // 1: directional light (orthographic map)
uniform float u_shadow_texel;          // texel edge at view depth 1 (spot) or in world units

// Light-view depth of `world` and the edge of a shadow-map texel there; `texel` gets the
// texel the point falls in (texel i spans [i, i + 1)). False outside the light's frustum.
bool light_map_point(vec3 world, out ivec2 texel, out float depth, out float footprint) {
    vec4 view_position = u_light_view * vec4(world, 1.0);
    vec4 clip = u_light_projection * view_position;
    depth = -view_position.z;
    footprint = u_orthographic == 1 ? u_shadow_texel : u_shadow_texel * depth;
    texel = ivec2(0);
    if (clip.w <= 0.0) return false;
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) return false;
    ivec2 size = textureSize(u_shadow_normal, 0);
    texel = clamp(ivec2(floor((ndc.xy * 0.5 + 0.5) * vec2(size))), ivec2(0), size - 1);
    return true;
}

// True when the point is inside the light's frustum and no surface the map stores lies
// more than `bias_texels` texel footprints (plus 10⁻⁴ of the depth, for float rounding) in
// front of it; a texel that saw nothing hides nothing.
bool light_map_reaches(vec3 world, float bias_texels) {
    ivec2 texel;
    float depth, footprint;
    if (!light_map_point(world, texel, depth, footprint)) return false;
    if (texelFetch(u_shadow_position, texel, 0).w < 0.5) return true;
    float stored = texelFetch(u_shadow_normal, texel, 0).w;
    return depth <= stored + footprint * bias_texels + 1e-4 * depth;
}

#endif
