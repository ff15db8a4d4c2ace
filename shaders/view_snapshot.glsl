#version 430 core
// The window's copy of one side's picture (explorer/ui/picture.py): the gather's linear
// direct and indirect radiance and the G-buffer's albedo (SOURCES 3), or the fog pass's two
// targets of a frame with fog (SOURCES 2, docs/MODEL.md "Fog"), copied texel for texel into
// textures the window owns, so that the view keeps showing a whole picture while the
// pipeline rewrites its own targets (a camera move re-renders the G-buffer before the
// gather, the gather runs in bands). Full-screen pass at the first source's size: a source
// of that size is copied texel for texel, a larger one (the G-buffer's albedo beside a
// reduced preview's gather, explorer/lpv/passes/gather.py) gives the texel below each pixel.
// EDGES 1 (with SOURCES 3): the G-buffer's position and normal mark the albedo copy's
// geometry edges, w = u_edge_flag instead of 1 (explorer/lpv/surface_edges.py, whose
// surface_edges() is this test in numpy), which the albedo view darkens (view.glsl).

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
#define SOURCES 3

uniform sampler2D u_source0;       // direct radiance, or the fog's direct in-scattering
uniform sampler2D u_source1;       // indirect radiance, or the fog's LPV in-scattering
uniform sampler2D u_source2;       // albedo, w = 1 where a surface is seen
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
    ivec2 at = pixel * textureSize(u_source2, 0) / size;
    out_copy2 = texelFetch(u_source2, at, 0);
#if EDGES == 1
    if (out_copy2.w > 0.5 && is_edge(at)) {
        out_copy2.w = u_edge_flag;
    }
#endif
#endif
}
#endif
