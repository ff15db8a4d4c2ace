#version 430 core
// One VPL texture set copied into its tile of the VPL atlas (explorer/lpv/passes/atlas.py), texel
// for texel: the viewport is the tile, u_tile_origin its lower-left texel in the atlas.
// Several lights' RSMs side by side in one texture set inject in one pass and serve the
// final gather as one shadow-map atlas (docs/MODEL.md "Several lights").

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
uniform sampler2D u_source_position;
uniform sampler2D u_source_normal;
uniform sampler2D u_source_flux;
uniform sampler2D u_source_albedo;
uniform int u_has_albedo;           // 0: the set has no albedo texture, write zeros
uniform ivec2 u_tile_origin;

layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_flux;
layout(location = 3) out vec4 out_albedo;

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy) - u_tile_origin;
    out_position = texelFetch(u_source_position, texel, 0);
    out_normal = texelFetch(u_source_normal, texel, 0);
    out_flux = texelFetch(u_source_flux, texel, 0);
    out_albedo = u_has_albedo == 1 ? texelFetch(u_source_albedo, texel, 0) : vec4(0.0);
}
#endif
