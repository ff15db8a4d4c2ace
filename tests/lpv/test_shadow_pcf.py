"""PCF shadow edges of the direct light (docs/MODEL.md "Final gather", Settings.shadow_kernel):
a hard edge with a kernel of 1, a linear ramp about k shadow-map texels wide with k,
and fully lit or fully shadowed ground left exactly as it was."""

from __future__ import annotations

import math

import numpy as np
import pytest

from explorer.gl.program import ProgramCache
from explorer.lpv.passes.gather import GatherInputs, GatherPass
from explorer.lpv.passes.gbuffer import GBufferPass
from explorer.lpv.passes.light_records import ShadowMaps
from explorer.lpv.passes.rsm import RsmPass, light_view, read_texture
from explorer.lpv.settings import MAX_SHADOW_KERNEL, Settings
from explorer.scene import Camera, MeshBuilder, Scene, SpotLight
from explorer.scene.gpu import SceneBuffers

RSM = 64
IMAGE = (128, 128)
ALBEDO = (0.7, 0.7, 0.7)
LIGHT_HEIGHT = 2.0
BLOCKER_HEIGHT = 0.5
BLOCKER_HALF = 0.5


@pytest.fixture(scope="module")
def visibility(gl_context):
    """Visibility direct / unshadowed Lambertian on the ground (NaN elsewhere) for each
    kernel, and the ground pixels' world positions."""
    ctx = gl_context
    mesh = MeshBuilder()
    mesh.rect((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0), 3.0, 3.0, ALBEDO)
    mesh.rect((0.0, BLOCKER_HEIGHT, 0.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0), BLOCKER_HALF,
              BLOCKER_HALF, ALBEDO)
    positions, normals, albedo = mesh.arrays()
    light = SpotLight((0.0, LIGHT_HEIGHT, 0.0), (0.0, 0.0, 0.0), 10.0)   # 90° frustum
    # the camera looks from below the blocker, so it sees the ground in the umbra too
    camera = Camera((1.6, 0.35, 0.5), (0.0, 0.0, 0.0), 80.0)
    scene = Scene("pcf", positions, normals, albedo, camera, light, (-3.0, -0.5, -3.0),
                  (3.0, 2.5, 3.0))
    programs = ProgramCache(ctx)
    geometry = SceneBuffers(ctx, scene)
    rsm, gbuffer, gather = RsmPass(ctx, programs), GBufferPass(ctx, programs), GatherPass(
        ctx, programs)
    try:
        view = light_view(scene, RSM)
        shadow = rsm.run(geometry, view)
        gbuffer.run(geometry, scene, IMAGE)
        position = read_texture(gbuffer.position)
        images = {}
        for kernel in (1, 3, 7):
            gather.run(gbuffer, ShadowMaps(shadow, view), None,
                       GatherInputs(shadow_kernel=kernel))
            images[kernel] = read_texture(gather.targets["direct"])[..., 0].astype(np.float64)
    finally:
        for thing in (gather, gbuffer, rsm, geometry, programs):
            thing.release()
    ground = (position[..., 3] > 0.5) & (np.abs(position[..., 1]) < 1e-4)
    offset = np.asarray(light.position) - position[..., :3]
    r2 = np.sum(offset**2, axis=-1)
    cos = offset[..., 1] / np.sqrt(r2)
    unshadowed = ALBEDO[0] / math.pi * light.intensity * cos / r2
    vis = {k: np.where(ground, image / unshadowed, np.nan) for k, image in images.items()}
    texel_on_ground = 2.0 * LIGHT_HEIGHT / RSM     # 90° frustum: 2·depth/W
    return vis, position[..., :3], texel_on_ground


def in_frustum(points: np.ndarray, margin: float) -> np.ndarray:
    """Ground points at least ``margin`` inside the light's 90° frustum (|x|, |z| < h)."""
    return np.maximum(np.abs(points[..., 0]), np.abs(points[..., 2])) < LIGHT_HEIGHT - margin


def shadow_distance(points: np.ndarray) -> np.ndarray:
    """Signed distance (per axis, the larger) of ground points outside the blocker's
    shadow square (negative inside): the square is the blocker scaled by h/(h − b)."""
    half = BLOCKER_HALF * LIGHT_HEIGHT / (LIGHT_HEIGHT - BLOCKER_HEIGHT)
    return np.maximum(np.abs(points[..., 0]), np.abs(points[..., 2])) - half


def test_fully_lit_and_fully_shadowed_ground_is_unchanged(visibility):
    vis, points, texel = visibility
    distance = shadow_distance(points)
    for kernel, v in vis.items():
        lit = np.isfinite(v) & (distance > (kernel / 2 + 2) * texel) & in_frustum(points, 0.1)
        umbra = np.isfinite(v) & (distance < -(kernel / 2 + 2) * texel)
        assert lit.sum() > 1000 and umbra.sum() > 20, kernel
        assert np.allclose(v[lit], 1.0, atol=1e-5), kernel
        assert np.all(v[umbra] == 0.0), kernel


def test_kernel_one_is_a_hard_edge(visibility):
    vis, _, _ = visibility
    v = vis[1][np.isfinite(vis[1])]
    assert np.all((np.abs(v) < 1e-5) | (np.abs(v - 1.0) < 1e-5))


def test_wider_kernels_ramp_the_edge_monotonically(visibility):
    vis, points, texel = visibility
    ramps = {}
    for kernel in (3, 7):
        v = vis[kernel]
        ramp = np.isfinite(v) & (v > 0.02) & (v < 0.98)
        ramps[kernel] = ramp
        # the ramp lies on the edge, within about half the kernel (+ bias and one texel)
        assert np.all(np.abs(shadow_distance(points[ramp])) < (kernel / 2 + 1.5) * texel)
        # along the line z = 0 out of the shadow, visibility never drops
        line = np.isfinite(v) & (np.abs(points[..., 2]) < 0.01) & in_frustum(points, 0.1)
        order = np.argsort(np.abs(points[..., 0][line]))
        assert line.sum() > 40
        assert np.all(np.diff(v[line][order]) >= -1e-5), kernel
    assert ramps[7].sum() > 1.8 * ramps[3].sum() > 0


def test_kernel_setting_is_checked():
    assert Settings().shadow_kernel == 3
    for bad in (0, MAX_SHADOW_KERNEL + 1, 2.5, True):
        with pytest.raises(ValueError, match="shadow_kernel"):
            Settings(shadow_kernel=bad)
