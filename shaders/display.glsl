#version 430 core
// The final image as shown (the display stage): the gather's linear direct and indirect
// radiance, exposed and encoded for the RGBA8 display texture. Everything that only
// changes how the frame looks (exposure, indirect only, the tone curve) lives here, so
// changing it runs this pass alone. Full-screen pass, one texel per pixel.
//     exposed = exposure · (direct + indirect)   (exposure · indirect with u_indirect_only)
//     shown   = srgb(tone_curve(exposed))
// The numpy twin is FrameResult.final_image (the exposed linear colour) followed by
// explorer.lpv.views.linear_to_srgb.

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER

uniform sampler2D u_direct;        // rgba32f linear radiance (gather.glsl target 0)
uniform sampler2D u_indirect;      // rgba32f linear radiance (gather.glsl target 1)
uniform float u_exposure;
uniform int u_indirect_only;

layout(location = 0) out vec4 out_display;

// The tone curve from exposed linear colour to [0, 1]. Linear-clip: values above 1 clip
// to white. A filmic curve (shaders/tonemap.glsl) plugs in here, selected by a uniform
// the display stage sets from its Settings field.
vec3 tone_curve(vec3 exposed) {
    return clamp(exposed, 0.0, 1.0);
}

// The sRGB transfer function (IEC 61966-2-1) of values in [0, 1].
vec3 linear_to_srgb(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 indirect = texelFetch(u_indirect, pixel, 0).rgb;
    vec3 direct = u_indirect_only == 1 ? vec3(0.0) : texelFetch(u_direct, pixel, 0).rgb;
    vec3 exposed = u_exposure * (direct + indirect);
    out_display = vec4(linear_to_srgb(tone_curve(exposed)), 1.0);
}
#endif
