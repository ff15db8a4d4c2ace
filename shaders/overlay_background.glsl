#version 430 core
// Overlay compositor, full-screen fill (explorer/ui/overlays/compositor.py): write every
// pixel's colour and depth. For the static layer the colour is the image the view shows
// and the depth is the G-buffer's world position projected with the frame's camera (the
// same matrices the G-buffer pass used), so the overlays drawn next hide behind the
// frame's surfaces exactly; background pixels get the far plane. For the output layer it
// copies the static layer, colour and depth.

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
uniform sampler2D u_base;            // colour (display values)
uniform int u_base_top_first;        // 1: row 0 of u_base is the image's top row
uniform int u_depth_is_position;     // 1: depth from u_position, 0: from u_depth
uniform sampler2D u_position;        // G-buffer world position (w = 1 on a surface)
uniform sampler2D u_depth;           // a depth texture (the same unit as u_position)
uniform mat4 u_view_projection;

out vec4 out_colour;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(u_position, 0);
    ivec2 base_size = textureSize(u_base, 0);
    ivec2 at = pixel * base_size / size;          // the same image at another size
    if (u_base_top_first == 1) {
        at.y = base_size.y - 1 - at.y;
    }
    out_colour = vec4(texelFetch(u_base, at, 0).rgb, 1.0);
    if (u_depth_is_position == 0) {
        gl_FragDepth = texelFetch(u_depth, pixel, 0).r;
        return;
    }
    vec4 position = texelFetch(u_position, pixel, 0);
    if (position.w < 0.5) {
        gl_FragDepth = 1.0;
        return;
    }
    vec4 clip = u_view_projection * vec4(position.xyz, 1.0);
    gl_FragDepth = clamp(clip.z / clip.w * 0.5 + 0.5, 0.0, 1.0);
}
#endif
