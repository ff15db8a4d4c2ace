#version 430 core
// Energy audit of one propagation step on the GPU (GridAudit, explorer/lpv/audit.py).
// AUDIT_STAGE 0: one invocation per cell computes 12 numbers, a 64-invocation workgroup sums
//   them in shared memory and writes one partial sum per workgroup:
//     [0..2]  flux of the grid "after" (or of after - before: the light one in-place step adds)
//     [3..5]  border loss:  flux the cell, as a source, sends to targets outside the grid
//     [6..8]  clamp gain:   flux its front faces gain by the clamp+ (used - raw intensity)
//     [9..11] occluded:     flux its faces lose to the geometry volume (1 - V_f)
//   The face terms use the same functions as propagate.glsl, in scatter form: for the source
//   cell s and direction d the target is s + d. Flux of a reprojected lobe:
//   sh_flux(weight * I * lobe(r)).
// AUDIT_STAGE 1: one workgroup sums the partials into 12 numbers at slot u_result_slot.
#define AUDIT_STAGE 0

#if defined COMPUTE_SHADER

layout(std430, binding = 2) buffer Partials { float partials[]; };
layout(std430, binding = 3) buffer Results { float results[]; };

const int AUDIT_VALUES = 12;

#if AUDIT_STAGE == 0

#include "grid.glsl"
#include "propagation_faces.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
const uint GROUP_SIZE = 64u;

uniform sampler3D u_before_r;
uniform sampler3D u_before_g;
uniform sampler3D u_before_b;
uniform sampler3D u_after_r;
uniform sampler3D u_after_g;
uniform sampler3D u_after_b;
uniform bool u_face_terms;            // false: only the flux of "after"
uniform bool u_after_minus_before;    // in-place steps: flux of after - before

shared float shared_sums[AUDIT_VALUES][GROUP_SIZE];

void cell_terms(ivec3 cell, out float values[AUDIT_VALUES]) {
    for (int i = 0; i < AUDIT_VALUES; ++i) {
        values[i] = 0.0;
    }
    if (!grid_inside(cell)) {
        return;
    }
    vec4 before[3] = vec4[3](texelFetch(u_before_r, cell, 0), texelFetch(u_before_g, cell, 0),
                             texelFetch(u_before_b, cell, 0));
    vec4 after[3] = vec4[3](texelFetch(u_after_r, cell, 0), texelFetch(u_after_g, cell, 0),
                            texelFetch(u_after_b, cell, 0));
    for (int channel = 0; channel < 3; ++channel) {
        vec4 counted = u_after_minus_before ? after[channel] - before[channel] : after[channel];
        values[channel] = sh_flux(counted);
    }
    if (!u_face_terms) {
        return;
    }
    for (int dir = 0; dir < 6; ++dir) {
        ivec3 target = cell + LPV_DIRECTIONS[dir];
        bool leaves = !grid_inside(target);
        vec4 blocker = lpv_shared_face_blocker(target, dir);
        for (int face = 0; face < lpv_face_count(); ++face) {
            vec3 reprojection = lpv_face_reprojection_direction(dir, face);
            float flux_per_intensity = lpv_face_weight(face)
                * sh_flux(sh_cosine_lobe(reprojection));
            float visibility = lpv_face_visibility(blocker, dir, face);
            for (int channel = 0; channel < 3; ++channel) {
                float raw = lpv_face_intensity_raw(before[channel], dir, face);
                float used = lpv_face_intensity(before[channel], dir, face);
                values[6 + channel] += flux_per_intensity * (used - raw);
                values[9 + channel] += flux_per_intensity * used * (1.0 - visibility);
                if (leaves) {
                    values[3 + channel] += flux_per_intensity * used * visibility;
                }
            }
        }
    }
}

void main() {
    float values[AUDIT_VALUES];
    cell_terms(ivec3(gl_GlobalInvocationID), values);
    uint lane = gl_LocalInvocationIndex;
    for (int i = 0; i < AUDIT_VALUES; ++i) {
        shared_sums[i][lane] = values[i];
    }
    barrier();
    for (uint stride = GROUP_SIZE / 2u; stride > 0u; stride /= 2u) {
        if (lane < stride) {
            for (int i = 0; i < AUDIT_VALUES; ++i) {
                shared_sums[i][lane] += shared_sums[i][lane + stride];
            }
        }
        barrier();
    }
    if (lane == 0u) {
        uvec3 groups = gl_NumWorkGroups;
        uint group = gl_WorkGroupID.x + groups.x * (gl_WorkGroupID.y + groups.y * gl_WorkGroupID.z);
        for (int i = 0; i < AUDIT_VALUES; ++i) {
            partials[group * uint(AUDIT_VALUES) + uint(i)] = shared_sums[i][0];
        }
    }
}

#else

layout(local_size_x = 256) in;
const uint GROUP_SIZE = 256u;

uniform int u_partial_count;
uniform int u_result_slot;

shared float shared_sums[AUDIT_VALUES][GROUP_SIZE];

void main() {
    uint lane = gl_LocalInvocationIndex;
    for (int i = 0; i < AUDIT_VALUES; ++i) {
        float sum = 0.0;
        for (uint group = lane; group < uint(u_partial_count); group += GROUP_SIZE) {
            sum += partials[group * uint(AUDIT_VALUES) + uint(i)];
        }
        shared_sums[i][lane] = sum;
    }
    barrier();
    for (uint stride = GROUP_SIZE / 2u; stride > 0u; stride /= 2u) {
        if (lane < stride) {
            for (int i = 0; i < AUDIT_VALUES; ++i) {
                shared_sums[i][lane] += shared_sums[i][lane + stride];
            }
        }
        barrier();
    }
    if (lane == 0u) {
        for (int i = 0; i < AUDIT_VALUES; ++i) {
            results[u_result_slot * AUDIT_VALUES + i] = shared_sums[i][0];
        }
    }
}

#endif
#endif
