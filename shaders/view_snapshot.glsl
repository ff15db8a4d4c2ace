#version 430 core
// The window's copy of one side's picture (explorer/ui/picture.py), the passes an image
// copy (glCopyImageSubData) cannot do. SOURCES 2: the gather's linear direct and indirect
// radiance, or the fog pass's two targets (docs/MODEL.md "Fog"), when the second is not the
// first's size: full-screen pass at the first source's size, the second's texel below each
// pixel. SOURCES 1: the albedo the view shows, from the picture's own copy of the G-buffer's
// albedo at the picture's size u_size (the texel below each pixel: the G-buffer is larger
// than a reduced preview's gather, explorer/lpv/passes/gather.py); with EDGES 1 the copies
// of the G-buffer's position and normal mark its geometry edges, w = u_edge_flag instead of
// 1 (explorer/lpv/surface_edges.py, whose surface_edges() is this test in numpy), which the
// albedo view darkens (view.glsl).

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
#define SOURCES 2

uniform sampler2D u_source0;       // direct radiance or the fog's direct in-scattering; albedo
#if SOURCES == 2
uniform sampler2D u_source1;       // indirect radiance, or the fog's LPV in-scattering
#else
uniform ivec2 u_size;              // the picture's
#endif
#define EDGES 0
#if EDGES == 1
uniform sampler2D u_position;      // the G-buffer's (w = 1 on a surface) ...
uniform sampler2D u_normal;        // ... and its normal (w = the pixel's world area)
uniform float u_edge_cosine;
uniform float u_edge_jump;
uniform float u_edge_flag;

// surface_edges(): a surface texel whose 4-neighbour is off the surfaces, on another face
// or farther than u_edge_jump footprints; the image's border is no edge.
bool is_edge(ivec2 at) {
    ivec2 size = textureSize(u_position, 0);
    vec4 p = texelFetch(u_position, at, 0);
    vec4 n = texelFetch(u_normal, at, 0);
    const ivec2 steps[4] = ivec2[4](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
    for (int k = 0; k < 4; ++k) {
        ivec2 there = at + steps[k];
        if (any(lessThan(there, ivec2(0))) || any(greaterThanEqual(there, size))) {
            continue;
        }
        vec4 q = texelFetch(u_position, there, 0);
        vec4 m = texelFetch(u_normal, there, 0);
        float footprint = sqrt(max(n.w, m.w));
        if (q.w <= 0.5 || dot(n.xyz, m.xyz) < u_edge_cosine
                || distance(p.xyz, q.xyz) > u_edge_jump * footprint) {
            return true;
        }
    }
    return false;
}
#endif

layout(location = 0) out vec4 out_copy0;
#if SOURCES == 2
layout(location = 1) out vec4 out_copy1;
#endif

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
#if SOURCES == 2
    ivec2 size = textureSize(u_source0, 0);
    out_copy0 = texelFetch(u_source0, pixel, 0);
    out_copy1 = texelFetch(u_source1, pixel * textureSize(u_source1, 0) / size, 0);
#else
    ivec2 at = pixel * textureSize(u_source0, 0) / u_size;
    out_copy0 = texelFetch(u_source0, at, 0);
#if EDGES == 1
    if (out_copy0.w > 0.5 && is_edge(at)) {
        out_copy0.w = u_edge_flag;
    }
#endif
#endif
}
#endif
