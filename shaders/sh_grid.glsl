#version 430 core
// Texel layout of a light grid of SH_ORDER vectors (docs/MODEL.md "L2 option"): one RGBA
// 3D texture per colour channel, N x N x (SH_GROUPS·N) texels; group k of cell (x, y, z)
// (coefficients 4k..4k+3) is texel (x, y, z + k·N). L1 (one group) is the plain N³ grid.
// Stacking the groups along z keeps three textures (and image units) per grid for either
// order: GL guarantees only 8 image units per compute shader and 8 draw buffers.
#ifndef SH_GRID_GLSL
#define SH_GRID_GLSL 1

#include "sh.glsl"
#include "grid.glsl"

ivec3 sh_group_texel(ivec3 cell, int k) {
    return cell + ivec3(0, 0, k * u_grid_resolution);
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

// L2: trilinear sample of the three groups at grid coordinates g [cells], clamped to the
// edge. Per group the z coordinate is clamped to the group's texel centres, which is
// exactly what clamp-to-edge does at the faces of a separate N³ texture.
ShL2 sh2_sample_groups(sampler3D tex, vec3 g) {
    float n = float(u_grid_resolution);
    vec2 xy = g.xy / n;
    float z = clamp(g.z, 0.5, n - 0.5);
    float depth = 3.0 * n;
    return ShL2(textureLod(tex, vec3(xy, z / depth), 0.0),
                textureLod(tex, vec3(xy, (z + n) / depth), 0.0),
                textureLod(tex, vec3(xy, (z + 2.0 * n) / depth), 0.0));
}

// Trilinear sample of the grid at a world point (final gather), clamped to the edge.
ShVec sh_sample_grid(sampler3D tex, vec3 world) {
#if SH_ORDER == 1
    return texture(tex, grid_texcoord(world));
#else
    return sh2_sample_groups(tex, grid_coords(world));
#endif
}

// The same at grid coordinates g [cells] of a grid with u_grid_resolution cells per axis
// but its own origin and cell size (a cascade, cascades.glsl); explicit LOD 0.
ShVec sh_sample_cells(sampler3D tex, vec3 g) {
#if SH_ORDER == 1
    return textureLod(tex, g / float(u_grid_resolution), 0.0);
#else
    return sh2_sample_groups(tex, g);
#endif
}

#endif
