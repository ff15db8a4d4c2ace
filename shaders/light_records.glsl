#version 430 core
// The RSM views as records in a storage buffer (docs/MODEL.md "Several lights"), and the
// light each view brings to a point: read by the gather's direct light, the fog's direct
// in-scattering and (with light_map.glsl) every shadow-map test. Python side:
// explorer/lpv/passes/light_records.py (light_records, LIGHT_BINDING). Include it once, in the
// stage that reads it.
#ifndef LIGHT_RECORDS_GLSL
#define LIGHT_RECORDS_GLSL 1

#include "spot.glsl"

// One record per RSM view.
struct LightRecord {
    mat4 view;              // world -> light view
    mat4 projection;
    vec4 position_kind;     // xyz: position (spot, point) or the orthographic eye; w: kind
                            // 0 spot, 1 directional, 2 a face of a point light's cube
    vec4 axis_power;        // xyz: spot axis, directional travel direction or the face's
                            // axis; w: intensity Φ_L/(4π) (spot, point) or irradiance E
    vec4 colour_texel;      // rgb: colour; w: shadow texel edge at depth 1 or in world units
    vec4 cone;              // x: 1 = the spot has a cone, y: cos inner, z: cos outer
    ivec4 tile;             // xy: lower-left texel of the view's shadow map, zw: its size
};
layout(std430, binding = 5) readonly buffer LightRecords { LightRecord u_lights[]; };
uniform int u_light_count;

bool light_is_orthographic(int light) {
    return u_lights[light].position_kind.w == 1.0;
}

// Whether the direction d from a point light falls in the cube face whose axis is `axis`
// (cube-map face selection: the largest |component| of d, ties going to x, then y, then
// z). The six faces partition the directions, so each point counts one face's light once
// (docs/MODEL.md "Several lights").
bool in_cube_face(vec3 d, vec3 axis) {
    vec3 a = abs(d);
    int major = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
    int face = abs(axis.x) > 0.5 ? 0 : (abs(axis.y) > 0.5 ? 1 : 2);
    return major == face && d[major] * axis[face] > 0.0;
}

// The irradiance view `light` brings to p on a plane facing it, without its colour and
// shadow: I·f(θ)/r² (spot, f its cone's falloff at the angle θ from its axis), I/r² (a
// point light's face, 0 for a point another face holds) or E (directional); `to_light`
// gets the unit direction from p towards the light.
float light_arrival(int light, vec3 p, out vec3 to_light) {
    vec3 axis = u_lights[light].axis_power.xyz;
    float power = u_lights[light].axis_power.w;
    if (light_is_orthographic(light)) {
        to_light = -axis;
        return power;
    }
    vec3 offset = u_lights[light].position_kind.xyz - p;
    float distance_squared = max(dot(offset, offset), 1e-12);
    to_light = offset * inversesqrt(distance_squared);
    if (u_lights[light].position_kind.w == 2.0 && !in_cube_face(-offset, axis)) {
        return 0.0;
    }
    vec4 cone = u_lights[light].cone;
    return power / distance_squared
         * spot_falloff_of(dot(-to_light, axis), cone.x > 0.5, cone.y, cone.z);
}

#endif
