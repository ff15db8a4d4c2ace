#version 430 core
// One propagation step as a gather (docs/MODEL.md "Propagation"): every target cell x sums,
// over the 6 directions d and the faces of x seen from the source x - d (or, with
// PROPAGATE_NEIGHBOURS 26, over the 26 offsets o and x's outer faces on the source's 3x3x3 block),
//     k_R * k_I * k_P * dw_f * I_f * V_f * lobe(r_f),   I_f = <s, Y(e_f)> (front: clamp+).
// Ping-pong (the ping_pong switch, compiled in as PROPAGATE_PING_PONG 1): read grid t-1
// through samplers, write grid t, and add it to the accumulation acc (each invocation
// touches only its own acc texel: no race).
// In place (the DX11 shader): neighbours are read from the very image being written and the
// step is added to it, acc += P(acc). Invocations race: some neighbours are already updated
// when read, so the result depends on the GPU's invocation order. Kept to show the hazard.
// What it can produce (one value per schedule of neighbour reads) is
// explorer/lpv/twin/light_grid.py in_place_step_candidates.
//
// The same dispatch measures the step's energy audit (GridAudit): every cell writes 21
// numbers to `cell_terms` (layout of audit_reduce.glsl): the flux the step delivers into it,
// the clamp gain, occluded flux and flux withheld by the budget of the faces it gathers
// through, as a border cell the border loss and those terms of the faces it sends out of
// the grid, and the flux reflected back into it and the blocked flux that could bounce
// (reflection.glsl);
// explorer/lpv/twin/light_grid.py propagation_step_cells books them alike. audit_reduce.glsl sums
// them; a shared-memory reduction here would need barrier(), which costs llvmpipe more than
// the whole step. Each cell also adds its record to its own running sum over the steps in
// `cell_sums` (no other invocation touches it), which the window reads back for one picked
// cell (explorer/lpv/audit.py CellAuditRecords).
// SH_ORDER 2 propagates L2 vectors (9 coefficients, stored as in sh_grid.glsl): the same
// faces and weights, evaluated and reprojected with the L2 basis and lobe.
#define IMAGE_FORMAT rgba32f
#define SH_ORDER 1
#define PROPAGATE_AUDIT 1
// The code paths are chosen when the program is compiled, from the switches and settings
// (explorer/lpv/passes/propagate.py `program_defines`): the ping-pong switch, whether there is a
// geometry volume, whether it reflects (Settings.bounces 2) and the neighbourhood (6 or 26,
// Settings.neighbours). llvmpipe runs both sides of
// a branch on a uniform under a lane mask, so each untaken path cost its full work: with
// all three as uniforms the audit-off kernel took 2.5x the minimal kernel at 32^3
// (BENCHMARKS.md). The other switches only select factors and stay uniforms.
#define PROPAGATE_PING_PONG 1
#define PROPAGATE_GEOMETRY 0
#define PROPAGATE_REFLECT 0
#define PROPAGATE_NEIGHBOURS 6
#define PROPAGATE_VISIBILITY 0
#define PROPAGATE_FLUX_BUDGET 0
#define PROPAGATE_REPROJECTION 0
// PROPAGATE_BUDGET_PASS 1 compiles the flux budget's pass instead of the step: every cell of
// grid t-1 writes its factor min(1, Phi / S) (lpv_positive_outflux) to `budget_scale`, which
// the step, dispatched after it, reads for each source it gathers from.
#define PROPAGATE_BUDGET_PASS 0
// The units the step reads its source from (sampler units) and writes its target to (image
// units): 0..2 and 0..2 unless a run's second program of the same variant moves them
// (explorer/lpv/passes/propagate.py `EVEN_STEP_UNITS`: ping and pong each on units of
// their own, so that a run's steps bind nothing anew).
#define PROPAGATE_SOURCE_R 0
#define PROPAGATE_SOURCE_G 1
#define PROPAGATE_SOURCE_B 2
#define PROPAGATE_TARGET_R 0
#define PROPAGATE_TARGET_G 1
#define PROPAGATE_TARGET_B 2

#if defined COMPUTE_SHADER

#include "grid.glsl"
#include "sh_grid.glsl"
#include "propagation_faces.glsl"
#include "reflection.glsl"

// 64 invocations: a 4x4x4 brick shares most neighbour reads in cache on real GPUs.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
const int AUDIT_VALUES = 21;

layout(binding = PROPAGATE_SOURCE_R) uniform sampler3D u_source_r;
layout(binding = PROPAGATE_SOURCE_G) uniform sampler3D u_source_g;
layout(binding = PROPAGATE_SOURCE_B) uniform sampler3D u_source_b;

// Image units are fixed by binding (moderngl cannot set image uniforms): targets 0..2 (or
// the PROPAGATE_TARGET_* units), accumulation 3..5.
layout(IMAGE_FORMAT, binding = PROPAGATE_TARGET_R) uniform image3D u_target_r;
layout(IMAGE_FORMAT, binding = PROPAGATE_TARGET_G) uniform image3D u_target_g;
layout(IMAGE_FORMAT, binding = PROPAGATE_TARGET_B) uniform image3D u_target_b;
layout(IMAGE_FORMAT, binding = 3) uniform image3D u_accumulated_r;
layout(IMAGE_FORMAT, binding = 4) uniform image3D u_accumulated_g;
layout(IMAGE_FORMAT, binding = 5) uniform image3D u_accumulated_b;

// Per-cell audit terms, quantity-major: cell_terms[quantity * N^3 + linear cell index].
layout(std430, binding = 4) buffer CellTerms { float cell_terms[]; };
// Their sums over the steps so far, cell-major (one cell's record is 18 adjacent floats, one
// small read): cell_sums[linear cell index * 18 + quantity]. Zeroed before the first step.
layout(std430, binding = 5) buffer CellSums { float cell_sums[]; };

// The flux budget's factors, one per cell (rgb; linear cell index).
layout(std430, binding = 6) buffer BudgetScale { vec4 budget_scale[]; };

int linear_cell(ivec3 cell) {
    return cell.x + u_grid_cells.x * (cell.y + u_grid_cells.y * cell.z);
}

// Also sets the flux budget's factor of the cell (lpv_budget) for the faces it sends next.
void load_source(ivec3 cell, out ShVec source[3]) {
#if PROPAGATE_FLUX_BUDGET && !PROPAGATE_BUDGET_PASS
    lpv_budget = budget_scale[linear_cell(cell)].rgb;
#endif
#if PROPAGATE_PING_PONG
    source[0] = SH_FETCH(u_source_r, cell);
    source[1] = SH_FETCH(u_source_g, cell);
    source[2] = SH_FETCH(u_source_b, cell);
#else
    source[0] = SH_IMAGE_LOAD(u_target_r, cell);
    source[1] = SH_IMAGE_LOAD(u_target_g, cell);
    source[2] = SH_IMAGE_LOAD(u_target_b, cell);
#endif
}

// The light the source cell - d sends into `cell` through its five faces (frame d, u, v).
#define LPV_GATHER(inside, d, u, v) if (inside) { \
        ShVec source[3]; \
        load_source(cell - (d), source); \
        lpv_send_frame(source, cell, d, u, v, false, front_weight, side_weight, received, \
                       audit); \
    }

// The light the source cell - o sends into `cell` through its outer faces (26 neighbours).
#define LPV_GATHER26(o) if (grid_inside(cell - (o))) { \
        ShVec source[3]; \
        load_source(cell - (o), source); \
        lpv_send_offset(source, cell, o, false, received, audit); \
    }

void propagate_cell(ivec3 cell, out float audit_record[AUDIT_VALUES]) {
    float front_weight = lpv_front_face_weight();
    float side_weight = lpv_side_face_weight();
    ShVec received[3] = ShVec[3](SHV_ZERO, SHV_ZERO, SHV_ZERO);
    LpvAudit audit = LpvAudit(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
    // One call per neighbour with its constant frame (d, u, v), in the order of
    // LPV_DIRECTIONS; nothing enters from outside the grid.
    ivec3 last = u_grid_cells - 1;
#if PROPAGATE_NEIGHBOURS == 26
    // One call per offset with a constant o, as LPV_GATHER does for the six frames, so
    // that the compiler folds each face's directions, lobe and weight into constants.
    LPV_GATHER26(ivec3(-1, -1, -1));
    LPV_GATHER26(ivec3(0, -1, -1));
    LPV_GATHER26(ivec3(1, -1, -1));
    LPV_GATHER26(ivec3(-1, 0, -1));
    LPV_GATHER26(ivec3(0, 0, -1));
    LPV_GATHER26(ivec3(1, 0, -1));
    LPV_GATHER26(ivec3(-1, 1, -1));
    LPV_GATHER26(ivec3(0, 1, -1));
    LPV_GATHER26(ivec3(1, 1, -1));
    LPV_GATHER26(ivec3(-1, -1, 0));
    LPV_GATHER26(ivec3(0, -1, 0));
    LPV_GATHER26(ivec3(1, -1, 0));
    LPV_GATHER26(ivec3(-1, 0, 0));
    LPV_GATHER26(ivec3(1, 0, 0));
    LPV_GATHER26(ivec3(-1, 1, 0));
    LPV_GATHER26(ivec3(0, 1, 0));
    LPV_GATHER26(ivec3(1, 1, 0));
    LPV_GATHER26(ivec3(-1, -1, 1));
    LPV_GATHER26(ivec3(0, -1, 1));
    LPV_GATHER26(ivec3(1, -1, 1));
    LPV_GATHER26(ivec3(-1, 0, 1));
    LPV_GATHER26(ivec3(0, 0, 1));
    LPV_GATHER26(ivec3(1, 0, 1));
    LPV_GATHER26(ivec3(-1, 1, 1));
    LPV_GATHER26(ivec3(0, 1, 1));
    LPV_GATHER26(ivec3(1, 1, 1));
#else
    LPV_GATHER(cell.x > 0, ivec3(1, 0, 0), ivec3(0, 1, 0), ivec3(0, 0, 1));
    LPV_GATHER(cell.x < last.x, ivec3(-1, 0, 0), ivec3(0, 1, 0), ivec3(0, 0, 1));
    LPV_GATHER(cell.y > 0, ivec3(0, 1, 0), ivec3(0, 0, 1), ivec3(1, 0, 0));
    LPV_GATHER(cell.y < last.y, ivec3(0, -1, 0), ivec3(0, 0, 1), ivec3(1, 0, 0));
    LPV_GATHER(cell.z > 0, ivec3(0, 0, 1), ivec3(1, 0, 0), ivec3(0, 1, 0));
    LPV_GATHER(cell.z < last.z, ivec3(0, 0, -1), ivec3(1, 0, 0), ivec3(0, 1, 0));
#endif
#if PROPAGATE_AUDIT
    // A border cell is also the source of the faces that leave the grid (audit only).
    if (any(equal(cell, ivec3(0))) || any(equal(cell, u_grid_cells - 1))) {
        ShVec own[3];
        load_source(cell, own);
        ShVec unused[3] = ShVec[3](SHV_ZERO, SHV_ZERO, SHV_ZERO);
#if PROPAGATE_NEIGHBOURS == 26
        for (int k = 0; k < 27; ++k) {
            ivec3 o = ivec3(k % 3, (k / 3) % 3, k / 9) - ivec3(1);
            if (k != 13 && !grid_inside(cell + o)) {
                lpv_send_offset(own, cell + o, o, true, unused, audit);
            }
        }
#else
        for (int dir = 0; dir < 6; ++dir) {
            ivec3 outside = cell + LPV_DIRECTIONS[dir];
            if (!grid_inside(outside)) {
                lpv_send(own, outside, dir, true, front_weight, side_weight, unused, audit);
            }
        }
#endif
    }
#endif
    vec3 reflected = vec3(0.0);
    vec3 blocked = vec3(0.0);
#if PROPAGATE_REFLECT
    ShVec own[3];
    load_source(cell, own);
    lpv_reflect(own, cell, front_weight, side_weight, received, reflected, blocked);
#endif
#if PROPAGATE_PING_PONG
    {
        SH_IMAGE_STORE(u_target_r, cell, received[0]);
        SH_IMAGE_STORE(u_target_g, cell, received[1]);
        SH_IMAGE_STORE(u_target_b, cell, received[2]);
        SH_IMAGE_STORE(u_accumulated_r, cell,
                       sh_add(SH_IMAGE_LOAD(u_accumulated_r, cell), received[0]));
        SH_IMAGE_STORE(u_accumulated_g, cell,
                       sh_add(SH_IMAGE_LOAD(u_accumulated_g, cell), received[1]));
        SH_IMAGE_STORE(u_accumulated_b, cell,
                       sh_add(SH_IMAGE_LOAD(u_accumulated_b, cell), received[2]));
    }
#else
    SH_IMAGE_STORE(u_target_r, cell, sh_add(SH_IMAGE_LOAD(u_target_r, cell), received[0]));
    SH_IMAGE_STORE(u_target_g, cell, sh_add(SH_IMAGE_LOAD(u_target_g, cell), received[1]));
    SH_IMAGE_STORE(u_target_b, cell, sh_add(SH_IMAGE_LOAD(u_target_b, cell), received[2]));
#endif
    vec3 delivered = vec3(sh_flux(received[0]), sh_flux(received[1]), sh_flux(received[2]));
    vec3 terms[7] = vec3[7](delivered, audit.border, audit.clamp_gain, audit.occluded,
                            reflected, blocked, audit.withheld);
    for (int i = 0; i < AUDIT_VALUES; ++i) {
        audit_record[i] = terms[i / 3][i % 3];
    }
}

// First cell of this dispatch: a step is dispatched in slabs of z layers
// (explorer/lpv/passes/propagate.py `slabs`), each a unit of a time-sliced frame.
uniform ivec3 u_cell_offset;

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID) + u_cell_offset;
    if (any(greaterThanEqual(cell, u_grid_cells))) {
        return;
    }
#if PROPAGATE_BUDGET_PASS
    ShVec held[3];
    load_source(cell, held);
    vec3 flux = max(vec3(sh_flux(held[0]), sh_flux(held[1]), sh_flux(held[2])), vec3(0.0));
    vec3 positive = lpv_positive_outflux(held);
    budget_scale[linear_cell(cell)] = vec4(mix(vec3(1.0), flux / max(positive, vec3(1e-30)),
                                               greaterThan(positive, flux)), 0.0);
    return;
#endif
    float audit[AUDIT_VALUES];
    propagate_cell(cell, audit);
#if PROPAGATE_AUDIT
    ivec3 n = u_grid_cells;
    int cells = n.x * n.y * n.z;
    int linear = cell.x + n.x * (cell.y + n.y * cell.z);
    for (int i = 0; i < AUDIT_VALUES; ++i) {
        cell_terms[i * cells + linear] = audit[i];
        cell_sums[linear * AUDIT_VALUES + i] += audit[i];
    }
#endif
}

#endif
