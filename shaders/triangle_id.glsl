#version 430 core
// Which triangle each pixel of the camera's view sees: the G-buffer pass's camera and depth
// test (gbuffer.glsl, same vertex transform, so the same triangle wins every pixel), with
// the triangle's index + 1 in the red channel (0 where no surface was seen). A float holds
// indices exactly below 2^24; explorer/truth/surface_masks.py refuses larger scenes.

uniform mat4 u_view;
uniform mat4 u_projection;

#if defined VERTEX_SHADER
in vec3 in_position;

void main() {
    gl_Position = u_projection * u_view * vec4(in_position, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
layout(location = 0) out vec4 out_triangle;
uniform int u_first_triangle;   // SceneBuffers.draw draws runs: gl_PrimitiveID restarts
uniform int u_one_sided;        // as in gbuffer.glsl: a one-sided back face is not there

void main() {
    if (u_one_sided == 1 && !gl_FrontFacing) {
        discard;
    }
    // the index into the scene's triangle soup: the run's first triangle + gl_PrimitiveID
    out_triangle = vec4(float(u_first_triangle + gl_PrimitiveID + 1), 0.0, 0.0, 1.0);
}
#endif
