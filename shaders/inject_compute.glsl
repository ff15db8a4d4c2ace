#version 430 core
// Light injection by compute shaders, the gather the DX12 write-up proposes, in two stages:
//   INJECT_STAGE 0 (bin):    one invocation per VPL pushes its index onto a per-cell linked
//                            list (atomicExchange on the list heads; index + 1, 0 = empty).
//   INJECT_STAGE 1 (gather): one invocation per cell walks its list and stores
//                            sum k_I * flux[c] * lobe(n) into the grid images; no blending
//                            and no write conflicts, and every cell is written (no clear).
// The list order depends on the atomic order, so sums may differ from the point injection
// in the last bits only (float addition order).
// SH_ORDER 2 stores L2 lobes (layout of sh_grid.glsl).
#define INJECT_STAGE 0
#define IMAGE_FORMAT rgba32f
#define SH_ORDER 1

#if defined COMPUTE_SHADER

#include "grid.glsl"
#include "vpl.glsl"
#include "lpv_corrections.glsl"
#include "sh_grid.glsl"

layout(std430, binding = 0) buffer CellHeads { uint cell_heads[]; };
layout(std430, binding = 1) buffer NextVpl { uint next_vpl[]; };

int cell_slot(ivec3 cell) {
    ivec3 n = u_grid_cells;
    return cell.x + n.x * (cell.y + n.y * cell.z);
}

#if INJECT_STAGE == 0

layout(local_size_x = 64) in;

void main() {
    int index = int(gl_GlobalInvocationID.x);
    if (index >= vpl_count()) {
        return;
    }
    Vpl vpl = vpl_fetch(index);
    ivec3 cell = grid_cell(vpl_injection_position(vpl));
    if (!vpl.valid || !grid_inside(cell)) {
        return;
    }
    next_vpl[index] = atomicExchange(cell_heads[cell_slot(cell)], uint(index + 1));
}

#else

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

// Image units are fixed by binding (moderngl cannot set image uniforms).
layout(IMAGE_FORMAT, binding = 0) uniform writeonly image3D u_grid_r;
layout(IMAGE_FORMAT, binding = 1) uniform writeonly image3D u_grid_g;
layout(IMAGE_FORMAT, binding = 2) uniform writeonly image3D u_grid_b;

void main() {
    ivec3 cell = ivec3(gl_GlobalInvocationID);
    if (!grid_inside(cell)) {
        return;
    }
    float k_injection = lpv_injection_factor();
    ShVec red = SHV_ZERO;
    ShVec green = SHV_ZERO;
    ShVec blue = SHV_ZERO;
    uint link = cell_heads[cell_slot(cell)];
    // Each VPL sits in at most one list, so a list is never longer than the VPL count; the
    // bound guards against a corrupted list hanging the GPU.
    int budget = vpl_count();
    while (link != 0u && budget > 0) {
        int index = int(link) - 1;
        Vpl vpl = vpl_fetch(index);
        ShVec lobe = sh_scale(shv_cosine_lobe(vpl.normal), k_injection);
        red = sh_add(red, sh_scale(lobe, vpl.flux.r));
        green = sh_add(green, sh_scale(lobe, vpl.flux.g));
        blue = sh_add(blue, sh_scale(lobe, vpl.flux.b));
        link = next_vpl[index];
        budget -= 1;
    }
    SH_IMAGE_STORE(u_grid_r, cell, red);
    SH_IMAGE_STORE(u_grid_g, cell, green);
    SH_IMAGE_STORE(u_grid_b, cell, blue);
}

#endif
#endif
