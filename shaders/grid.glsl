#version 430 core
// World <-> grid mapping of docs/MODEL.md; the uniforms are GridSpec.uniforms().
// Grid coordinate g = (p - origin)/cell_size, cell index floor(g).
#ifndef GRID_GLSL
#define GRID_GLSL 1

uniform vec3 u_grid_origin;
uniform float u_grid_cell_size;
uniform ivec3 u_grid_cells;  // (nx, ny, nz)

vec3 grid_coords(vec3 world) {
    return (world - u_grid_origin) / u_grid_cell_size;
}

ivec3 grid_cell(vec3 world) {
    return ivec3(floor(grid_coords(world)));
}

// Whether an integer cell lies in a box of `cells` cells along x, y, z.
bool grid_inside(ivec3 cell, ivec3 cells) {
    return all(greaterThanEqual(cell, ivec3(0))) && all(lessThan(cell, cells));
}

bool grid_inside(ivec3 cell) {
    return grid_inside(cell, u_grid_cells);
}

#endif
