#version 430 core
// Reading one VPL from the VplTextures hand-over (explorer/lpv/vpl.py): position.w = 1 where
// the light saw a surface (0: skip), normal.w = view depth, flux.rgb in watts per channel.
#ifndef VPL_GLSL
#define VPL_GLSL 1

uniform sampler2D u_vpl_position;
uniform sampler2D u_vpl_normal;
uniform sampler2D u_vpl_flux;

struct Vpl {
    vec3 position;
    bool valid;
    vec3 normal;
    float depth;
    vec3 flux;
};

int vpl_count() {
    ivec2 size = textureSize(u_vpl_position, 0);
    return size.x * size.y;
}

// The VPL of texel `index`, counted row by row over the textures.
Vpl vpl_fetch(int index) {
    int width = textureSize(u_vpl_position, 0).x;
    ivec2 texel = ivec2(index % width, index / width);
    vec4 position = texelFetch(u_vpl_position, texel, 0);
    vec4 normal = texelFetch(u_vpl_normal, texel, 0);
    Vpl vpl;
    vpl.position = position.xyz;
    vpl.valid = position.w != 0.0;
    vpl.normal = normal.xyz;
    vpl.depth = normal.w;
    vpl.flux = texelFetch(u_vpl_flux, texel, 0).rgb;
    return vpl;
}

// Where a VPL is injected into the light grid (docs/MODEL.md "Injection"): moved
// u_injection_offset = δ·cell_size world units along its normal, into the cell in front of
// its surface (0: at the surface point itself).
uniform float u_injection_offset;

vec3 vpl_injection_position(Vpl vpl) {
    return vpl.position + u_injection_offset * vpl.normal;
}

#endif
