#version 430 core
// Wireframe overlay: coloured line segments in world space (grid lattice, cascade
// extents, the picked cell).

uniform mat4 u_view_projection;

#if defined VERTEX_SHADER
in vec3 in_position;
in vec4 in_colour;
out vec4 v_colour;

void main() {
    v_colour = in_colour;
    gl_Position = u_view_projection * vec4(in_position, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
in vec4 v_colour;
out vec4 out_colour;

void main() {
    out_colour = v_colour;
}
#endif
