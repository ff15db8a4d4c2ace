#version 430 core
// Texel layout of a light grid of SH_ORDER vectors (docs/MODEL.md "L2 option"): one RGBA
// 3D texture per colour channel, nx x ny x (SH_GROUPS·nz) texels; group k of cell (x, y, z)
// (coefficients 4k..4k+3) is texel (x, y, z + k·nz). L1 (one group) is the plain grid.
// Stacking the groups along z keeps three textures (and image units) per grid for either
// order: GL guarantees only 8 image units per compute shader and 8 draw buffers.
#ifndef SH_GRID_GLSL
#define SH_GRID_GLSL 1

#include "sh.glsl"
#include "grid.glsl"

ivec3 sh_group_texel(ivec3 cell, int k) {
    return cell + ivec3(0, 0, k * u_grid_cells.z);
}

#if SH_ORDER == 1
#define SH_FETCH(tex, cell) texelFetch(tex, cell, 0)
#define SH_IMAGE_LOAD(img, cell) imageLoad(img, cell)
#define SH_IMAGE_STORE(img, cell, value) imageStore(img, cell, value)
#else
#define SH_FETCH(tex, cell) ShL2(texelFetch(tex, cell, 0), \
    texelFetch(tex, sh_group_texel(cell, 1), 0), texelFetch(tex, sh_group_texel(cell, 2), 0))
#define SH_IMAGE_LOAD(img, cell) ShL2(imageLoad(img, cell), \
    imageLoad(img, sh_group_texel(cell, 1)), imageLoad(img, sh_group_texel(cell, 2)))
#define SH_IMAGE_STORE(img, cell, value) { ShL2 sh_stored_ = (value); \
    imageStore(img, cell, sh_stored_.g0); \
    imageStore(img, sh_group_texel(cell, 1), sh_stored_.g1); \
    imageStore(img, sh_group_texel(cell, 2), sh_stored_.g2); }
#endif

// Trilinear lookup of the grid (final gather, docs/MODEL.md "Final gather"): texel centres
// at i + ½, clamped to the edge of the N³ block of each texel group (group k of an L2 grid
// is the block starting at z texel k·N, layout above; clamping each group to its own block
// is what clamp-to-edge does at the faces of a separate N³ texture).
// SH_SHADER_FILTER 0: the texture unit's linear filter. 1: the same weights computed here
// in float32 from 8 texelFetch per group. A GPU's texture unit computes the weights with 8
// fractional bits (NVIDIA; D3D's SUBTEXEL_FRACTIONAL_BIT_COUNT), an error of up to 1/512 of
// the difference between neighbouring texels, while llvmpipe's are float32 and 4-6 times
// cheaper than the fetches here. explorer/lpv/passes/gather.py measures the texture unit once per
// context (filter_probe.glsl) and sets 1 where it is not exact, so the gather matches the
// float64 numpy gather (explorer/lpv/twin/light_grid.py) to float32 precision on every GPU.
#ifndef SH_SHADER_FILTER
#define SH_SHADER_FILTER 0
#endif

vec4 sh_trilinear_block(sampler3D tex, ivec3 lo, ivec3 hi, vec3 f, int dz) {
    return mix(mix(mix(texelFetch(tex, ivec3(lo.x, lo.y, lo.z + dz), 0),
                       texelFetch(tex, ivec3(hi.x, lo.y, lo.z + dz), 0), f.x),
                   mix(texelFetch(tex, ivec3(lo.x, hi.y, lo.z + dz), 0),
                       texelFetch(tex, ivec3(hi.x, hi.y, lo.z + dz), 0), f.x), f.y),
               mix(mix(texelFetch(tex, ivec3(lo.x, lo.y, hi.z + dz), 0),
                       texelFetch(tex, ivec3(hi.x, lo.y, hi.z + dz), 0), f.x),
                   mix(texelFetch(tex, ivec3(lo.x, hi.y, hi.z + dz), 0),
                       texelFetch(tex, ivec3(hi.x, hi.y, hi.z + dz), 0), f.x), f.y), f.z);
}

// Trilinear sample of the grid's light vector at grid coordinates g [cells] of a grid with
// u_grid_cells cells along x, y, z (its own origin and cell size: the single grid or a
// cascade, cascades.glsl).
ShVec sh_sample_cells(sampler3D tex, vec3 g) {
    ivec3 n = u_grid_cells;
#if SH_SHADER_FILTER
    vec3 t = clamp(g - 0.5, vec3(0.0), vec3(n - 1));
    ivec3 lo = ivec3(floor(t));
    ivec3 hi = min(lo + 1, n - 1);
    vec3 f = t - vec3(lo);
#if SH_ORDER == 1
    return sh_trilinear_block(tex, lo, hi, f, 0);
#else
    return ShL2(sh_trilinear_block(tex, lo, hi, f, 0),
                sh_trilinear_block(tex, lo, hi, f, n.z),
                sh_trilinear_block(tex, lo, hi, f, 2 * n.z));
#endif
#else
#if SH_ORDER == 1
    return textureLod(tex, g / vec3(n), 0.0);
#else
    // per group the z coordinate is clamped to the group's texel centres
    vec2 xy = g.xy / vec2(n.xy);
    float z = clamp(g.z, 0.5, float(n.z) - 0.5);
    float depth = 3.0 * float(n.z);
    return ShL2(textureLod(tex, vec3(xy, z / depth), 0.0),
                textureLod(tex, vec3(xy, (z + float(n.z)) / depth), 0.0),
                textureLod(tex, vec3(xy, (z + 2.0 * float(n.z)) / depth), 0.0));
#endif
#endif
}

// The same at a world point of the grid of grid.glsl (final gather).
ShVec sh_sample_grid(sampler3D tex, vec3 world) {
    return sh_sample_cells(tex, grid_coords(world));
}

#endif
