#version 430 core
// Light injection as points (docs/MODEL.md "Injection"): one point per VPL, drawn into the
// layer gl_Layer = cell.z of a layered 2D-array target N x N x N with additive ONE,ONE
// blending, three render targets for the r, g, b SH vectors. The caller copies the layers
// into the grid's 3D textures (volume_copy.glsl).
// grid[c, cell(p + offset*n)] += k_I * flux[c] * lobe(n).
// SH_ORDER 2 injects the L2 lobe: the geometry shader emits one point per texel group, into
// layer cell.z + k·N (the layout of sh_grid.glsl), and the fragment writes group k.
#define SH_ORDER 1

#if defined VERTEX_SHADER

#include "grid.glsl"
#include "vpl.glsl"

flat out ivec3 v_cell;
flat out int v_keep;
flat out vec3 v_normal;
flat out vec3 v_flux;

void main() {
    Vpl vpl = vpl_fetch(gl_VertexID);
    v_cell = grid_cell(vpl_injection_position(vpl));
    v_keep = int(vpl.valid && grid_inside(v_cell));
    v_normal = vpl.normal;
    v_flux = vpl.flux;
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}

#endif

#if defined GEOMETRY_SHADER

#include "grid.glsl"

#include "sh.glsl"

layout(points) in;
layout(points, max_vertices = SH_GROUPS) out;

flat in ivec3 v_cell[];
flat in int v_keep[];
flat in vec3 v_normal[];
flat in vec3 v_flux[];

flat out vec3 g_normal;
flat out vec3 g_flux;
flat out int g_group;

void main() {
    if (v_keep[0] == 0) {
        return;  // an empty RSM texel or a VPL outside the grid adds nothing
    }
    // The pixel centre of column x, row y of an nx x ny viewport, in clip space.
    vec2 ndc = (vec2(v_cell[0].xy) + 0.5) / vec2(u_grid_cells.xy) * 2.0 - 1.0;
    for (int group = 0; group < SH_GROUPS; ++group) {
        gl_Position = vec4(ndc, 0.0, 1.0);
        gl_Layer = v_cell[0].z + group * u_grid_cells.z;
        g_normal = v_normal[0];
        g_flux = v_flux[0];
        g_group = group;
        EmitVertex();
        EndPrimitive();
    }
}

#endif

#if defined FRAGMENT_SHADER

#include "lpv_corrections.glsl"

flat in vec3 g_normal;
flat in vec3 g_flux;
flat in int g_group;

layout(location = 0) out vec4 out_red;
layout(location = 1) out vec4 out_green;
layout(location = 2) out vec4 out_blue;

void main() {
    vec4 lobe = lpv_injection_factor() * sh_group(shv_cosine_lobe(g_normal), g_group);
    out_red = g_flux.r * lobe;
    out_green = g_flux.g * lobe;
    out_blue = g_flux.b * lobe;
}

#endif
