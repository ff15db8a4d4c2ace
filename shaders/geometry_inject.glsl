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
// CAMERA_SURFELS 1 (docs/MODEL.md "Camera occluders"): the points are the camera's G-buffer
// pixels instead of VPLs, drawn into their own targets and added to the views' merged
// volume. A pixel at view depth w is a surfel of area pixel_area * w^2 (the RSM texel's
// rule, with pixel_area = (2 tan(fov_y/2) / H)^2), facing the camera; a pixel that ANY RSM
// view sees (its shadow-map test passes with the plane's largest depth offset within a
// texel as bias) is skipped, because that view's volume already holds a surfel of that
// surface, and the per-cell merge of the views keeps it at most once.
#ifndef CAMERA_SURFELS
#define CAMERA_SURFELS 0
#endif

#if defined VERTEX_SHADER

#include "grid.glsl"
#include "lpv_corrections.glsl"

flat out ivec3 v_cell;
flat out int v_keep;
flat out vec3 v_normal;
flat out float v_area;
flat out vec3 v_albedo;

#if CAMERA_SURFELS

#include "light_map.glsl"

uniform sampler2D u_surfel_position;   // G-buffer position (w = 1 where a surface was seen)
uniform sampler2D u_surfel_normal;     // G-buffer normal, facing the camera
uniform sampler2D u_surfel_albedo;     // G-buffer albedo
uniform mat4 u_camera_view;
uniform float u_pixel_area;            // a pixel's area at view depth 1

// Whether RSM view `light` holds this surface: the light reaches the point within the
// largest depth difference between a plane's point and its texel's centre,
// (√2/2)·texel·tan θ (derivation occlusion.reprojection_depth_bound; tan θ capped at 10,
// grazing light).
bool seen_by_view(int light, vec3 position, vec3 normal) {
    vec3 to_light = light_is_orthographic(light)
                  ? -u_lights[light].axis_power.xyz
                  : normalize(u_lights[light].position_kind.xyz - position);
    float cos_light = max(abs(dot(normal, to_light)), 1e-6);
    float tangent = min(sqrt(max(1.0 - cos_light * cos_light, 0.0)) / cos_light, 10.0);
    return light_map_reaches(light, position, 0.5 * sqrt(2.0) * tangent);
}

// Whether any RSM view holds this surface.
bool seen_by_lights(vec3 position, vec3 normal) {
    for (int light = 0; light < u_light_count; ++light) {
        if (seen_by_view(light, position, normal)) {
            return true;
        }
    }
    return false;
}

void main() {
    int width = textureSize(u_surfel_position, 0).x;
    ivec2 pixel = ivec2(gl_VertexID % width, gl_VertexID / width);
    vec4 position = texelFetch(u_surfel_position, pixel, 0);
    v_normal = texelFetch(u_surfel_normal, pixel, 0).xyz;
    float depth = -(u_camera_view * vec4(position.xyz, 1.0)).z;
    v_cell = ivec3(floor(grid_coords(position.xyz) + 0.5));
    v_keep = int(position.w > 0.5 && grid_inside(v_cell, u_grid_cells + 1)
                 && !seen_by_lights(position.xyz, v_normal));
    v_area = u_pixel_area * (u_surfel_area_squared ? depth * depth : depth)
           / (u_grid_cell_size * u_grid_cell_size);
    v_albedo = texelFetch(u_surfel_albedo, pixel, 0).rgb;
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}

#else

#include "vpl.glsl"

uniform float u_vpl_texel_area;
uniform bool u_vpl_orthographic;

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
    v_keep = int(vpl.valid && grid_inside(v_cell, u_grid_cells + 1));
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

#endif  // CAMERA_SURFELS

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
    vec2 ndc = (vec2(v_cell[0].xy) + 0.5) / vec2(u_grid_cells.xy + 1) * 2.0 - 1.0;
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
