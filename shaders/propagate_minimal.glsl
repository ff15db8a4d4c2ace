#version 430 core
// The least one propagation step needs (docs/MODEL.md "Propagation"): the baseline that
// `lpv-explorer bench` times propagate.glsl against, in the same run. Every target cell x
// gathers, from each of its 6 neighbours x - d, through the front face and the four side
// faces of x:
//     received += w_f * clamp+(I_f) (front) or w_f * I_f (sides) * V_f * lobe(r_f),
//     I_f = <s, Y(e_f)>,  V_f = 1 - clamp(<blocker, Y(-e_f)>, 0, 1),
// writes grid t (reads grid t-1 with texelFetch) and adds it into the accumulation.
// Only the corrected, L1, ping-pong, one-bounce form: no switches, no audit, no reflection,
// the geometry volume compiled in only when there is one (PROPAGATE_GEOMETRY). Each neighbour is
// written out with its constant direction and tangents, so Y(e_f) and lobe(r_f) of the
// five faces fold into the generated constants at compile time. With the corrected
// switches it computes what propagate.glsl computes (tests/lpv/passes/test_pass_propagate.py).
#define IMAGE_FORMAT rgba32f
#define PROPAGATE_GEOMETRY 0

#if defined COMPUTE_SHADER

#include "sh.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

uniform ivec3 u_grid_cells;       // (nx, ny, nz)
uniform sampler3D u_source_r;
uniform sampler3D u_source_g;
uniform sampler3D u_source_b;
uniform sampler3D u_geometry;      // (nx+1)(ny+1)(nz+1) texels centred on the light grid's corners

layout(IMAGE_FORMAT, binding = 0) uniform writeonly image3D u_target_r;
layout(IMAGE_FORMAT, binding = 1) uniform writeonly image3D u_target_g;
layout(IMAGE_FORMAT, binding = 2) uniform writeonly image3D u_target_b;
layout(IMAGE_FORMAT, binding = 3) uniform image3D u_accumulated_r;
layout(IMAGE_FORMAT, binding = 4) uniform image3D u_accumulated_g;
layout(IMAGE_FORMAT, binding = 5) uniform image3D u_accumulated_b;

// k_R k_I k_P dw_f with the corrected factors: k_R k_I k_P = 1/pi.
const float FRONT_WEIGHT = FRONT_FACE_SOLID_ANGLE * INV_PI;
const float SIDE_WEIGHT = SIDE_FACE_SOLID_ANGLE * INV_PI;

void face(vec4 sr, vec4 sg, vec4 sb, vec4 blocker, vec3 eval_direction, vec3 normal,
          float weight, bool clamped, inout vec4 r, inout vec4 g, inout vec4 b) {
    vec4 basis = sh_eval(eval_direction);
    vec3 intensity = vec3(dot(sr, basis), dot(sg, basis), dot(sb, basis));
    if (clamped) {
        intensity = max(intensity, vec3(0.0));
    }
#if PROPAGATE_GEOMETRY
    weight *= 1.0 - clamp(dot(blocker, sh_eval(-eval_direction)), 0.0, 1.0);
#endif
    vec4 lobe = sh_cosine_lobe(normal) * weight;
    r += lobe * intensity.r;
    g += lobe * intensity.g;
    b += lobe * intensity.b;
}

// The light of the source cell - d through the five faces of `cell` (d, u, v constant).
void neighbour(ivec3 cell, ivec3 d, ivec3 u, ivec3 v, inout vec4 r, inout vec4 g,
               inout vec4 b) {
    ivec3 source = cell - d;
    vec4 sr = texelFetch(u_source_r, source, 0);
    vec4 sg = texelFetch(u_source_g, source, 0);
    vec4 sb = texelFetch(u_source_b, source, 0);
    vec4 blocker = vec4(0.0);
#if PROPAGATE_GEOMETRY
    ivec3 corner = cell + max(-d, ivec3(0));
    blocker = 0.25 * (texelFetch(u_geometry, corner, 0) + texelFetch(u_geometry, corner + u, 0)
                    + texelFetch(u_geometry, corner + v, 0)
                    + texelFetch(u_geometry, corner + u + v, 0));
#endif
    vec3 fd = vec3(d);
    vec3 fu = vec3(u);
    vec3 fv = vec3(v);
    vec3 big = SIDE_EVAL_BIG * fd;
    face(sr, sg, sb, blocker, fd, fd, FRONT_WEIGHT, true, r, g, b);
    face(sr, sg, sb, blocker, big + SIDE_EVAL_SMALL * fu, fu, SIDE_WEIGHT, false, r, g, b);
    face(sr, sg, sb, blocker, big - SIDE_EVAL_SMALL * fu, -fu, SIDE_WEIGHT, false, r, g, b);
    face(sr, sg, sb, blocker, big + SIDE_EVAL_SMALL * fv, fv, SIDE_WEIGHT, false, r, g, b);
    face(sr, sg, sb, blocker, big - SIDE_EVAL_SMALL * fv, -fv, SIDE_WEIGHT, false, r, g, b);
}

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    ivec3 last = u_grid_cells - 1;
    if (any(greaterThan(cell, last))) {
        return;
    }
    vec4 r = vec4(0.0);
    vec4 g = vec4(0.0);
    vec4 b = vec4(0.0);
    // nothing enters from outside the grid: only the neighbours inside are read
    if (cell.x > 0) neighbour(cell, ivec3(1, 0, 0), ivec3(0, 1, 0), ivec3(0, 0, 1), r, g, b);
    if (cell.x < last.x) neighbour(cell, ivec3(-1, 0, 0), ivec3(0, 1, 0), ivec3(0, 0, 1), r, g, b);
    if (cell.y > 0) neighbour(cell, ivec3(0, 1, 0), ivec3(0, 0, 1), ivec3(1, 0, 0), r, g, b);
    if (cell.y < last.y) neighbour(cell, ivec3(0, -1, 0), ivec3(0, 0, 1), ivec3(1, 0, 0), r, g, b);
    if (cell.z > 0) neighbour(cell, ivec3(0, 0, 1), ivec3(1, 0, 0), ivec3(0, 1, 0), r, g, b);
    if (cell.z < last.z) neighbour(cell, ivec3(0, 0, -1), ivec3(1, 0, 0), ivec3(0, 1, 0), r, g, b);
    imageStore(u_target_r, cell, r);
    imageStore(u_target_g, cell, g);
    imageStore(u_target_b, cell, b);
    imageStore(u_accumulated_r, cell, imageLoad(u_accumulated_r, cell) + r);
    imageStore(u_accumulated_g, cell, imageLoad(u_accumulated_g, cell) + g);
    imageStore(u_accumulated_b, cell, imageLoad(u_accumulated_b, cell) + b);
}

#endif
