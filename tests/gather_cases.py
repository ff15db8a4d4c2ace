"""The gather tests' shared scene, grids and read-back (tests/lpv/passes/test_pass_gather.py,
tests/lpv/test_cascades.py, tests/lpv/test_l2.py use them)."""

from __future__ import annotations

import contextlib

import numpy as np
import pytest

from explorer.gl.program import ProgramCache
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.gather import GatherPass
from explorer.lpv.passes.gbuffer import GBufferPass
from explorer.lpv.passes.rsm import RsmPass, light_view, read_texture
from explorer.lpv.passes.textures import LpvGrid
from explorer.scene import Camera, MeshBuilder, Scene, SpotLight
from explorer.scene.gpu import SceneBuffers

N = 8
IMAGE = (48, 40)
ALBEDO = np.array([0.9, 0.6, 0.3])
TOLERANCE = 1e-5
"""GPU against the float64 reference, relative to the largest expected value: the same
bound as the injection and geometry passes. Both ways of interpolating the grid
(shaders/sh_grid.glsl: the texture unit where its weights are exact, as on llvmpipe, or the
shader's own float32 weights) agree with the reference to about 5e-7 on llvmpipe; a 1 %
change anywhere in the gather is 1e3 times this."""
FILTERS = pytest.mark.parametrize("shader_filter", [False, True],
                                  ids=["texture-unit", "shader-filter"])


@contextlib.contextmanager
def filtering(gather: GatherPass, shader_filter: bool):
    """Run the gather with the grid interpolated by the texture unit or by the shader,
    whichever this GPU would pick (GatherPass.shader_filter)."""
    chosen = gather.shader_filter
    gather.shader_filter = shader_filter
    try:
        yield
    finally:
        gather.shader_filter = chosen


def gather_scene(ctx):
    """The gather tests' two-rectangle scene lit by a spot, its RSM, G-buffer, an empty
    grid and the passes (a generator: the ``setup`` fixture of tests/lpv/conftest.py)."""
    programs = ProgramCache(ctx)
    mesh = MeshBuilder()
    mesh.rect((0.0, -0.5, 0.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0), 0.9, 0.9, ALBEDO)
    mesh.rect((0.0, 0.0, -0.7), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), 0.9, 0.5, ALBEDO)
    positions, normals, albedo = mesh.arrays()
    light = SpotLight((0.0, 0.6, 0.3), (0.0, -0.5, 0.0), 10.0)
    scene = Scene("gather-test", positions, normals, albedo,
                  Camera((0.0, 0.8, 2.2), (0.0, -0.3, 0.0), 50.0), light,
                  (-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))
    geometry = SceneBuffers(ctx, scene)
    rsm, gbuffer, gather = RsmPass(ctx, programs), GBufferPass(ctx, programs), GatherPass(
        ctx, programs)
    view = light_view(scene, 64)
    shadow = rsm.run(geometry, view)
    gbuffer.run(geometry, scene, IMAGE)
    spec = GridSpec.enclosing(scene.bounds_min, scene.bounds_max, N)
    grid = LpvGrid(ctx, N)
    yield ctx, scene, view, shadow, gbuffer, gather, grid, spec
    for thing in (grid, gather, gbuffer, rsm, geometry, programs):
        thing.release()


def read_gbuffer(gbuffer: GBufferPass) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                np.ndarray]:
    """position (H, W, 4), normal (H, W, 3), albedo (H, W, 3) and the mask of the pixels
    that saw a surface."""
    position = read_texture(gbuffer.position)
    normal = read_texture(gbuffer.normal)[..., :3]
    albedo = read_texture(gbuffer.albedo)[..., :3]
    return position, normal, albedo, position[..., 3] > 0.5


def smooth_grid(spec: GridSpec) -> np.ndarray:
    """A grid whose coefficients vary smoothly over the cells (positive band 0)."""
    idx = np.indices(spec.cells).transpose(1, 2, 3, 0) / max(spec.cells)  # (nx, ny, nz, 3)
    grid = np.zeros((3, *spec.cells, 4), np.float32)
    for c in range(3):
        grid[c, ..., 0] = 0.02 * (1.0 + c + idx[..., 0] + 2 * idx[..., 1])
        grid[c, ..., 1] = -0.01 * (1.0 + idx[..., 2])
        grid[c, ..., 2] = 0.005 * (idx[..., 0] - idx[..., 1])
        grid[c, ..., 3] = 0.004 * c * idx[..., 2]
    return grid


def visible_points(gbuffer: GBufferPass) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                 np.ndarray]:
    """(position (M, 3), normal (M, 3), albedo (M, 3), mask (H, W)) of the pixels that saw
    a surface."""
    position, normal, albedo, valid = read_gbuffer(gbuffer)
    return position[valid][:, :3], normal[valid], albedo[valid], valid
