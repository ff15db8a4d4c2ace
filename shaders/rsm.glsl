#version 430 core
// Shadow map + reflective shadow map in one MRT pass (docs/MODEL.md "Reflective shadow map"):
// one view of one light (a point light renders six, docs/MODEL.md "Several lights").
// Targets: 0 = world position (w = 1 where a surface was seen), 1 = normal facing the light
// (w = view depth from the light), 2 = reflected flux per texel (rgb, watts), 3 = diffuse
// albedo (rgb; read by the geometry volume to reflect blocked light, docs/MODEL.md
// "More bounces").

uniform mat4 u_light_view;
uniform mat4 u_light_projection;

#include "surface.glsl"

#if defined VERTEX_SHADER
out float v_depth;

void main() {
    vec4 view_position = u_light_view * vec4(in_position, 1.0);
    pass_surface();
    v_depth = -view_position.z;
    gl_Position = u_light_projection * view_position;
}
#endif

#if defined FRAGMENT_SHADER
#include "spot.glsl"

uniform int u_orthographic;         // 0: spot light, 1: directional light
uniform vec3 u_light_position;      // spot
uniform vec3 u_light_direction;     // directional: the direction the light travels
uniform float u_light_intensity;    // spot: Φ_L / (4π)  [W/sr]
uniform float u_light_irradiance;   // directional: E on a plane facing the light [W/m²]
uniform float u_texel_world_area;   // directional: world area of one texel [m²]
uniform vec2 u_rsm_size;
uniform float u_frustum_half_width; // spot: t = tan(fov/2), the frustum cuts depth 1 in [-t, t]²
uniform vec3 u_light_colour;        // the light's flux per channel is its flux times this

in float v_depth;

layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_flux;
layout(location = 3) out vec4 out_albedo;

// Solid angle of the spherical triangle spanned by three (not necessarily unit) corner
// directions (Van Oosterom & Strackee): tan(Ω/2) = |a·(b×c)| / (|a||b||c| + (a·b)|c| +
// (a·c)|b| + (b·c)|a|). For corners of one texel on the plane z = 1 the triple product is
// exactly the texel's (dx·dy), so the formula stays accurate for tiny texels where
// differences of atan terms would cancel.
float triangle_solid_angle(vec3 a, vec3 b, vec3 c, float triple) {
    float la = length(a), lb = length(b), lc = length(c);
    float denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    return 2.0 * atan(triple, denominator);
}

// The texel's corners on the plane at view depth 1 (the frustum cuts it in [-t, t]²).
vec2 texel_corner(vec2 texel) {
    return (texel / u_rsm_size * 2.0 - 1.0) * u_frustum_half_width;
}

// Exact solid angle of the RSM texel under this fragment, seen from the spot light: the
// texel is the rectangle [x0, x1]×[y0, y1] of the plane at view depth 1, split into two
// triangles.
float texel_solid_angle(vec2 texel) {
    vec2 lo = texel_corner(texel);
    vec2 hi = texel_corner(texel + 1.0);
    float triple = (hi.x - lo.x) * (hi.y - lo.y);
    vec3 c00 = vec3(lo.x, lo.y, 1.0), c10 = vec3(hi.x, lo.y, 1.0);
    vec3 c11 = vec3(hi.x, hi.y, 1.0), c01 = vec3(lo.x, hi.y, 1.0);
    return triangle_solid_angle(c00, c10, c11, triple)
         + triangle_solid_angle(c00, c11, c01, triple);
}

void main() {
    vec3 normal = surface_normal();  // the side the light sees (a one-sided back: none)
    vec3 albedo = surface_albedo();  // per pixel: the texture at this texel's surfel
    vec3 to_light = u_orthographic == 1 ? -u_light_direction
                                        : normalize(u_light_position - v_position);
    // The texel's footprint on the surface already shrinks with cos θ_i, so the flux the
    // surface intercepts through one texel is I·ρ (spot) or E·A_texel (directional) and
    // the reflected flux is c_diff times that; cos θ_i only decides whether the light
    // reaches the front of the surface (docs/MODEL.md, "Reflective shadow map"). A spot
    // cone scales the texel's flux by its falloff at the texel's centre direction
    // (docs/MODEL.md "Spot cone"): the direction (c, 1) at depth 1 is cos θ = 1/|(c, 1)|
    // off the axis.
    float faces_light = dot(normal, to_light) > 0.0 ? 1.0 : 0.0;
    vec2 texel = floor(gl_FragCoord.xy);
    vec2 centre = texel_corner(texel + 0.5);
    float incident = u_orthographic == 1
        ? u_light_irradiance * u_texel_world_area
        : u_light_intensity * texel_solid_angle(texel)
          * spot_falloff(inversesqrt(1.0 + dot(centre, centre)));
    out_position = vec4(v_position, 1.0);
    out_normal = vec4(normal, v_depth);
    out_flux = vec4(albedo * u_light_colour * incident * faces_light, 0.0);
    out_albedo = vec4(albedo, 0.0);
}
#endif
