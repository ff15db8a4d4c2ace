#version 430 core
// The window's copy of one side's picture (explorer/ui/picture.py): the gather's linear
// direct and indirect radiance and the G-buffer's albedo, copied texel for texel into
// textures the window owns, so that the view keeps showing a whole picture while the
// pipeline rewrites its own targets (a camera move re-renders the G-buffer before the
// gather, the gather runs in bands). Full-screen pass, one texel per pixel.

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
uniform sampler2D u_direct;        // rgba32f linear radiance (gather.glsl target 0)
uniform sampler2D u_indirect;      // rgba32f linear radiance (gather.glsl target 1)
uniform sampler2D u_albedo;        // G-buffer albedo, w = 1 where a surface is seen

layout(location = 0) out vec4 out_direct;
layout(location = 1) out vec4 out_indirect;
layout(location = 2) out vec4 out_albedo;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    out_direct = texelFetch(u_direct, pixel, 0);
    out_indirect = texelFetch(u_indirect, pixel, 0);
    out_albedo = texelFetch(u_albedo, pixel, 0);
}
#endif
