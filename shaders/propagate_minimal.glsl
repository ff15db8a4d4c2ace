#version 430 core
// The least one propagation step needs (docs/MODEL.md "Propagation"): the baseline that
// `lpv-explorer bench` times propagate.glsl against, in the same run.
// Every target cell x gathers, over the 6 directions d, from the source x - d through the
// front face and the four side faces of x:
//     received += w_f * clamp+(I_f) (front face) or w_f * I_f (side faces) * V_f * lobe(r_f),
//     I_f = <s, Y(e_f)>,  V_f = 1 - clamp(<blocker, Y(-e_f)>, 0, 1),
// and writes grid t (ping-pong: reads grid t-1 through samplers) and acc += grid t.
// Only the corrected, L1, ping-pong, one-bounce form: no switches, no audit, no
// reflection. With the corrected switches (front-face clamp on) it computes what
// propagate.glsl computes (tests/test_pass_propagate.py checks it).
#define IMAGE_FORMAT rgba32f

#if defined COMPUTE_SHADER

#include "grid.glsl"
#include "sh.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

uniform sampler3D u_source_r;
uniform sampler3D u_source_g;
uniform sampler3D u_source_b;
uniform sampler3D u_geometry;      // (N+1)^3 texels centred on the light grid's corners
uniform bool u_use_geometry;

// k_R k_I k_P dw_f with the corrected factors: k_R k_I k_P = 1/pi.
const float FRONT_WEIGHT = FRONT_FACE_SOLID_ANGLE * INV_PI;
const float SIDE_WEIGHT = SIDE_FACE_SOLID_ANGLE * INV_PI;

layout(IMAGE_FORMAT, binding = 0) uniform writeonly image3D u_target_r;
layout(IMAGE_FORMAT, binding = 1) uniform writeonly image3D u_target_g;
layout(IMAGE_FORMAT, binding = 2) uniform writeonly image3D u_target_b;
layout(IMAGE_FORMAT, binding = 3) uniform image3D u_accumulated_r;
layout(IMAGE_FORMAT, binding = 4) uniform image3D u_accumulated_g;
layout(IMAGE_FORMAT, binding = 5) uniform image3D u_accumulated_b;

const ivec3 DIRECTIONS[6] = ivec3[6](ivec3(1, 0, 0), ivec3(-1, 0, 0), ivec3(0, 1, 0),
                                     ivec3(0, -1, 0), ivec3(0, 0, 1), ivec3(0, 0, -1));
const ivec3 TANGENT_U[6] = ivec3[6](ivec3(0, 1, 0), ivec3(0, 1, 0), ivec3(0, 0, 1),
                                    ivec3(0, 0, 1), ivec3(1, 0, 0), ivec3(1, 0, 0));
const ivec3 TANGENT_V[6] = ivec3[6](ivec3(0, 0, 1), ivec3(0, 0, 1), ivec3(1, 0, 0),
                                    ivec3(1, 0, 0), ivec3(0, 1, 0), ivec3(0, 1, 0));

vec4 r_sum = vec4(0.0);
vec4 g_sum = vec4(0.0);
vec4 b_sum = vec4(0.0);

void face(vec4 sr, vec4 sg, vec4 sb, vec4 blocker, vec3 eval_direction, vec3 normal,
          float weight, bool clamped) {
    vec4 basis = sh_eval(eval_direction);
    vec3 intensity = vec3(dot(sr, basis), dot(sg, basis), dot(sb, basis));
    if (clamped) {
        intensity = max(intensity, vec3(0.0));
    }
    float visibility = 1.0 - clamp(dot(blocker, sh_eval(-eval_direction)), 0.0, 1.0);
    vec4 lobe = sh_cosine_lobe(normal) * (weight * visibility);
    r_sum += lobe * intensity.r;
    g_sum += lobe * intensity.g;
    b_sum += lobe * intensity.b;
}

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    if (!grid_inside(cell)) {
        return;
    }
    for (int dir = 0; dir < 6; ++dir) {
        ivec3 source = cell - DIRECTIONS[dir];
        if (!grid_inside(source)) {
            continue;
        }
        vec4 sr = texelFetch(u_source_r, source, 0);
        vec4 sg = texelFetch(u_source_g, source, 0);
        vec4 sb = texelFetch(u_source_b, source, 0);
        ivec3 u = TANGENT_U[dir];
        ivec3 v = TANGENT_V[dir];
        vec4 blocker = vec4(0.0);
        if (u_use_geometry) {
            ivec3 corner = cell + max(-DIRECTIONS[dir], ivec3(0));
            blocker = 0.25 * (texelFetch(u_geometry, corner, 0)
                            + texelFetch(u_geometry, corner + u, 0)
                            + texelFetch(u_geometry, corner + v, 0)
                            + texelFetch(u_geometry, corner + u + v, 0));
        }
        vec3 d = vec3(DIRECTIONS[dir]);
        vec3 fu = vec3(u);
        vec3 fv = vec3(v);
        face(sr, sg, sb, blocker, d, d, FRONT_WEIGHT, true);
        face(sr, sg, sb, blocker, SIDE_EVAL_BIG * d + SIDE_EVAL_SMALL * fu, fu,
             SIDE_WEIGHT, false);
        face(sr, sg, sb, blocker, SIDE_EVAL_BIG * d - SIDE_EVAL_SMALL * fu, -fu,
             SIDE_WEIGHT, false);
        face(sr, sg, sb, blocker, SIDE_EVAL_BIG * d + SIDE_EVAL_SMALL * fv, fv,
             SIDE_WEIGHT, false);
        face(sr, sg, sb, blocker, SIDE_EVAL_BIG * d - SIDE_EVAL_SMALL * fv, -fv,
             SIDE_WEIGHT, false);
    }
    imageStore(u_target_r, cell, r_sum);
    imageStore(u_target_g, cell, g_sum);
    imageStore(u_target_b, cell, b_sum);
    imageStore(u_accumulated_r, cell, imageLoad(u_accumulated_r, cell) + r_sum);
    imageStore(u_accumulated_g, cell, imageLoad(u_accumulated_g, cell) + g_sum);
    imageStore(u_accumulated_b, cell, imageLoad(u_accumulated_b, cell) + b_sum);
}

#endif
