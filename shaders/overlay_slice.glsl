#version 430 core
// Slice plane overlay: a quad through the centres of one layer of cells, coloured per cell
// by a scalar (explorer/ui/overlays/quantities.py slice_field) through a colour map table
// (the colour bar's). One draw of 4 vertices; the quad is corner + s·edge_u + t·edge_v.

uniform mat4 u_view_projection;
uniform vec3 u_corner;
uniform vec3 u_edge_u;
uniform vec3 u_edge_v;

#if defined VERTEX_SHADER
out vec2 v_st;

void main() {
    vec2 st = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
    v_st = st;
    gl_Position = u_view_projection * vec4(u_corner + st.x * u_edge_u + st.y * u_edge_v, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
uniform sampler2D u_values;       // R32F, texel (i, j) = cell i along u, j along v
uniform sampler2D u_colour_map;   // RGBA8, COLOUR_MAP_SIZE x 1, bottom of the bar first
uniform float u_low;
uniform float u_high;
uniform float u_opacity;
uniform int u_log;                // 1: t = log10(value/high)/decades + 1 (SliceField.log)
#define LOG_FLOOR_OPACITY 0.2
uniform float u_decades;

in vec2 v_st;
out vec4 out_colour;

void main() {
    ivec2 cells = textureSize(u_values, 0);
    ivec2 cell = clamp(ivec2(floor(v_st * vec2(cells))), ivec2(0), cells - 1);
    float value = texelFetch(u_values, cell, 0).r;
    float t = u_log == 1
        ? log(max(value, 1e-30) / u_high) / (log(10.0) * u_decades) + 1.0
        : (value - u_low) / max(u_high - u_low, 1e-30);
    t = clamp(t, 0.0, 1.0);
    int entries = textureSize(u_colour_map, 0).x;
    vec3 colour = texelFetch(u_colour_map, ivec2(int(round(t * float(entries - 1))), 0), 0).rgb;
    // on a log scale a cell below the bottom of the bar holds (relatively) nothing: it is
    // drawn faint so the scene behind shows where the light is not
    float faint = (u_log == 1 && t <= 0.0) ? LOG_FLOOR_OPACITY : 1.0;
    out_colour = vec4(colour, u_opacity * faint);
}
#endif
