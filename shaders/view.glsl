#version 430 core
// What the View panel shows (explorer/ui/view_composer.py), from the pictures of sides A
// and B (their linear direct and indirect radiance and albedo, view_snapshot.glsl). Every
// display-only choice lives here, so changing it draws this pass once and runs no stage
// of the pipeline:
//   VIEW_MODE 0, one side: the chosen buffer as the display shows it (docs/MODEL.md
//     "Display"): final = display_encode(exposure·(direct + indirect)) (exposure·indirect
//     with indirect only), with fog (FOG_A) the surfaces seen through it plus its
//     in-scattering (fog_compose.glsl); direct and indirect (the surfaces' own) encoded
//     alike; albedo (its geometry edges darkened) clamped and sRGB-encoded. The same as display.glsl for "final".
//   VIEW_MODE 1, difference: the luminance of the chosen linear buffer of A minus B (final:
//     with each side's exposure, as FrameResult.final_image), |A − B| on the heat map or
//     A − B on the diverging map, over u_top (the scale bar's top).
// The mode, the buffer and whether each side has fog are compile-time constants (the composer compiles one program
// per pair on first use, ProgramCache defines): llvmpipe runs both sides of a branch on a
// uniform, which made a uniform-driven pass cost 2.6 times the display pass.
// Full-screen pass; row 0 at the bottom, as GL draws. Side B may be another size than the
// output (it lags A while the camera moves): it is sampled at the same place in the image.

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
#include "tonemap.glsl"
#include "fog_compose.glsl"

const int BUFFER_FINAL = 0;        // explorer/ui/state.py VIEW_BUFFERS order
const int BUFFER_DIRECT = 1;
const int BUFFER_INDIRECT = 2;
const int BUFFER_ALBEDO = 3;
const vec3 REC709_LUMA = vec3(0.2126, 0.7152, 0.0722);   // explorer/lpv/twin/tonemap.py

#define VIEW_MODE 0                // 0 one side, 1 difference
#define VIEW_BUFFER 0              // BUFFER_*
#define FOG_A 0                    // 1: side A's picture has fog to compose ("final")
#define FOG_B 0                    // likewise side B's (difference)
uniform int u_indirect_only;
uniform int u_tone_map;            // TONE_MAP_* of tonemap.glsl
uniform sampler2D u_direct_a;
uniform sampler2D u_indirect_a;
uniform sampler2D u_albedo_a;
uniform sampler2D u_fog_direct_a;  // fog.glsl's targets as the picture copied them
uniform sampler2D u_fog_lpv_a;
uniform float u_exposure_a;
uniform float u_scale_a;           // display scale (auto exposure) of side A
uniform sampler2D u_direct_b;
uniform sampler2D u_indirect_b;
uniform sampler2D u_albedo_b;
uniform sampler2D u_fog_direct_b;
uniform sampler2D u_fog_lpv_b;
uniform float u_exposure_b;
uniform int u_signed;              // difference: 1 = A − B on the diverging map
uniform float u_top;               // difference: the value at the top of the scale
uniform sampler2D u_colour_map;    // difference: colour table, bottom of the bar first
uniform float u_edge_flag;         // albedo: an edge pixel's w, and what scales its colour
uniform float u_edge_shade;        // (explorer/lpv/surface_edges.py)

layout(location = 0) out vec4 out_colour;

// The linear colour of the chosen buffer (FrameResult.final_image for "final"; ``fog``:
// compose the fog's targets over it).
vec3 linear_buffer(sampler2D direct, sampler2D indirect, sampler2D albedo,
                   sampler2D fog_direct, sampler2D fog_lpv, bool fog, ivec2 at,
                   float exposure) {
    if (VIEW_BUFFER == BUFFER_ALBEDO) {
        vec4 a = texelFetch(albedo, at, 0);
        // the geometry's edges the picture's copy marked (view_snapshot.glsl): a flat
        // albedo alone hides a white block before a white wall
        return abs(a.w - u_edge_flag) < 0.01 ? u_edge_shade * a.rgb : a.rgb;
    }
    vec3 d = texelFetch(direct, at, 0).rgb;
    vec3 i = texelFetch(indirect, at, 0).rgb;
    if (VIEW_BUFFER == BUFFER_DIRECT) {
        return d;
    }
    if (VIEW_BUFFER == BUFFER_INDIRECT) {
        return i;
    }
    vec3 surfaces = u_indirect_only == 1 ? i : d + i;
    if (fog) {
        surfaces = seen_through_fog(surfaces, texelFetch(fog_direct, at, 0),
                                    texelFetch(fog_lpv, at, 0).rgb, u_indirect_only == 1);
    }
    return exposure * surfaces;
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
#if VIEW_MODE == 0
    vec3 linear = linear_buffer(u_direct_a, u_indirect_a, u_albedo_a, u_fog_direct_a,
                                u_fog_lpv_a, FOG_A == 1, pixel, u_exposure_a);
    if (VIEW_BUFFER == BUFFER_ALBEDO) {
        out_colour = vec4(linear_to_srgb(linear), 1.0);
    } else {
        float exposure = VIEW_BUFFER == BUFFER_FINAL ? 1.0 : u_exposure_a;
        out_colour = vec4(display_encode(exposure * linear, u_scale_a, u_tone_map), 1.0);
    }
#else
    ivec2 size = textureSize(u_direct_a, 0);
    ivec2 at_b = pixel * textureSize(u_direct_b, 0) / size;
    float a = dot(linear_buffer(u_direct_a, u_indirect_a, u_albedo_a, u_fog_direct_a,
                                u_fog_lpv_a, FOG_A == 1, pixel, u_exposure_a), REC709_LUMA);
    float b = dot(linear_buffer(u_direct_b, u_indirect_b, u_albedo_b, u_fog_direct_b,
                                u_fog_lpv_b, FOG_B == 1, at_b, u_exposure_b), REC709_LUMA);
    float t = u_signed == 1 ? 0.5 + 0.5 * (a - b) / u_top : abs(a - b) / u_top;
    t = clamp(t, 0.0, 1.0);
    float entries = float(textureSize(u_colour_map, 0).x);
    // the table's texel centres: entry k at (k + 0.5)/entries, linear filtering between
    out_colour = vec4(texture(u_colour_map, vec2((t * (entries - 1.0) + 0.5) / entries, 0.5)).rgb,
                      1.0);
#endif
}
#endif
