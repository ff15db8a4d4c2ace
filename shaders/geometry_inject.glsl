#version 430 core
// Geometry-volume injection (docs/MODEL.md "Geometry volume"): every VPL is also an occluder
// surfel of area A; it adds A/cell_size^2 * lobe(n) (one-sided) or
// A/cell_size^2 * (lobe(n) + lobe(-n)) (double-sided) to the geometry cell whose centre is
// the nearest light-grid corner, i.e. cell round(g) of an (N+1)^3 grid. Drawn as points into
// a layered (N+1)^3 2D-array target with ONE,ONE blending, copied into the 3D texture after.
// Surfel area (annotations §5): perspective texel_area * depth^2 (u_surfel_area_squared) or
// texel_area * depth (the published bug); orthographic: texel_area.
// A second target sums the surfels' albedo weighted by their area, (A/cell_size^2)*(a, 1):
// the area-weighted mean albedo of a geometry cell is rgb / w (docs/MODEL.md "More
// bounces"); 0 where the VPL textures carry no albedo.

#if defined VERTEX_SHADER

#include "grid.glsl"
#include "vpl.glsl"
#include "lpv_corrections.glsl"

uniform float u_vpl_texel_area;
uniform bool u_vpl_orthographic;

flat out ivec3 v_cell;
flat out int v_keep;
flat out vec3 v_normal;
flat out float v_area;
flat out vec3 v_albedo;

uniform sampler2D u_vpl_albedo;
uniform bool u_has_albedo;

float surfel_area(Vpl vpl) {
    if (u_vpl_orthographic) {
        return u_vpl_texel_area;
    }
    return u_vpl_texel_area * (u_surfel_area_squared ? vpl.depth * vpl.depth : vpl.depth);
}

void main() {
    Vpl vpl = vpl_fetch(gl_VertexID);
    v_cell = ivec3(floor(grid_coords(vpl.position) + 0.5));
    v_keep = int(vpl.valid && grid_inside(v_cell, u_grid_resolution + 1));
    v_normal = vpl.normal;
    v_area = surfel_area(vpl) / (u_grid_cell_size * u_grid_cell_size);
    v_albedo = vec3(0.0);
    if (u_has_albedo) {
        int width = textureSize(u_vpl_albedo, 0).x;
        v_albedo = texelFetch(u_vpl_albedo, ivec2(gl_VertexID % width, gl_VertexID / width),
                              0).rgb;
    }
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}

#endif

#if defined GEOMETRY_SHADER

#include "grid.glsl"

layout(points) in;
layout(points, max_vertices = 1) out;

flat in ivec3 v_cell[];
flat in int v_keep[];
flat in vec3 v_normal[];
flat in float v_area[];
flat in vec3 v_albedo[];

flat out vec3 g_normal;
flat out float g_area;
flat out vec3 g_albedo;

void main() {
    if (v_keep[0] == 0) {
        return;
    }
    vec2 ndc = (vec2(v_cell[0].xy) + 0.5) / float(u_grid_resolution + 1) * 2.0 - 1.0;
    gl_Position = vec4(ndc, 0.0, 1.0);
    gl_Layer = v_cell[0].z;
    g_normal = v_normal[0];
    g_area = v_area[0];
    g_albedo = v_albedo[0];
    EmitVertex();
    EndPrimitive();
}

#endif

#if defined FRAGMENT_SHADER

#include "sh.glsl"

uniform bool u_double_sided;

flat in vec3 g_normal;
flat in float g_area;
flat in vec3 g_albedo;

layout(location = 0) out vec4 out_blocker;
layout(location = 1) out vec4 out_albedo;

void main() {
    vec4 lobe = sh_cosine_lobe(g_normal);
    if (u_double_sided) {
        lobe += sh_cosine_lobe(-g_normal);  // band 1 cancels: an isotropic blocker
    }
    out_blocker = g_area * lobe;
    out_albedo = g_area * vec4(g_albedo, 1.0);
}

#endif
