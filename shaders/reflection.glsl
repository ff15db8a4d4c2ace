#version 430 core
// More bounces (docs/MODEL.md "More bounces"): light that a propagation step sends from a
// cell towards a neighbour and that the geometry volume blocks is partly reflected back
// into the sending cell, as a clamped cosine lobe around the blocking surfels' normal,
// with flux = (area-weighted mean albedo of the shared face) x (blocked flux, clamp+).
// Included by propagate.glsl, which calls it only when compiled with PROPAGATE_REFLECT 1
// (Settings.bounces 2, with a geometry volume). Light vectors are
// ShVec (L1 or L2 after SH_ORDER, sh.glsl); the reflected lobe has the grid's order.
#ifndef REFLECTION_GLSL
#define REFLECTION_GLSL 1

#include "propagation_faces.glsl"

// (N+1)^3 texels like u_geometry: sum over the cell's surfels of (A/cell^2) * (albedo, 1).
uniform sampler3D u_geometry_albedo;

// Sums of the four geometry cells on the face shared by `target` and target - d (the same
// corners as lpv_shared_face_blocker); rgb / w is their area-weighted mean albedo.
vec4 lpv_shared_face_albedo(ivec3 target, int dir) {
    ivec3 corner = target + max(-LPV_DIRECTIONS[dir], ivec3(0));
    ivec3 u = LPV_TANGENT_U[dir];
    ivec3 v = LPV_TANGENT_V[dir];
    return texelFetch(u_geometry_albedo, corner, 0) + texelFetch(u_geometry_albedo, corner + u, 0)
         + texelFetch(u_geometry_albedo, corner + v, 0)
         + texelFetch(u_geometry_albedo, corner + u + v, 0);
}

// Direction the reflected lobe points to: the blockers' mean normal (band 1 of a cosine lobe
// around n is (-c n.y, c n.z, -c n.x)) when it faces back towards the sending cell, else
// straight back (-d), e.g. for a double-sided volume, whose band 1 cancels.
vec3 lpv_reflection_normal(vec4 blocker, int dir) {
    vec3 normal = vec3(-blocker.w, -blocker.y, blocker.z);
    vec3 back = -vec3(LPV_DIRECTIONS[dir]);
    return dot(normal, back) > 0.0 ? normalize(normal) : back;
}

// Adds to `received` (this cell's next grid value) what the geometry volume reflects of
// the light `own` sends to its six neighbours. `blocked` sums the blocked flux [W] that
// can bounce (clamp+ per direction: blocking the negative lobe tail of L1 SH is no light
// arriving at a surface), `reflected` the flux reflected.
void lpv_reflect(ShVec own[3], ivec3 cell, float front_weight, float side_weight,
                 inout ShVec received[3], inout vec3 reflected, inout vec3 blocked) {
    for (int dir = 0; dir < 6; ++dir) {
        ivec3 target = cell + LPV_DIRECTIONS[dir];
        // The five faces towards `target`, sent as if leaving: only the audit is wanted,
        // whose `occluded` is exactly the flux the geometry volume takes from them.
        LpvAudit pair = LpvAudit(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        ShVec unused[3] = ShVec[3](SHV_ZERO, SHV_ZERO, SHV_ZERO);
        lpv_send(own, target, dir, true, front_weight, side_weight, unused, pair);
        vec3 bounced = max(pair.occluded, vec3(0.0));
        blocked += bounced;
        vec4 albedo_sum = lpv_shared_face_albedo(target, dir);
        if (albedo_sum.w <= 0.0) {
            continue;   // no albedo known on the face: nothing reflected
        }
        vec3 flux = albedo_sum.rgb / albedo_sum.w * bounced;
        ShVec lobe = shv_cosine_lobe(lpv_reflection_normal(
            lpv_shared_face_blocker(target, dir), dir));
        ShVec per_watt = sh_divide(lobe, sh_flux(lobe));
        received[0] = sh_add(received[0], sh_scale(per_watt, flux.r));
        received[1] = sh_add(received[1], sh_scale(per_watt, flux.g));
        received[2] = sh_add(received[2], sh_scale(per_watt, flux.b));
        reflected += flux;
    }
}

#endif
