#version 430 core
// Energy audit on the GPU (GridAudit, explorer/lpv/audit.py), read back as small sums.
// An audit record is 21 numbers:
//     [0..2]  flux (of a grid, or delivered into the grid by a propagation step)
//     [3..5]  border loss:  flux sent to targets outside the grid
//     [6..8]  clamp gain:   flux the faces gain by the clamp+ (clamped - raw intensity)
//     [9..11] occluded:     flux the faces lose to the geometry volume (1 - V_f)
//     [12..14] reflected:   flux the geometry volume reflects back (reflection.glsl)
//     [15..17] blocked:     blocked flux that can bounce (clamp+ per direction)
//     [18..20] withheld:    flux the flux budget kept back ((1 - beta) * clamp+ faces)
// Stages (select with AUDIT_STAGE):
//   0: partial records of the flux of one grid (the injected grid, the accumulation);
//   1: partial records of the per-cell records propagate.glsl wrote (cell_terms);
//   2: every slot's partial records folded into its result (once, before the read-back).
// Stages 0 and 1 run one invocation per partial and write slot u_result_slot's region of
// `partials` (P records per slot); invocation p sums the cells p, p + P, p + 2P, ...:
// neighbouring invocations read neighbouring memory. Stage 1 reduces several steps' records
// in one dispatch (the propagation's steps in a row, each writing its records
// u_record_stride floats after the last's): row y of the dispatch is slot
// u_result_slot + y, the same sums in the same order as one dispatch per step. Stage 2 runs one invocation per
// (slot, value), summing that value over the slot's P partials. No barrier() anywhere:
// llvmpipe pays more for it than for a whole propagation step.
#define AUDIT_STAGE 0
// Stage 0's sampler units of the grid it reduces: 0..2 unless a second program moves them
// (explorer/lpv/passes/audit_reduce.py `PING_GRID_DEFINES`: the flux of the propagation's
// ping grid, which stays on units of its own).
#define AUDIT_GRID_R 0
#define AUDIT_GRID_G 1
#define AUDIT_GRID_B 2

#if defined COMPUTE_SHADER

#include "sh.glsl"
#include "grid.glsl"

const int AUDIT_VALUES = 21;
const int CELLS_PER_PARTIAL = 64;

layout(std430, binding = 2) buffer Partials { float partials[]; };
layout(std430, binding = 3) buffer Results { float results[]; };
layout(std430, binding = 4) buffer CellTerms { float cell_terms[]; };

uniform int u_partial_count;    // P, partial records per slot

#if AUDIT_STAGE == 0 || AUDIT_STAGE == 1

uniform int u_result_slot;
#if AUDIT_STAGE == 1
uniform int u_record_stride;    // floats from one step's records to the next's
#endif

layout(local_size_x = 64) in;

layout(binding = AUDIT_GRID_R) uniform sampler3D u_grid_r;
layout(binding = AUDIT_GRID_G) uniform sampler3D u_grid_g;
layout(binding = AUDIT_GRID_B) uniform sampler3D u_grid_b;

void main() {
    int partial = int(gl_GlobalInvocationID.x);
    if (partial >= u_partial_count) {
        return;
    }
    ivec3 n = u_grid_cells;
    int cells = n.x * n.y * n.z;
    float sums[AUDIT_VALUES];
    for (int i = 0; i < AUDIT_VALUES; ++i) {
        sums[i] = 0.0;
    }
    for (int linear = partial; linear < cells; linear += u_partial_count) {
#if AUDIT_STAGE == 0
        ivec3 cell = ivec3(linear % n.x, (linear / n.x) % n.y, linear / (n.x * n.y));
        sums[0] += sh_flux(texelFetch(u_grid_r, cell, 0));
        sums[1] += sh_flux(texelFetch(u_grid_g, cell, 0));
        sums[2] += sh_flux(texelFetch(u_grid_b, cell, 0));
#else
        int step_records = int(gl_GlobalInvocationID.y) * u_record_stride;
        for (int i = 0; i < AUDIT_VALUES; ++i) {
            sums[i] += cell_terms[step_records + i * cells + linear];
        }
#endif
    }
    int record = (u_result_slot + int(gl_GlobalInvocationID.y)) * u_partial_count + partial;
    for (int i = 0; i < AUDIT_VALUES; ++i) {
        partials[record * AUDIT_VALUES + i] = sums[i];
    }
}

#else

layout(local_size_x = 64) in;

uniform int u_slot_count;

void main() {
    int index = int(gl_GlobalInvocationID.x);
    if (index >= u_slot_count * AUDIT_VALUES) {
        return;
    }
    int slot = index / AUDIT_VALUES;
    int value = index % AUDIT_VALUES;
    float sum = 0.0;
    for (int partial = 0; partial < u_partial_count; ++partial) {
        sum += partials[(slot * u_partial_count + partial) * AUDIT_VALUES + value];
    }
    results[index] = sum;
}

#endif
#endif
