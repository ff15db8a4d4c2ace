"""Final gather of a hand-made grid against numpy (docs/MODEL.md "Final gather")."""

from __future__ import annotations

import math

import numpy as np
import pytest

from explorer.gl.program import ProgramCache
from explorer.lpv.gather import GatherPass
from explorer.lpv.gbuffer import GBufferPass
from explorer.lpv.grid import GridSpec
from explorer.lpv.rsm import RsmPass, light_view, read_texture
from explorer.lpv.textures import LpvGrid
from explorer.scene import Camera, MeshBuilder, Scene, SpotLight
from explorer.scene.gpu import SceneBuffers

N = 8
IMAGE = (48, 40)
ALBEDO = np.array([0.9, 0.6, 0.3])


def lobe(n: np.ndarray) -> np.ndarray:
    """MODEL.md clamped-cosine lobe, (..., 4)."""
    a, b = math.sqrt(math.pi) / 2, math.sqrt(math.pi / 3)
    return np.stack([np.full(n.shape[:-1], a), -b * n[..., 1], b * n[..., 2], -b * n[..., 0]],
                    axis=-1)


def trilinear(grid: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Sample (3, N, N, N, 4) at continuous grid coordinates g (M, 3) like a linear-filtered
    3D texture clamped to the edge: texel centres at i + ½."""
    n = grid.shape[1]
    t = np.clip(g - 0.5, 0.0, n - 1)
    i0 = np.clip(np.floor(t).astype(int), 0, n - 1)
    i1 = np.minimum(i0 + 1, n - 1)
    f = t - i0
    out = np.zeros((3, len(g), grid.shape[-1]))
    for corner in range(8):
        pick = [(corner >> axis) & 1 for axis in range(3)]
        idx = [np.where(p, i1[:, a], i0[:, a]) for a, p in enumerate(pick)]
        weight = np.prod([np.where(p, f[:, a], 1 - f[:, a]) for a, p in enumerate(pick)], axis=0)
        out += weight[None, :, None] * grid[:, idx[0], idx[1], idx[2], :]
    return out


@pytest.fixture(scope="module")
def setup(gl_context):
    ctx = gl_context
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
    idx = np.indices((N, N, N)).transpose(1, 2, 3, 0) / N            # (N, N, N, 3)
    grid = np.zeros((3, N, N, N, 4), np.float32)
    for c in range(3):
        grid[c, ..., 0] = 0.02 * (1.0 + c + idx[..., 0] + 2 * idx[..., 1])
        grid[c, ..., 1] = -0.01 * (1.0 + idx[..., 2])
        grid[c, ..., 2] = 0.005 * (idx[..., 0] - idx[..., 1])
        grid[c, ..., 3] = 0.004 * c * idx[..., 2]
    return grid


def test_indirect_matches_numpy(setup):
    ctx, scene, view, shadow, gbuffer, gather, grid, spec = setup
    values = smooth_grid(spec)
    grid.write(values)
    gather.run(gbuffer, shadow, view, grid.textures, spec, exposure=1.0, indirect_only=False)
    position, normal, albedo, valid = read_gbuffer(gbuffer)
    indirect = read_texture(gather.targets["indirect"])[..., :3]
    assert valid.mean() > 0.3
    g = spec.grid_coords(position[valid][:, :3])
    s = trilinear(values.astype(np.float64), g)                      # (3, M, 4)
    irradiance = np.maximum(np.einsum("cmk,mk->mc", s, lobe(-normal[valid])), 0.0)
    irradiance /= spec.cell_size ** 2
    expected = albedo[valid] / math.pi * irradiance
    assert np.allclose(indirect[valid], expected, rtol=2e-2, atol=1e-3 * expected.max())
    assert np.all(indirect[~valid] == 0.0)
    # received = E · pixel area; summed, it is the flux the visible surfaces receive
    received = read_texture(gather.targets["received"])[..., :3]
    area = read_texture(gbuffer.normal)[..., 3]
    assert np.allclose(received[valid], irradiance * area[valid, None], rtol=2e-2,
                       atol=1e-3 * received.max())


def test_l2_indirect_matches_numpy(setup):
    """sh_order 2: E = <s, lobe_L2(−n)>/cell², with s sampled trilinearly from the 3 texel
    groups stacked along z (clamped to each group's own edge)."""
    from explorer.lpv.reference import cosine_lobe

    ctx, scene, view, shadow, gbuffer, gather, _, _ = setup
    # the back wall (z = −0.7) at grid z = 0.2: below the first texel centre, where a
    # plain lookup into the stacked texture would blend in another group
    spec = GridSpec((-1.0, -1.0, -0.75), 0.25, N)
    values = np.concatenate([smooth_grid(spec), np.zeros((3, N, N, N, 5), np.float32)], -1)
    idx = np.indices((N, N, N)).transpose(1, 2, 3, 0) / N
    for k in range(4, 9):   # band 2 varying along z, so a blend across groups would show
        values[..., k] = 0.006 * (k - 6) * (1.0 + idx[..., 2] - idx[..., k % 3])
    grid = LpvGrid(ctx, N, sh_order=2)
    try:
        grid.write(values)
        gather.run(gbuffer, shadow, view, grid.textures, spec, exposure=1.0,
                   indirect_only=False, sh_order=2)
    finally:
        grid.release()
    position = read_texture(gbuffer.position)
    normal = read_texture(gbuffer.normal)[..., :3]
    albedo = read_texture(gbuffer.albedo)[..., :3]
    indirect = read_texture(gather.targets["indirect"])[..., :3]
    valid = position[..., 3] > 0.5
    assert (spec.grid_coords(position[valid][:, :3])[:, 2] < 0.5).sum() > 20
    s = trilinear(values.astype(np.float64), spec.grid_coords(position[valid][:, :3]))
    irradiance = np.maximum(np.einsum("cmk,mk->mc", s, cosine_lobe(-normal[valid], 2)), 0.0)
    expected = albedo[valid] / math.pi * irradiance / spec.cell_size ** 2
    assert np.allclose(indirect[valid], expected, rtol=2e-2, atol=1e-3 * expected.max())
    l1_only = albedo[valid] / math.pi * np.maximum(np.einsum(
        "cmk,mk->mc", s[..., :4], lobe(-normal[valid])), 0.0) / spec.cell_size ** 2
    assert not np.allclose(indirect[valid], l1_only, rtol=2e-2, atol=1e-3 * expected.max())


def test_pixel_areas_add_up_to_the_visible_surface(setup):
    ctx, scene, view, shadow, gbuffer, gather, grid, spec = setup
    position = read_texture(gbuffer.position)
    area = read_texture(gbuffer.normal)[..., 3]
    floor = (position[..., 3] > 0.5) & np.isclose(position[..., 1], -0.5, atol=1e-4)
    # every floor pixel covers the floor's area seen through it: a fraction of 1.8²
    assert 0.0 < area[floor].sum() < 1.8 * 1.8
    assert np.all(area[floor] > 0)


def test_direct_light_is_the_shadowed_lambertian(setup):
    ctx, scene, view, shadow, gbuffer, gather, grid, spec = setup
    grid.clear()
    gather.run(gbuffer, shadow, view, grid.textures, spec, exposure=1.0, indirect_only=False)
    position, normal, albedo, valid = read_gbuffer(gbuffer)
    direct = read_texture(gather.targets["direct"])[..., :3]
    offset = np.asarray(scene.light.position) - position[..., :3]
    r2 = np.sum(offset**2, axis=-1)
    cos = np.sum(normal * offset, axis=-1) / np.sqrt(r2)
    # inside the spot's frustum (with a margin for the frustum edge)
    to_point = -offset / np.sqrt(r2)[..., None]
    axis = view.direction
    local = to_point @ view.view[:3, :3].T
    inside = np.all(np.abs(local[..., :2] / -local[..., 2:3]) < 0.9, axis=-1)
    pick = valid & inside & (cos > 0.2)
    assert pick.sum() > 100
    expected = albedo * (scene.light.flux / (4 * math.pi)) * (cos / r2)[..., None] / math.pi
    assert np.allclose(direct[pick], expected[pick], rtol=1e-3)
    assert axis[1] < 0
    # outside the frustum: no direct light
    outside = valid & ~np.all(np.abs(local[..., :2] / -local[..., 2:3]) < 1.05, axis=-1)
    assert np.all(direct[outside] == 0.0)


def test_exposure_and_indirect_only(setup):
    # the display encoding of the final image: tests/test_display.py
    ctx, scene, view, shadow, gbuffer, gather, grid, spec = setup
    grid.write(smooth_grid(spec))
    gather.run(gbuffer, shadow, view, grid.textures, spec, exposure=2.5, indirect_only=False)
    direct = read_texture(gather.targets["direct"])[..., :3]
    indirect = read_texture(gather.targets["indirect"])[..., :3]
    final = read_texture(gather.targets["final"])[..., :3]
    assert np.allclose(final, 2.5 * (direct + indirect), rtol=1e-5, atol=1e-7)
    gather.run(gbuffer, shadow, view, grid.textures, spec, exposure=2.5, indirect_only=True)
    final = read_texture(gather.targets["final"])[..., :3]
    assert np.allclose(final, 2.5 * indirect, rtol=1e-5, atol=1e-7)
