#version 430 core
// One propagation step as a gather (docs/MODEL.md "Propagation"): every target cell x sums,
// over the 6 directions d and the faces of x seen from the source x - d,
//     k_R * k_I * k_P * dw_f * I_f * V_f * lobe(r_f),   I_f = <s, Y(e_f)> (front: clamp+).
// Ping-pong (u_ping_pong): read grid t-1 through samplers, write grid t, and add it to the
// accumulation acc (each invocation touches only its own acc texel: no race).
// In place (the DX11 shader): neighbours are read from the very image being written and the
// step is added to it, acc += P(acc). Invocations race: some neighbours are already updated
// when read, so the result depends on the GPU's invocation order. Kept to show the hazard.
#define IMAGE_FORMAT rgba32f

#if defined COMPUTE_SHADER

#include "grid.glsl"
#include "propagation_faces.glsl"

// 64 invocations: a 4x4x4 brick shares most neighbour reads in cache on real GPUs.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

// Image units are fixed by binding (moderngl cannot set image uniforms): targets 0..2,
// accumulation 3..5.
uniform sampler3D u_source_r;
uniform sampler3D u_source_g;
uniform sampler3D u_source_b;

layout(IMAGE_FORMAT, binding = 0) uniform image3D u_target_r;
layout(IMAGE_FORMAT, binding = 1) uniform image3D u_target_g;
layout(IMAGE_FORMAT, binding = 2) uniform image3D u_target_b;

layout(IMAGE_FORMAT, binding = 3) uniform image3D u_accumulated_r;
layout(IMAGE_FORMAT, binding = 4) uniform image3D u_accumulated_g;
layout(IMAGE_FORMAT, binding = 5) uniform image3D u_accumulated_b;

void load_source(ivec3 cell, out vec4 source[3]) {
    if (u_ping_pong) {
        source[0] = texelFetch(u_source_r, cell, 0);
        source[1] = texelFetch(u_source_g, cell, 0);
        source[2] = texelFetch(u_source_b, cell, 0);
    } else {
        source[0] = imageLoad(u_target_r, cell);
        source[1] = imageLoad(u_target_g, cell);
        source[2] = imageLoad(u_target_b, cell);
    }
}

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    if (!grid_inside(cell)) {
        return;
    }
    vec4 gathered[3] = vec4[3](vec4(0.0), vec4(0.0), vec4(0.0));
    for (int dir = 0; dir < 6; ++dir) {
        ivec3 source_cell = cell - LPV_DIRECTIONS[dir];
        if (!grid_inside(source_cell)) {
            continue;  // nothing enters from outside the grid
        }
        vec4 source[3];
        load_source(source_cell, source);
        vec4 blocker = lpv_shared_face_blocker(cell, dir);
        for (int face = 0; face < lpv_face_count(); ++face) {
            float weight = lpv_face_weight(face) * lpv_face_visibility(blocker, dir, face);
            vec4 lobe = weight * sh_cosine_lobe(lpv_face_reprojection_direction(dir, face));
            for (int channel = 0; channel < 3; ++channel) {
                gathered[channel] += lpv_face_intensity(source[channel], dir, face) * lobe;
            }
        }
    }
    if (u_ping_pong) {
        imageStore(u_target_r, cell, gathered[0]);
        imageStore(u_target_g, cell, gathered[1]);
        imageStore(u_target_b, cell, gathered[2]);
        imageStore(u_accumulated_r, cell, imageLoad(u_accumulated_r, cell) + gathered[0]);
        imageStore(u_accumulated_g, cell, imageLoad(u_accumulated_g, cell) + gathered[1]);
        imageStore(u_accumulated_b, cell, imageLoad(u_accumulated_b, cell) + gathered[2]);
    } else {
        imageStore(u_target_r, cell, imageLoad(u_target_r, cell) + gathered[0]);
        imageStore(u_target_g, cell, imageLoad(u_target_g, cell) + gathered[1]);
        imageStore(u_target_b, cell, imageLoad(u_target_b, cell) + gathered[2]);
    }
}

#endif
