#version 430 core
// The scene-mesh interface of the passes that rasterise the scene (gbuffer, rsm): the vertex
// attributes explorer/scene/gpu.py binds (VERTEX_FORMAT), the varyings handed from the
// vertex to the fragment stage, and the two-sided normal. Include it once, outside the stage
// sections: it declares what the stage being compiled needs.
#ifndef SURFACE_GLSL
#define SURFACE_GLSL 1

#if defined VERTEX_SHADER
in vec3 in_position;
in vec3 in_normal;
in vec3 in_albedo;
out vec3 v_position;
out vec3 v_normal;
out vec3 v_albedo;

// Hand the vertex's world position, normal and albedo to the fragment stage.
void pass_surface() {
    v_position = in_position;
    v_normal = in_normal;
    v_albedo = in_albedo;
}
#endif

#if defined FRAGMENT_SHADER
in vec3 v_position;
in vec3 v_normal;
in vec3 v_albedo;

// Two-sided surfaces: the normal that faces the viewer (the camera or the light).
vec3 facing_normal() {
    return normalize(gl_FrontFacing ? v_normal : -v_normal);
}
#endif

#endif
