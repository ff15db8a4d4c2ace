#version 430 core
// The final image as shown (the display stage, docs/MODEL.md "Display"): the gather's
// linear direct and indirect radiance, exposed, tone-mapped and sRGB-encoded into the RGBA8
// display texture. Everything that only changes how the frame looks (exposure, indirect
// only, auto exposure, the tone curve) lives here, so changing it runs this pass alone.
// Full-screen pass, one texel per pixel.
//     exposed = exposure · (direct + indirect)   (exposure · indirect with u_indirect_only)
//     shown   = display_encode(exposed, display scale, tone map)   (tonemap.glsl)
// The display scale is the auto exposure key/L̄ (or 1). With fog (docs/MODEL.md "Fog") the
// surfaces are seen through the medium and the medium's in-scattering adds to them:
//     exposed = exposure · (T·(direct + indirect) + fog_direct + fog_lpv)
// (exposure · (T·indirect + fog_lpv) with u_indirect_only: the LPV's light alone;
// fog_compose.glsl, which the window's view pass shares).
// Numpy twin: FrameResult.final_image (the exposed colour, explorer.lpv.passes.display
// exposed_image) through explorer.lpv.twin.tonemap.display_encode.

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
#include "tonemap.glsl"
#include "fog_compose.glsl"

uniform sampler2D u_direct;        // rgba32f linear radiance (gather.glsl target 0)
uniform sampler2D u_indirect;      // rgba32f linear radiance (gather.glsl target 1)
uniform float u_exposure;          // Settings.exposure
uniform float u_display_scale;     // auto exposure key/L̄, or 1
uniform int u_indirect_only;
uniform int u_tone_map;            // TONE_MAP_LINEAR_CLIP or TONE_MAP_FILMIC
uniform int u_fog;                 // 1: compose the fog pass's targets
uniform sampler2D u_fog_direct;    // fog.glsl target 0: direct in-scattering rgb, T in alpha
uniform sampler2D u_fog_lpv;       // fog.glsl target 1: the LPV's in-scattering rgb

layout(location = 0) out vec4 out_display;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 indirect = texelFetch(u_indirect, pixel, 0).rgb;
    vec3 direct = u_indirect_only == 1 ? vec3(0.0) : texelFetch(u_direct, pixel, 0).rgb;
    vec3 linear = direct + indirect;
    if (u_fog == 1) {
        linear = seen_through_fog(linear, texelFetch(u_fog_direct, pixel, 0),
                                  texelFetch(u_fog_lpv, pixel, 0).rgb, u_indirect_only == 1);
    }
    vec3 exposed = u_exposure * linear;
    out_display = vec4(display_encode(exposed, u_display_scale, u_tone_map), 1.0);
}
#endif
