"""Injection on the GPU: both modes against the numpy twin and each other."""

from __future__ import annotations

import numpy as np
import pytest
from lpv_cases import random_vpls, relative_error

from explorer.gl.program import ProgramCache
from explorer.lpv import inject
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.inject import InjectPass
from explorer.lpv.passes.textures import LpvGrid
from explorer.lpv.settings import PRESETS, Corrections
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.vpl import VplArrays, VplTextures

SPEC = GridSpec(origin=(-1.0, 0.5, -2.0), cell_size=0.25, resolution=8)


@pytest.mark.parametrize("mode", ["points", "compute"])
@pytest.mark.parametrize("preset", ["corrected", "original"])
def test_injection_matches_the_reference(ctx, mode, preset):
    vpls = random_vpls(1, SPEC, 400, outside=20)
    corrections = PRESETS[preset]
    expected = twin.inject(vpls, SPEC, corrections)
    assert relative_error(inject(vpls, SPEC, corrections, mode, ctx=ctx), expected) < 1e-5


def test_point_and_compute_injection_agree_on_crowded_cells(ctx):
    # 5000 VPLs in 4^3 cells: ~80 per cell, summed in different orders by the two paths.
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 4)
    vpls = random_vpls(2, spec, 5000, outside=50)   # > 4096: two texture rows, padded
    points = inject(vpls, spec, mode="points", ctx=ctx)
    compute = inject(vpls, spec, mode="compute", ctx=ctx)
    assert np.count_nonzero(points[..., 0]) == 3 * 4 ** 3
    assert relative_error(compute, points) < 1e-5


def test_a_vpl_lands_in_its_cell_with_the_lobe_and_the_pi_correction(ctx):
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 4)
    vpls = VplArrays(np.array([[1.3, 2.6, 3.2]]), np.array([[0.0, 0.0, 1.0]]),
                     np.array([[1.0, 2.0, 4.0]]), np.ones(1), 0.01)
    for mode in ("points", "compute"):
        grid = inject(vpls, spec, mode=mode, ctx=ctx)
        nonzero = np.argwhere(np.abs(grid).sum(axis=-1) > 0)
        assert nonzero.tolist() == [[0, 1, 2, 3], [1, 1, 2, 3], [2, 1, 2, 3]]
        # lobe(+z) = (sqrt(pi)/2, 0, sqrt(pi/3), 0), scaled by flux/pi: flux 2*sqrt(pi)*f0 = Φ
        lobe = np.array([np.sqrt(np.pi) / 2, 0.0, np.sqrt(np.pi / 3), 0.0]) / np.pi
        assert np.allclose(grid[:, 1, 2, 3], np.outer([1.0, 2.0, 4.0], lobe), rtol=1e-6)
        assert np.allclose(2 * np.sqrt(np.pi) * grid[:, 1, 2, 3, 0], [1.0, 2.0, 4.0])


@pytest.mark.parametrize("mode", ["points", "compute"])
def test_empty_texels_are_skipped_and_the_grid_is_overwritten(ctx, mode):
    """Texels with position.w == 0 (the light saw nothing) add nothing, even with flux."""
    vpls = random_vpls(3, SPEC, 30)
    count = vpls.count
    rows = np.zeros((2, count, 4), np.float32)   # row 1: empty texels with large flux
    position, normal, flux = rows.copy(), rows.copy(), rows.copy()
    position[0, :, :3], position[0, :, 3] = vpls.positions, 1.0
    position[1, :, :3] = vpls.positions
    normal[:, :, :3] = vpls.normals
    normal[:, :, 3] = vpls.depth
    flux[0, :, :3] = vpls.flux
    flux[1, :, :3] = 1000.0
    textures = VplTextures(*[ctx.texture((count, 2), 4, data.tobytes(), dtype="f4")
                             for data in (position, normal, flux)], texel_area=0.02)
    grid = LpvGrid(ctx, SPEC.resolution)
    injector = InjectPass(ctx, ProgramCache(ctx))
    try:
        grid.write(np.full((3,) + (8,) * 3 + (4,), 7.0))   # stale data must disappear
        injector.run(textures, SPEC, Corrections(), mode, grid)
        assert relative_error(grid.read(), twin.inject(vpls, SPEC)) < 1e-5
    finally:
        injector.release()
        grid.release()
        textures.release()


def test_half_float_grid(ctx):
    vpls = random_vpls(4, SPEC, 200)
    expected = twin.inject(vpls, SPEC)
    for mode in ("points", "compute"):
        grid = inject(vpls, SPEC, mode=mode, ctx=ctx, fmt="rgba16f")
        assert grid.dtype == np.float32
        assert relative_error(grid, expected) < 2e-3


def test_grid_round_trip_keeps_the_axis_order(ctx):
    data = np.random.default_rng(5).standard_normal((3, 6, 6, 6, 4)).astype(np.float32)
    grid = LpvGrid(ctx, 6)
    try:
        grid.write(data)
        assert np.array_equal(grid.read(), data)
        grid.clear()
        assert not grid.read().any()
        with pytest.raises(ValueError, match=r"\(3, 6, 6, 6, 4\)"):
            grid.write(data[:, :5])
    finally:
        grid.release()


def test_bad_input_is_named(ctx):
    vpls = random_vpls(6, SPEC, 5)
    with pytest.raises(ValueError, match="injection mode"):
        inject(vpls, SPEC, mode="splat", ctx=ctx)
    with pytest.raises(TypeError, match="VplArrays"):
        inject(np.zeros((5, 3)), SPEC, ctx=ctx)
    with pytest.raises(ValueError, match="format"):
        inject(vpls, SPEC, ctx=ctx, fmt="rgba8")
    injector = InjectPass(ctx, ProgramCache(ctx))
    textures = VplTextures.from_arrays(ctx, vpls)
    grid = LpvGrid(ctx, 4)
    try:
        with pytest.raises(ValueError, match="4\\^3 cells"):
            injector.run(textures, SPEC, Corrections(), "points", grid)
    finally:
        grid.release()
        textures.release()


def test_point_injection_gives_the_callers_framebuffer_back(ctx):
    screen = ctx.simple_framebuffer((16, 8))
    screen.use()
    inject(random_vpls(7, SPEC, 10), SPEC, mode="points", ctx=ctx)
    assert ctx.fbo is screen and tuple(ctx.viewport) == (0, 0, 16, 8)
    # Left bound and alive on purpose: a standalone context has no default framebuffer to
    # go back to, and releasing a bound framebuffer breaks the next pass that restores it.
