#version 430 core
// The final image as shown (docs/MODEL.md "Display"): the gather's linear final colour
// times the display scale (auto exposure, or 1), through the tone curve, sRGB-encoded into
// the RGBA8 display texture. Full-screen pass, one texel per pixel.

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
#include "tonemap.glsl"

uniform sampler2D u_final;         // linear exposure·(direct + indirect), rgba32f
uniform float u_display_scale;     // auto exposure key/L̄, or 1
uniform int u_tone_map;            // TONE_MAP_LINEAR_CLIP or TONE_MAP_FILMIC

layout(location = 0) out vec4 out_display;

void main() {
    vec3 linear = texelFetch(u_final, ivec2(gl_FragCoord.xy), 0).rgb;
    out_display = vec4(display_encode(linear, u_display_scale, u_tone_map), 1.0);
}
#endif
