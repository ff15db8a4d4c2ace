#version 430 core
// Oriented disc overlay (VPLs, geometry-volume blockers, the picked point): per instance
// a disc of radius in_radius·u_radius_scale around in_position, in the plane normal to
// in_normal, lifted by u_lift along the normal so it does not fight with its surface.

uniform mat4 u_view_projection;
uniform float u_lift;
uniform float u_radius_scale;     // every disc's radius times this (the size slider)

#if defined VERTEX_SHADER
in vec2 in_disc;                  // mesh: a point of the unit disc
in vec3 in_position;              // instance
in vec3 in_normal;
in vec3 in_colour;
in float in_radius;

out vec3 v_colour;
out float v_rim;

void main() {
    vec3 n = normalize(in_normal);
    vec3 helper = abs(n.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 t = normalize(cross(n, helper));
    vec3 b = cross(n, t);
    float radius = u_radius_scale * in_radius;
    vec3 world = in_position + u_lift * n + radius * (in_disc.x * t + in_disc.y * b);
    v_colour = in_colour;
    v_rim = length(in_disc);
    gl_Position = u_view_projection * vec4(world, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
in vec3 v_colour;
in float v_rim;
out vec4 out_colour;

void main() {
    // a darker rim keeps neighbouring discs of the same colour apart
    out_colour = vec4(v_colour * (1.0 - 0.45 * smoothstep(0.7, 1.0, v_rim)), 1.0);
}
#endif
