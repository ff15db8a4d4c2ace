#version 430 core
// Overlay compositor, first pass (explorer/ui/overlays/compositor.py): copy the image the
// view shows and write the depth of the frame's own surfaces, so the overlays drawn next
// are hidden behind the scene exactly where the G-buffer saw a surface. The depth is the
// G-buffer's world position projected with the frame's camera (the same matrices the
// G-buffer pass used); background pixels get the far plane.

#if defined VERTEX_SHADER
#include "fullscreen.glsl"
#endif

#if defined FRAGMENT_SHADER
uniform sampler2D u_base;         // the view's image (display colours)
uniform int u_base_top_first;     // 1: row 0 of u_base is the image's top row
uniform sampler2D u_position;     // G-buffer world position (w = 1 on a surface), GL rows
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
    vec4 position = texelFetch(u_position, pixel, 0);
    if (position.w < 0.5) {
        gl_FragDepth = 1.0;
        return;
    }
    vec4 clip = u_view_projection * vec4(position.xyz, 1.0);
    gl_FragDepth = clamp(clip.z / clip.w * 0.5 + 0.5, 0.0, 1.0);
}
#endif
