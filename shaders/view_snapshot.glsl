#version 430 core
// The window's copy of one side's picture (explorer/ui/picture.py): the gather's linear
// direct and indirect radiance and the G-buffer's albedo (SOURCES 3), or the fog pass's two
// targets of a frame with fog (SOURCES 2, docs/MODEL.md "Fog"), copied texel for texel into
// textures the window owns, so that the view keeps showing a whole picture while the
// pipeline rewrites its own targets (a camera move re-renders the G-buffer before the
// gather, the gather runs in bands). Full-screen pass at the first source's size: a source
// of that size is copied texel for texel, a larger one (the G-buffer's albedo beside a
// reduced preview's gather, explorer/lpv/passes/gather.py) gives the texel below each pixel.

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
#define SOURCES 3

uniform sampler2D u_source0;       // direct radiance, or the fog's direct in-scattering
uniform sampler2D u_source1;       // indirect radiance, or the fog's LPV in-scattering
uniform sampler2D u_source2;       // albedo, w = 1 where a surface is seen

layout(location = 0) out vec4 out_copy0;
layout(location = 1) out vec4 out_copy1;
#if SOURCES == 3
layout(location = 2) out vec4 out_copy2;
#endif

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(u_source0, 0);
    out_copy0 = texelFetch(u_source0, pixel, 0);
    out_copy1 = texelFetch(u_source1, pixel * textureSize(u_source1, 0) / size, 0);
#if SOURCES == 3
    out_copy2 = texelFetch(u_source2, pixel * textureSize(u_source2, 0) / size, 0);
#endif
}
#endif
