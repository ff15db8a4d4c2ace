#version 430 core
// G-buffer for the one-bounce reference (explorer/truth/gbuffer.py): world position,
// world normal and albedo of the surface each pixel sees, from the scene's own camera.
// Used when a FrameResult does not carry the Pipeline's G-buffer.

#if defined VERTEX_SHADER
uniform mat4 u_view_projection;
in vec3 in_position;
in vec3 in_normal;
in vec3 in_albedo;
out vec3 v_position;
out vec3 v_normal;
out vec3 v_albedo;

void main() {
    v_position = in_position;
    v_normal = in_normal;
    v_albedo = in_albedo;
    gl_Position = u_view_projection * vec4(in_position, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
in vec3 v_position;
in vec3 v_normal;
in vec3 v_albedo;
layout(location = 0) out vec4 out_position;  // w = 1: a surface was seen
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;

void main() {
    out_position = vec4(v_position, 1.0);
    out_normal = vec4(normalize(v_normal), 0.0);
    out_albedo = vec4(v_albedo, 1.0);
}
#endif
