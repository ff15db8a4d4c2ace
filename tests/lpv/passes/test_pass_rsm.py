"""RSM and downsample passes against numpy evaluations of docs/MODEL.md."""

from __future__ import annotations

import math

import numpy as np
import pytest

from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.downsample import DownsamplePass, downsampled_size
from explorer.lpv.passes.rsm import RsmPass, light_view
from explorer.lpv.vpl import VplTextures
from explorer.scene import Camera, DirectionalLight, MeshBuilder, Scene, SpotLight
from explorer.scene.gpu import SceneBuffers

SIZE = 64
ALBEDO = np.array([0.8, 0.5, 0.25])
PLANE_NORMAL = np.array([0.3, 1.0, 0.2]) / np.linalg.norm([0.3, 1.0, 0.2])
PLANE_POINT = np.array([0.0, -1.0, 0.0])


def plane_scene(light) -> Scene:
    """A large tilted plane under the light: it fills the whole 90° frustum."""
    mesh = MeshBuilder()
    u = np.cross(PLANE_NORMAL, [0.0, 0.0, 1.0])
    mesh.rect(PLANE_POINT, PLANE_NORMAL, u / np.linalg.norm(u), 40.0, 40.0, ALBEDO)
    positions, normals, albedo = mesh.arrays()
    return Scene("plane", positions, normals, albedo, Camera((0, 0, 3), (0, 0, 0)), light,
                 (-5.0, -5.0, -5.0), (5.0, 5.0, 5.0))


def raw(texture) -> np.ndarray:
    """Texture as (rows from the bottom, columns, 4), the GL layout."""
    width, height = texture.size
    return np.frombuffer(texture.read(), np.float32).reshape(height, width, 4)


def render_rsm(ctx, programs, scene, size=SIZE):
    geometry = SceneBuffers(ctx, scene)
    rsm = RsmPass(ctx, programs)
    view = light_view(scene, size)
    textures = rsm.run(geometry, view)
    arrays = [raw(t) for t in (textures.position, textures.normal, textures.flux)]
    return rsm, geometry, view, textures, arrays


def rectangle_solid_angle(x, y):
    """Solid angle of [0, x]×[0, y] on the plane at distance 1 (signed): an independent
    closed form, not the triangle formula the shader uses."""
    return np.arctan(x * y / np.sqrt(1.0 + x * x + y * y))


def test_spot_flux_per_texel_matches_the_model(ctx, programs):
    flux_total = 12.0
    light = SpotLight((0.0, 0.0, 0.0), (0.0, -1.0, 0.0), flux_total)
    scene = plane_scene(light)
    rsm, geometry, view, textures, (position, normal, flux) = render_rsm(ctx, programs, scene)
    try:
        assert np.all(position[..., 3] == 1.0)
        edges = np.linspace(-1.0, 1.0, SIZE + 1)
        x0, x1 = edges[None, :-1], edges[None, 1:]
        y0, y1 = edges[:-1, None], edges[1:, None]
        solid_angle = (rectangle_solid_angle(x1, y1) - rectangle_solid_angle(x0, y1)
                       - rectangle_solid_angle(x1, y0) + rectangle_solid_angle(x0, y0))
        # MODEL.md: Φ_o = c_diff · ρ/(4π) · Φ_L for a surface facing the light
        expected = ALBEDO[None, None, :] * (solid_angle / (4 * math.pi) * flux_total)[..., None]
        assert np.allclose(flux[..., :3], expected, rtol=2e-4)
        # the whole frustum (4π/6) reaches the plane: c·Φ_L/6 in total
        assert np.allclose(flux[..., :3].sum(axis=(0, 1)), ALBEDO * flux_total / 6, rtol=1e-4)

        # positions: the plane hit by the ray through each texel centre
        centres = 0.5 * (edges[:-1] + edges[1:])
        xs, ys = np.meshgrid(centres, centres)
        view_dirs = np.stack([xs, ys, -np.ones_like(xs)], axis=-1)
        world_dirs = view_dirs @ view.view[:3, :3]            # inverse rotation
        t = (PLANE_POINT @ PLANE_NORMAL) / (world_dirs @ PLANE_NORMAL)
        hits = world_dirs * t[..., None]
        assert np.allclose(position[..., :3], hits, atol=2e-4 * np.abs(hits).max())
        # normal.w = view depth (distance along the light's axis)
        assert np.allclose(normal[..., 3], t, rtol=1e-4)
        assert np.allclose(normal[..., :3], PLANE_NORMAL, atol=1e-5)
        assert textures.texel_area == pytest.approx(4.0 / SIZE**2)
    finally:
        rsm.release()
        geometry.release()


def test_spot_flux_ignores_surfaces_facing_away_from_the_light(ctx, programs):
    # the light under the plane sees its back: two-sided, the normal is flipped to face it
    light = SpotLight((0.0, -3.0, 0.0), (0.0, 0.0, 0.0), 6.0)
    scene = plane_scene(light)
    rsm, geometry, _, _, (position, normal, flux) = render_rsm(ctx, programs, scene)
    try:
        assert np.all(normal[..., :3] @ PLANE_NORMAL < -0.99)
        assert np.allclose(flux[..., :3].sum(axis=(0, 1)), ALBEDO * 6.0 / 6, rtol=1e-4)
    finally:
        rsm.release()
        geometry.release()


def test_directional_flux_is_irradiance_times_texel_area(ctx, programs):
    light = DirectionalLight((0.0, 5.0, 0.0), (0.0, 0.0, 0.0), 100.0)
    scene = plane_scene(light)
    rsm, geometry, view, textures, (position, _, flux) = render_rsm(ctx, programs, scene)
    try:
        assert textures.projection == "orthographic"
        irradiance = light.irradiance(scene.bounds_min, scene.bounds_max)
        expected = ALBEDO * irradiance * textures.texel_area
        assert np.allclose(flux[..., :3], expected, rtol=1e-5)
        assert np.allclose(flux[..., :3].sum(axis=(0, 1)), ALBEDO * 100.0, rtol=1e-4)
    finally:
        rsm.release()
        geometry.release()


def test_average_downsample_conserves_flux(ctx, programs):
    light = SpotLight((0.0, 0.0, 0.0), (0.0, -1.0, 0.0), 12.0)
    scene = plane_scene(light)
    rsm, geometry, view, textures, (position, normal, flux) = render_rsm(ctx, programs, scene)
    down = DownsamplePass(ctx, programs)
    spec = GridSpec.enclosing(scene.bounds_min, scene.bounds_max, 16)
    try:
        for factor in (2, 3):
            result = down.run(textures, "average", factor, spec, view)
            assert result.size == downsampled_size((SIZE, SIZE), factor)
            assert result.texel_area == pytest.approx(textures.texel_area * factor**2)
            small_flux = raw(result.flux)
            assert np.allclose(small_flux[..., :3].sum(axis=(0, 1)),
                               flux[..., :3].sum(axis=(0, 1)), rtol=1e-5)
        # factor 2: each VPL is the mean position of its 2×2 block and the sum of its flux
        result = down.run(textures, "average", 2, spec, view)
        blocks = position[..., :3].reshape(SIZE // 2, 2, SIZE // 2, 2, 3).mean(axis=(1, 3))
        assert np.allclose(raw(result.position)[..., :3], blocks, atol=1e-4)
        flux_blocks = flux[..., :3].reshape(SIZE // 2, 2, SIZE // 2, 2, 3).sum(axis=(1, 3))
        assert np.allclose(raw(result.flux)[..., :3], flux_blocks, rtol=1e-5)
    finally:
        down.release()
        rsm.release()
        geometry.release()


def test_brightest_downsample_keeps_texels_near_the_brightest_cell(ctx, programs):
    # four VPLs in one 2×2 block: three near each other, one far away (dropped)
    position = np.array([[0.1, 0.1, 0.1], [0.15, 0.1, 0.1], [0.1, 0.12, 0.1], [0.9, 0.9, 0.9]])
    flux = np.array([[1.0, 1.0, 1.0], [2.0, 2.0, 2.0], [0.5, 0.5, 0.5], [0.25, 0.25, 0.25]])
    normal = np.tile([0.0, 1.0, 0.0], (4, 1))
    data = {"position": np.hstack([position, np.ones((4, 1))]),
            "normal": np.hstack([normal, np.ones((4, 1))]),
            "flux": np.hstack([flux, np.zeros((4, 1))])}
    textures = [ctx.texture((2, 2), 4, data[name].astype(np.float32).tobytes(), dtype="f4")
                for name in ("position", "normal", "flux")]
    vpls = VplTextures(*textures, texel_area=0.01)
    spec = GridSpec((0.0, 0.0, 0.0), 0.1, 10)
    scene = plane_scene(SpotLight((0, 2, 0), (0, 0, 0), 1.0))
    view = light_view(scene, 2)
    down = DownsamplePass(ctx, programs)
    try:
        brightest = down.run(vpls, "brightest", 2, spec, view)
        assert np.allclose(raw(brightest.flux)[0, 0, :3], 3.5)        # 1 + 2 + 0.5 kept
        assert np.allclose(raw(brightest.position)[0, 0, :3], position[:3].mean(axis=0),
                           atol=1e-6)
        average = down.run(vpls, "average", 2, spec, view)
        assert np.allclose(raw(average.flux)[0, 0, :3], 3.75)         # everything
    finally:
        down.release()
        vpls.release()
