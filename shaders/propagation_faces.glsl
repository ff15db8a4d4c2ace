#version 430 core
// The 6 neighbour directions and the 5 faces per neighbour of the propagation step
// (docs/MODEL.md "Propagation"), shared by propagate.glsl (gather) and its audit.
//
// Direction d (index 0..5: +x, -x, +y, -y, +z, -z) has the frame (d, u, v) with u, v the two
// other axes (any frame gives the same sums). The front face of the target has normal d and
// is evaluated along d; the side faces have normals +u, -u, +v, -v and are evaluated along
// side/sqrt(5) + 2d/sqrt(5), the direction from the source centre to the side face's centre.
// The target cell x gathers from the source x - d. Light vectors are ShVec (sh.glsl:
// L1 or L2 after SH_ORDER); the geometry volume stays L1 (vec4).
#ifndef PROPAGATION_FACES_GLSL
#define PROPAGATION_FACES_GLSL 1

#include "sh.glsl"
#include "lpv_corrections.glsl"

const ivec3 LPV_DIRECTIONS[6] = ivec3[6](
    ivec3(1, 0, 0), ivec3(-1, 0, 0),
    ivec3(0, 1, 0), ivec3(0, -1, 0),
    ivec3(0, 0, 1), ivec3(0, 0, -1));
const ivec3 LPV_TANGENT_U[6] = ivec3[6](
    ivec3(0, 1, 0), ivec3(0, 1, 0),
    ivec3(0, 0, 1), ivec3(0, 0, 1),
    ivec3(1, 0, 0), ivec3(1, 0, 0));
const ivec3 LPV_TANGENT_V[6] = ivec3[6](
    ivec3(0, 0, 1), ivec3(0, 0, 1),
    ivec3(1, 0, 0), ivec3(1, 0, 0),
    ivec3(0, 1, 0), ivec3(0, 1, 0));

// Intensity -> reprojected SH scale of a face, without visibility: k_R * k_I * k_P * dw_f,
// or with model_face_weights off the DX11 shader's dw_front/(2 pi) (DX11_FRONT_SHARE / pi).
float lpv_front_face_weight() {
    if (!u_model_face_weights) {
        return DX11_FRONT_SHARE / lpv_pi() * lpv_front_solid_angle();
    }
    return lpv_reprojection_factor() * lpv_injection_factor() * lpv_propagation_factor()
        * lpv_front_solid_angle();
}

// The same for a side face (DX11: dw_side/(3 pi)); 0 when side faces are switched off.
float lpv_side_face_weight() {
    if (!u_side_faces) {
        return 0.0;
    }
    if (!u_model_face_weights) {
        return DX11_SIDE_SHARE / lpv_pi() * lpv_side_solid_angle();
    }
    return lpv_reprojection_factor() * lpv_injection_factor() * lpv_propagation_factor()
        * lpv_side_solid_angle();
}

// Geometry volume: (N+1)^3 texels, texel j centred on light-grid corner j. Whether there is
// one is chosen when the program is compiled (PROPAGATE_GEOMETRY, like the other code paths
// of propagate.glsl), so a grid without one fetches nothing for it.
#ifndef PROPAGATE_GEOMETRY
#define PROPAGATE_GEOMETRY 0
#endif
uniform sampler3D u_geometry;

// Mean geometry SH over the face shared by `target` and its source target - d (frame d, u, v).
// Along the axis of d that face is at corner target (d > 0) or target + 1 (d < 0); valid for
// targets one cell outside the grid too (the face is then on the grid boundary).
vec4 lpv_face_blocker(ivec3 target, ivec3 d, ivec3 u, ivec3 v) {
#if !PROPAGATE_GEOMETRY
    return vec4(0.0);
#endif
    ivec3 corner = target + max(-d, ivec3(0));
    return 0.25 * (texelFetch(u_geometry, corner, 0) + texelFetch(u_geometry, corner + u, 0)
                 + texelFetch(u_geometry, corner + v, 0)
                 + texelFetch(u_geometry, corner + u + v, 0));
}

// The same for direction index `dir`.
vec4 lpv_shared_face_blocker(ivec3 target, int dir) {
    return lpv_face_blocker(target, LPV_DIRECTIONS[dir], LPV_TANGENT_U[dir], LPV_TANGENT_V[dir]);
}

// How a face's blocking tau = <blocker, Y(-e_f)> becomes its visibility (compiled in from
// Settings.geometry_visibility): 0 linear V = 1 - clamp(tau, 0, 1) (the LPV paper's), 1
// statistical V = exp(-max(tau, 0)), the chance that a ray passes surfels placed
// independently at random (derivation occlusion.statistical_visibility).
#ifndef PROPAGATE_VISIBILITY
#define PROPAGATE_VISIBILITY 0
#endif

float lpv_visibility(float tau) {
#if PROPAGATE_VISIBILITY == 1
    return exp(-max(tau, 0.0));
#else
    return 1.0 - clamp(tau, 0.0, 1.0);
#endif
}

// Flux budget (Settings.flux_budget, docs/MODEL.md "Flux budget"): every face of a source
// cell sends lpv_budget * clamp+(I_f), lpv_budget the source's factor min(1, Phi / S) with
// S the flux of all its faces clamp+ (written per cell by the budget pass of propagate.glsl,
// read by load_source), so no cell sends more than it holds and no face negative light.
#ifndef PROPAGATE_FLUX_BUDGET
#define PROPAGATE_FLUX_BUDGET 0
#endif
vec3 lpv_budget = vec3(1.0);

// Audit terms of a step, per channel, in watts.
struct LpvAudit {
    vec3 clamp_gain;   // flux added by clamp+ (front faces; every face under the budget)
    vec3 occluded;     // flux removed by the geometry volume (1 - V_f)
    vec3 border;       // flux sent to targets outside the grid
    vec3 withheld;     // flux the flux budget kept back: (1 - lpv_budget) * clamp+(I_f)
};

// The axis of a face's reprojected cosine lobe (Settings.reprojection, docs/MODEL.md
// "Propagation"): PROPAGATE_REPROJECTION 0 the face's normal (the LPV paper's), 1 the unit
// direction from the source cell's centre to the face's centre, which is the face's
// evaluation direction e_f: the light keeps the way it crossed the face. A cosine lobe's
// flux does not depend on its axis, so the step's flux and its audit are the same.
#ifndef PROPAGATE_REPROJECTION
#define PROPAGATE_REPROJECTION 0
#endif
vec3 lpv_reprojection_axis(vec3 normal, vec3 towards_centre) {
#if PROPAGATE_REPROJECTION == 1
    return towards_centre;
#else
    return normal;
#endif
}

// One face (docs/MODEL.md "Propagation"):
//     I_f = <s, Y(e_f)> (clamp+ when `clamped`),  V_f = 1 - clamp(<blocker, Y(-e_f)>, 0, 1),
//     received += weight * I_f * V_f * lobe(r_f)   (when the target is inside the grid).
// The flux of a reprojected lobe scale*lobe(r) is sh_flux(scale * lobe(r)).
void lpv_send_face(ShVec source[3], vec3 eval_direction, vec3 reprojection, float weight,
                   bool clamped, vec4 blocker, bool leaving, inout ShVec received[3],
                   inout LpvAudit audit) {
    ShVec basis = shv_eval(eval_direction);
    ShVec lobe = shv_cosine_lobe(reprojection);
    vec3 raw = vec3(sh_dot(source[0], basis), sh_dot(source[1], basis),
                    sh_dot(source[2], basis));
#if PROPAGATE_FLUX_BUDGET
    vec3 unbudgeted = max(raw, vec3(0.0));
    vec3 used = lpv_budget * unbudgeted;
#else
    vec3 used = clamped ? max(raw, vec3(0.0)) : raw;
    vec3 unbudgeted = used;
#endif
    // A surfel blocks light that runs into its front side, i.e. travels against its normal:
    // the blocker lobe is evaluated at -e_f, so a lit wall does not shadow its own bounce.
#if PROPAGATE_GEOMETRY
    vec4 against = sh_eval(-eval_direction);
    float visibility = lpv_visibility(dot(blocker, against));
#else
    float visibility = 1.0;
#endif
    float flux_per_intensity = weight * sh_flux(lobe);
    audit.clamp_gain += flux_per_intensity * (unbudgeted - raw);
    audit.withheld += flux_per_intensity * (unbudgeted - used);
    audit.occluded += flux_per_intensity * (1.0 - visibility) * used;
    if (leaving) {
        audit.border += flux_per_intensity * visibility * used;
    } else {
        ShVec scaled = sh_scale(lobe, weight * visibility);
        received[0] = sh_add(received[0], sh_scale(scaled, used.r));
        received[1] = sh_add(received[1], sh_scale(scaled, used.g));
        received[2] = sh_add(received[2], sh_scale(scaled, used.b));
    }
}

// Light one source cell (SH vectors `source`: r, g, b) sends through the faces of its
// neighbour `target` = source + d (frame d, u, v): the front face, then the four side faces.
// propagate.glsl calls it with constant frames, one call per neighbour, so that the
// compiler folds Y(e_f) and lobe(r_f) of every face into constants (a loop over an index
// into LPV_DIRECTIONS kept them as run-time arithmetic and cost llvmpipe about 2x).
void lpv_send_frame(ShVec source[3], ivec3 target, ivec3 d_cells, ivec3 u_cells,
                    ivec3 v_cells, bool leaving, float front_weight, float side_weight,
                    inout ShVec received[3], inout LpvAudit audit) {
    vec4 blocker = lpv_face_blocker(target, d_cells, u_cells, v_cells);
    vec3 d = vec3(d_cells);
    lpv_send_face(source, d, d, front_weight, u_clamp_front_face, blocker, leaving,
                  received, audit);
    if (side_weight == 0.0) {
        return;
    }
    vec3 u = vec3(u_cells);
    vec3 v = vec3(v_cells);
    vec3 towards_front = SIDE_EVAL_BIG * d;
    vec3 side_u = towards_front + SIDE_EVAL_SMALL * u;
    vec3 side_minus_u = towards_front - SIDE_EVAL_SMALL * u;
    vec3 side_v = towards_front + SIDE_EVAL_SMALL * v;
    vec3 side_minus_v = towards_front - SIDE_EVAL_SMALL * v;
    lpv_send_face(source, side_u, lpv_reprojection_axis(u, side_u), side_weight, false,
                  blocker, leaving, received, audit);
    lpv_send_face(source, side_minus_u, lpv_reprojection_axis(-u, side_minus_u), side_weight,
                  false, blocker, leaving, received, audit);
    lpv_send_face(source, side_v, lpv_reprojection_axis(v, side_v), side_weight, false,
                  blocker, leaving, received, audit);
    lpv_send_face(source, side_minus_v, lpv_reprojection_axis(-v, side_minus_v), side_weight,
                  false, blocker, leaving, received, audit);
}

// 26 neighbours (docs/MODEL.md "26 neighbours", derivations/neighbours26.py): the source
// target - o sends through the faces of its neighbour `target` that lie on the surface of the
// 3x3x3 block around the source, one per non-zero component i of the offset o: normal o_i e_i,
// evaluated towards the face centre (3 o_i along i, 2 o_j along the other non-zero j),
// solid angle front, edge or corner after how many components are non-zero. The blocker is
// the mean geometry over the corners source and target share (4, 2 or 1).
#ifndef PROPAGATE_NEIGHBOURS
#define PROPAGATE_NEIGHBOURS 6
#endif

vec4 lpv_shared_corner_blocker(ivec3 target, ivec3 o) {
#if !PROPAGATE_GEOMETRY
    return vec4(0.0);
#endif
    ivec3 base = target + max(-o, ivec3(0));
    ivec3 free_axes = ivec3(equal(o, ivec3(0)));
    vec4 total = vec4(0.0);
    float count = 0.0;
    for (int k = 0; k < 8; ++k) {
        ivec3 step = ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        if (any(greaterThan(step, free_axes))) {
            continue;
        }
        total += texelFetch(u_geometry, base + step, 0);
        count += 1.0;
    }
    return total / count;
}

// The solid angle of an outer face of the 3x3x3 block: front, edge or corner after how
// many components of the offset o are non-zero (derivations/neighbours26.py).
float lpv_offset_solid_angle(ivec3 o) {
    int nonzero = int(o.x != 0) + int(o.y != 0) + int(o.z != 0);
    return nonzero == 1 ? FRONT_FACE_SOLID_ANGLE
         : (nonzero == 2 ? EDGE_FACE_SOLID_ANGLE : CORNER_FACE_SOLID_ANGLE);
}

// The centre of the outer face along `axis` of the neighbour at offset o: 3 o_i along the
// face's axis, 2 o_j along the other non-zero components.
vec3 lpv_offset_face_centre(vec3 offset, int axis) {
    vec3 centre = 2.0 * offset;
    centre[axis] = 3.0 * offset[axis];
    return centre;
}

void lpv_send_offset(ShVec source[3], ivec3 target, ivec3 o, bool leaving,
                     inout ShVec received[3], inout LpvAudit audit) {
    int nonzero = int(o.x != 0) + int(o.y != 0) + int(o.z != 0);
    float weight = lpv_reprojection_factor() * lpv_injection_factor()
        * lpv_propagation_factor() * lpv_offset_solid_angle(o);
    vec4 blocker = lpv_shared_corner_blocker(target, o);
    vec3 offset = vec3(o);
    for (int axis = 0; axis < 3; ++axis) {
        if (o[axis] == 0) {
            continue;
        }
        vec3 centre = lpv_offset_face_centre(offset, axis);
        vec3 normal = vec3(0.0);
        normal[axis] = offset[axis];
        vec3 towards_centre = normalize(centre);
        lpv_send_face(source, towards_centre, lpv_reprojection_axis(normal, towards_centre),
                      weight, nonzero == 1 && u_clamp_front_face, blocker, leaving, received,
                      audit);
    }
}

// S of the flux budget: the flux the source sends through all its faces, each clamp+,
// before visibility (the faces of lpv_send_frame or lpv_send_offset for every neighbour).
vec3 lpv_positive_outflux(ShVec source[3]) {
    float lobe_flux = sh_flux(shv_cosine_lobe(vec3(0.0, 0.0, 1.0)));
    vec3 total = vec3(0.0);
#if PROPAGATE_NEIGHBOURS == 26
    float scale = lpv_reprojection_factor() * lpv_injection_factor()
        * lpv_propagation_factor();
    for (int k = 0; k < 27; ++k) {
        ivec3 o = ivec3(k % 3, (k / 3) % 3, k / 9) - ivec3(1);
        if (o == ivec3(0)) {
            continue;
        }
        float angle = lpv_offset_solid_angle(o);
        vec3 offset = vec3(o);
        for (int axis = 0; axis < 3; ++axis) {
            if (o[axis] == 0) {
                continue;
            }
            ShVec basis = shv_eval(normalize(lpv_offset_face_centre(offset, axis)));
            total += scale * angle * lobe_flux * max(vec3(sh_dot(source[0], basis),
                sh_dot(source[1], basis), sh_dot(source[2], basis)), vec3(0.0));
        }
    }
#else
    float front_weight = lpv_front_face_weight();
    float side_weight = lpv_side_face_weight();
    for (int dir = 0; dir < 6; ++dir) {
        vec3 d = vec3(LPV_DIRECTIONS[dir]);
        vec3 u = vec3(LPV_TANGENT_U[dir]);
        vec3 v = vec3(LPV_TANGENT_V[dir]);
        vec3 directions[5] = vec3[5](d, SIDE_EVAL_BIG * d + SIDE_EVAL_SMALL * u,
                                     SIDE_EVAL_BIG * d - SIDE_EVAL_SMALL * u,
                                     SIDE_EVAL_BIG * d + SIDE_EVAL_SMALL * v,
                                     SIDE_EVAL_BIG * d - SIDE_EVAL_SMALL * v);
        for (int f = 0; f < 5; ++f) {
            ShVec basis = shv_eval(directions[f]);
            float weight = f == 0 ? front_weight : side_weight;
            total += weight * lobe_flux * max(vec3(sh_dot(source[0], basis),
                sh_dot(source[1], basis), sh_dot(source[2], basis)), vec3(0.0));
        }
    }
#endif
    return total;
}

// The same for direction index `dir` (the audit's border faces, the reflection).
void lpv_send(ShVec source[3], ivec3 target, int dir, bool leaving, float front_weight,
              float side_weight, inout ShVec received[3], inout LpvAudit audit) {
    lpv_send_frame(source, target, LPV_DIRECTIONS[dir], LPV_TANGENT_U[dir],
                   LPV_TANGENT_V[dir], leaving, front_weight, side_weight, received, audit);
}

#endif
