#version 430 core
// The 6 neighbour directions and the 5 faces per neighbour of the propagation step
// (docs/MODEL.md "Propagation"), shared by propagate.glsl and audit_reduce.glsl so the audit
// measures exactly what the propagation does.
//
// Direction d (index 0..5: +x, -x, +y, -y, +z, -z) has the frame (d, u, v) with u, v the two
// other axes. Face 0 is the front face (normal d); faces 1..4 are the side faces with normals
// +u, -u, +v, -v. The target cell x gathers from the source x - d.
#ifndef PROPAGATION_FACES_GLSL
#define PROPAGATION_FACES_GLSL 1

#include "sh.glsl"
#include "lpv_corrections.glsl"

const ivec3 LPV_DIRECTIONS[6] = ivec3[6](
    ivec3(1, 0, 0), ivec3(-1, 0, 0),
    ivec3(0, 1, 0), ivec3(0, -1, 0),
    ivec3(0, 0, 1), ivec3(0, 0, -1));

const int LPV_FRONT_FACE = 0;

ivec3 lpv_axis(int axis) {
    return ivec3(equal(ivec3(0, 1, 2), ivec3(axis % 3)));
}

// Normal of the side face `face` (1..4) of direction `dir`: +u, -u, +v, -v.
vec3 lpv_side_normal(int dir, int face) {
    int axis = dir / 2;
    vec3 u = vec3(lpv_axis(axis + 1));
    vec3 v = vec3(lpv_axis(axis + 2));
    vec3 tangent = face <= 2 ? u : v;
    return (face % 2 == 1) ? tangent : -tangent;
}

// Direction at which the source's intensity is evaluated for the face: d for the front face,
// side/sqrt(5) + 2d/sqrt(5) (towards the side face's centre) for a side face.
vec3 lpv_face_eval_direction(int dir, int face) {
    vec3 d = vec3(LPV_DIRECTIONS[dir]);
    if (face == LPV_FRONT_FACE) {
        return d;
    }
    return SIDE_EVAL_SMALL * lpv_side_normal(dir, face) + SIDE_EVAL_BIG * d;
}

// Direction of the cosine lobe the face's flux is reprojected into: the face normal.
vec3 lpv_face_reprojection_direction(int dir, int face) {
    return face == LPV_FRONT_FACE ? vec3(LPV_DIRECTIONS[dir]) : lpv_side_normal(dir, face);
}

float lpv_face_solid_angle(int face) {
    return face == LPV_FRONT_FACE ? lpv_front_solid_angle() : lpv_side_solid_angle();
}

int lpv_face_count() {
    return u_side_faces ? 5 : 1;
}

// Intensity of one channel towards the face, before and after the front-face clamp.
float lpv_face_intensity_raw(vec4 source, int dir, int face) {
    return dot(source, sh_eval(lpv_face_eval_direction(dir, face)));
}

float lpv_face_intensity(vec4 source, int dir, int face) {
    float intensity = lpv_face_intensity_raw(source, dir, face);
    if (face == LPV_FRONT_FACE && u_clamp_front_face) {
        intensity = max(intensity, 0.0);
    }
    return intensity;
}

// Intensity -> reprojected SH scale of a face without visibility: k_R * k_I * k_P * dw_f.
float lpv_face_weight(int face) {
    return lpv_reprojection_factor() * lpv_injection_factor() * lpv_propagation_factor()
        * lpv_face_solid_angle(face);
}

// Geometry volume: (N+1)^3 texels, texel j centred on light-grid corner j.
uniform sampler3D u_geometry;
uniform bool u_use_geometry;

// Mean geometry SH over the face shared by `target` and its source target - d. Along the
// axis of d that face is at corner target (d > 0) or target + 1 (d < 0); valid for targets
// one cell outside the grid too (the face is then on the grid boundary).
vec4 lpv_shared_face_blocker(ivec3 target, int dir) {
    if (!u_use_geometry) {
        return vec4(0.0);
    }
    ivec3 d = LPV_DIRECTIONS[dir];
    ivec3 corner = target + max(-d, ivec3(0));
    ivec3 u = lpv_axis(dir / 2 + 1);
    ivec3 v = lpv_axis(dir / 2 + 2);
    return 0.25 * (texelFetch(u_geometry, corner, 0) + texelFetch(u_geometry, corner + u, 0)
                 + texelFetch(u_geometry, corner + v, 0)
                 + texelFetch(u_geometry, corner + u + v, 0));
}

// V_f = 1 - clamp(<blocker, Y(e_f)>, 0, 1).
float lpv_face_visibility(vec4 blocker, int dir, int face) {
    if (!u_use_geometry) {
        return 1.0;
    }
    float blocking = dot(blocker, sh_eval(lpv_face_eval_direction(dir, face)));
    return 1.0 - clamp(blocking, 0.0, 1.0);
}

#endif
