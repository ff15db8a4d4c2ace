#version 430 core
// The scene-mesh interface of the passes that rasterise the scene (gbuffer, rsm): the vertex
// attributes explorer/scene/gpu.py binds (VERTEX_FORMAT), the varyings handed from the
// vertex to the fragment stage, the base-colour texture sampled per pixel and the
// surface's sidedness (docs/MODEL.md "Sidedness"). Include it once, outside the stage
// sections: it declares what the stage being compiled needs.
#ifndef SURFACE_GLSL
#define SURFACE_GLSL 1

#if defined VERTEX_SHADER
in vec3 in_position;
in vec3 in_normal;
in vec3 in_albedo;
in vec2 in_uv;
out vec3 v_position;
out vec3 v_normal;
out vec3 v_albedo;
out vec2 v_uv;

// Hand the vertex's world position, normal, albedo and texture coordinates to the fragment
// stage.
void pass_surface() {
    v_position = in_position;
    v_normal = in_normal;
    v_albedo = in_albedo;
    v_uv = in_uv;
}
#endif

#if defined FRAGMENT_SHADER
in vec3 v_position;
in vec3 v_normal;
in vec3 v_albedo;
in vec2 v_uv;

uniform sampler2D u_base_colour;  // linear base colour, mipmapped (1×1 white: untextured)
uniform int u_one_sided;          // 1: the triangles of this draw exist only from the front

// The surface's normal towards the viewer (the camera or the light). A two-sided surface
// turns its normal towards the viewer; a one-sided surface seen from behind is not there
// for this viewer (the fragment is discarded, as back-face culling would), so light passes
// it and the camera sees what lies behind it. Call it first in main().
vec3 surface_normal() {
    if (u_one_sided == 1 && !gl_FrontFacing) {
        discard;
    }
    return normalize(gl_FrontFacing ? v_normal : -v_normal);
}

// Linear diffuse albedo at this pixel: the vertex albedo (the material's factor) times the
// base-colour texture sampled here (trilinear: the mip level follows the pixel's footprint
// in the texture, from the implicit derivatives of v_uv).
vec3 surface_albedo() {
    return v_albedo * texture(u_base_colour, v_uv).rgb;
}
#endif

#endif
