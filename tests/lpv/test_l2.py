"""The L2 option (Settings.sh_order = 2, docs/MODEL.md "L2 option"): reference helpers,
GPU injection + propagation against the numpy twin, invariants, storage, pipeline."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from lpv_cases import cube_symmetries, random_grid, random_vpls, relative_error

from explorer.lpv import constants as K
from explorer.lpv import inject, propagate
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.geometry import inject_geometry
from explorer.lpv.passes.light_records import ShadowMaps
from explorer.lpv.passes.propagate import propagate_with_audit
from explorer.lpv.passes.textures import LpvGrid
from explorer.lpv.settings import PRESETS, Corrections, Settings
from explorer.lpv.twin import light_grid as twin

SPEC = GridSpec(origin=(0.0, 0.0, 0.0), cell_size=0.5, resolution=8)


def fibonacci_directions(count: int) -> np.ndarray:
    """``count`` nearly uniform unit directions (equal-area spiral), for quadrature."""
    index = np.arange(count) + 0.5
    z = 1.0 - 2.0 * index / count
    angle = np.pi * (1.0 + 5.0 ** 0.5) * index
    radius = np.sqrt(1.0 - z * z)
    return np.stack([radius * np.cos(angle), radius * np.sin(angle), z], -1)


def random_l2_grid(seed: int, resolution: int, higher: float = 0.4) -> np.ndarray:
    """(3, N, N, N, 9): positive band 0, bands 1 and 2 of relative size ``higher``."""
    rng = np.random.default_rng(seed)
    band2 = higher * rng.standard_normal((3,) + (resolution,) * 3 + (5,))
    return np.concatenate([random_grid(seed, resolution, higher), band2], -1)


def sh_symmetry(matrix: np.ndarray) -> np.ndarray:
    """9×9 matrix D moving the SH vector of f(ω) to that of f(Mᵀω) (the function turned
    by the orthogonal ``matrix`` M): least squares on sampled directions, D f = g with
    Y(ω)·g = Y(Mᵀω)·f for all ω (exact: each band is closed under rotations)."""
    directions = fibonacci_directions(200)
    basis = twin.sh_basis(directions, 2)
    turned = twin.sh_basis(directions @ np.asarray(matrix, np.float64), 2)  # Y(Mᵀω)
    solution, *_ = np.linalg.lstsq(basis, turned, rcond=None)
    return solution


def transform_l2_grid(grid: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """The L2 grid moved by the cube symmetry ``matrix`` about the grid centre."""
    n = grid.shape[1]
    centre = (n - 1) / 2.0
    cells = np.indices((n, n, n)).reshape(3, -1)
    moved = np.rint(matrix @ (cells - centre) + centre).astype(np.int64)
    out = np.empty_like(grid)
    out[:, moved[0], moved[1], moved[2]] = grid[:, cells[0], cells[1], cells[2]] @ \
        sh_symmetry(matrix).T
    return out


# ------------------------------------------------------------------ reference helpers


def test_l2_basis_and_lobe_of_the_reference():
    directions = fibonacci_directions(20000)
    weight = 4.0 * np.pi / len(directions)
    basis = twin.sh_basis(directions, 2)
    assert np.allclose(basis.T @ basis * weight, np.eye(9), atol=2e-3)
    assert np.array_equal(basis[:, :4], twin.sh_basis(directions))
    normal = np.array([0.48, -0.6, 0.64])
    projected = (np.maximum(directions @ normal, 0.0)[:, None] * basis).sum(0) * weight
    lobe = twin.cosine_lobe(normal, 2)
    assert np.allclose(lobe, projected, atol=2e-3)
    assert np.array_equal(lobe[:4], twin.cosine_lobe(normal))
    # band 2 = π/4·Y2(n): the shaders' constants say the same
    assert np.allclose(lobe[4:], np.pi / 4 * twin.sh_basis(normal, 2)[4:])
    assert np.isclose(K.SH_L2_LOBE_C2, np.pi / 4 * K.SH_L2_C2)
    # a corrected VPL still injects exactly its flux
    vpls = random_vpls(30, SPEC, 50)
    assert np.allclose(twin.flux(twin.inject(vpls, SPEC, sh_order=2)),
                       vpls.flux.sum(axis=0))
    with pytest.raises(ValueError, match="sh_order"):
        twin.cosine_lobe(normal, 3)


def test_symmetry_matrices_rotate_a_lobe_like_its_normal():
    normal = np.array([0.6, 0.0, 0.8])
    for matrix in cube_symmetries()[::7]:
        assert np.allclose(sh_symmetry(matrix) @ twin.cosine_lobe(normal, 2),
                           twin.cosine_lobe(matrix @ normal, 2), atol=1e-9)


# ------------------------------------------------------------------ GPU vs reference

CASES = [
    ("corrected", {}, "points", "one-sided"),
    ("original", {}, "compute", "double-sided"),
    ("corrected", {"side_faces": False}, "compute", "one-sided"),
    ("corrected", {"clamp_front_face": False, "exact_constants": False}, "points", None),
    ("original", {"surfel_area_squared": False, "reprojection_pi": True}, "points",
     "one-sided"),
    ("corrected", {"propagation_4pi": False, "injection_pi": False}, "compute", None),
]


@pytest.mark.parametrize("case", range(len(CASES)))
def test_l2_inject_and_propagate_match_the_reference(ctx, case):
    preset, changes, injection_mode, geometry_mode = CASES[case]
    corrections = replace(PRESETS[preset], **changes)
    vpls = random_vpls(40 + case, SPEC, 120, outside=5, texel_area=0.05)
    grid = inject(vpls, SPEC, corrections, injection_mode, ctx=ctx, sh_order=2)
    assert grid.shape == (3, 8, 8, 8, 9)
    assert relative_error(grid, twin.inject(vpls, SPEC, corrections, sh_order=2)) < 1e-5
    geometry = None if geometry_mode is None else inject_geometry(
        vpls, SPEC, corrections, geometry_mode, ctx=ctx)
    steps, accumulated, audit = propagate_with_audit(grid, corrections, 3, geometry, ctx=ctx)
    want_steps, want_accumulated, want_audit = twin.propagate_audited(
        grid, corrections, 3, geometry)
    for step, want in zip(steps, want_steps):
        assert relative_error(step, want) < 1e-4
    assert relative_error(accumulated, want_accumulated) < 1e-4
    scale = float(np.abs(want_audit.injected).max())
    for name in ("per_step", "border_loss", "clamp_gain", "occluded", "accumulated"):
        assert np.abs(getattr(audit, name) - getattr(want_audit, name)).max() <= 1e-4 * scale
    if geometry is not None:
        assert audit.occluded.min() > 0


def test_l2_with_injection_offset_and_second_bounce_matches_the_reference(ctx):
    """The leak-reduction options work with L2: injection offset (points and compute) and
    the geometry volume's reflection (bounces 2, reflected lobe of the grid's order)."""
    vpls = random_vpls(60, SPEC, 120, texel_area=0.05)
    expected = twin.inject(vpls, SPEC, offset_cells=0.5, sh_order=2)
    for mode in ("points", "compute"):
        grid = inject(vpls, SPEC, mode=mode, ctx=ctx, offset_cells=0.5, sh_order=2)
        assert relative_error(grid, expected) < 1e-5
    rng = np.random.default_rng(61)
    normals = rng.standard_normal((9, 9, 9, 3))
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    geometry = 0.8 * rng.random((9, 9, 9))[..., None] * twin.cosine_lobe(normals)
    albedo = np.concatenate([0.5 * rng.random((9, 9, 9, 3)), np.ones((9, 9, 9, 1))], -1)
    grid = random_l2_grid(62, 8, 0.3)
    steps, _, audit = propagate_with_audit(grid, Corrections(), 2, geometry, ctx=ctx,
                                           geometry_albedo=albedo, bounces=2)
    want_steps, _, want_audit = twin.propagate_audited(grid, Corrections(), 2, geometry,
                                                            albedo, bounces=2)
    for step, want in zip(steps, want_steps):
        assert relative_error(step, want) < 1e-4
    assert want_audit.reflected.min() > 0
    assert np.abs(audit.reflected - want_audit.reflected).max() < 1e-4 * grid[..., 0].sum()


def test_l2_in_place_propagation_runs_and_double_counts(ctx):
    grid = random_l2_grid(50, 8, 0.2)
    corrections = Corrections(ping_pong=False)
    _, _, audit = propagate_with_audit(grid, corrections, 2, ctx=ctx)
    _, _, ping_pong = propagate_with_audit(grid, Corrections(), 2, ctx=ctx)
    assert np.all(audit.accumulated > ping_pong.accumulated)


# ------------------------------------------------------------------ invariants


def centred_l2_source(resolution: int, block: int, seed: int, higher: float) -> np.ndarray:
    grid = np.zeros((3,) + (resolution,) * 3 + (9,))
    lo = (resolution - block) // 2
    grid[:, lo:lo + block, lo:lo + block, lo:lo + block] = random_l2_grid(seed, block, higher)
    return grid


def test_corrected_l2_propagation_conserves_flux_away_from_the_border(ctx):
    # bands 1 and 2 small: the intensity is positive in every direction
    grid = centred_l2_source(12, 2, 51, higher=0.02)
    _, _, audit = propagate_with_audit(grid, Corrections(clamp_front_face=False), 3, ctx=ctx)
    assert np.all(audit.border_loss == 0) and np.all(audit.clamp_gain == 0)
    assert np.abs(audit.per_step / audit.injected - 1.0).max() < 1e-5


def test_l2_isotropic_centre_source_is_invariant_under_the_48_cube_symmetries(ctx):
    grid = np.zeros((3, 7, 7, 7, 9))
    grid[:, 3, 3, 3, 0] = [1.0, 2.0, 3.0]
    result = sum(propagate(grid, Corrections(), 3, ctx=ctx))
    assert np.abs(result[..., 4:]).max() > 1e-3 * result[..., 0].max()  # band 2 is used
    for matrix in cube_symmetries():
        assert relative_error(transform_l2_grid(result, matrix), result) < 1e-5


def test_l2_propagation_commutes_with_the_48_cube_symmetries(ctx):
    """A directional L2 source: turning or mirroring it (band 2 by its 5×5 rotation)
    turns or mirrors the propagated result."""
    grid = centred_l2_source(6, 2, 52, higher=0.6)
    corrections = Corrections()
    result = sum(propagate(grid, corrections, 2, ctx=ctx))
    for matrix in cube_symmetries():
        moved = sum(propagate(transform_l2_grid(grid, matrix), corrections, 2, ctx=ctx))
        assert relative_error(moved, transform_l2_grid(result, matrix)) < 1e-5


def test_l2_propagation_is_linear_without_the_clamp(ctx):
    corrections = Corrections(clamp_front_face=False)
    first, second = random_l2_grid(53, 8), random_l2_grid(54, 8)
    together = sum(propagate(2.0 * first - 0.5 * second, corrections, 3, ctx=ctx))
    apart = [sum(propagate(g, corrections, 3, ctx=ctx)) for g in (first, second)]
    assert relative_error(together, 2.0 * apart[0] - 0.5 * apart[1]) < 1e-5
    # with the clamp, positive scaling still commutes
    scaled = sum(propagate(2.5 * first, Corrections(), 3, ctx=ctx))
    assert relative_error(scaled, 2.5 * sum(propagate(first, Corrections(), 3, ctx=ctx))) < 1e-5


# ------------------------------------------------------------------ storage, settings


def test_l2_grid_round_trip_and_bad_input(ctx):
    grid = LpvGrid(ctx, 4, sh_order=2)
    try:
        values = np.random.default_rng(55).standard_normal((3, 4, 4, 4, 9)).astype(np.float32)
        grid.write(values)
        assert grid.coefficients == 9 and grid.textures[0].size == (4, 4, 12)
        assert np.array_equal(grid.read(), values)
        with pytest.raises(ValueError, match=r"\(3, 4, 4, 4, 9\)"):
            grid.write(values[..., :4])
    finally:
        grid.release()
    with pytest.raises(ValueError, match="sh_order must be 1"):
        LpvGrid(ctx, 4, sh_order=3)
    with pytest.raises(ValueError, match="sh_order must be one of 1, 2"):
        Settings(sh_order=0)
    from explorer.lpv.cascades import texture_bytes

    # four light grids of 3 channels, 3 texels per cell instead of 1
    assert texture_bytes(8, 1, "rgba32f", False, sh_groups=3) - texture_bytes(
        8, 1, "rgba32f", False) == 4 * 3 * 2 * 16 * 8 ** 3
    with pytest.raises(ValueError, match="4 \\(L1\\) or 9 \\(L2\\)"):
        propagate(np.zeros((3, 4, 4, 4, 5)), ctx=ctx)


def test_l2_half_float_grid_propagates(ctx):
    grid = random_l2_grid(56, 8, 0.3)
    half = propagate(grid, Corrections(), 2, ctx=ctx, fmt="rgba16f")
    assert half[0].shape == (3, 8, 8, 8, 9)
    assert relative_error(half[-1], twin.propagate(grid, Corrections(), 2)[-1]) < 5e-3


def test_pipeline_with_l2(ctx):
    from explorer.lpv.pipeline import Pipeline

    settings = Settings(grid_size=8, iterations=3, rsm_size=16, width=32, height=32,
                        gather_damping=True)
    pipeline = Pipeline(settings, ctx=ctx)
    try:
        first = pipeline.run(keep_steps=True)
        second = pipeline.run(settings.with_changes(sh_order=2), keep_steps=True)
        assert second.stages_run == ("inject", "propagate", "gather", "display")
        assert first.accumulated.shape[-1] == 4 and second.accumulated.shape[-1] == 9
        # The L1 part of the injected L2 grid is the L1 grid (same flux); propagation then
        # differs through band 2. (The Cornell walls lie on cell faces, so compare with the
        # GPU's own injected grid rather than a float64 injection.)
        assert np.allclose(second.steps[0][..., :4], first.steps[0], rtol=1e-6, atol=1e-9)
        assert np.allclose(second.audit.injected, first.audit.injected, rtol=1e-5)
        accumulated = sum(twin.propagate(second.steps[0], Corrections(), 3))
        assert relative_error(second.accumulated, accumulated) < 1e-4
        lit = second.indirect.sum(axis=2) > 0
        assert lit.mean() > 0.3 and np.isfinite(second.indirect).all()
    finally:
        pipeline.release()


# ------------------------------------------------------------------ cascades


@pytest.mark.parametrize("shader_filter", [False, True], ids=["texture-unit", "shader-filter"])
def test_l2_cascade_gather_blends_like_numpy(setup, ctx, shader_filter):
    """Two L2 cascades in the final gather: Σ_k W_k·clamp+(<s_k, lobe₂(−n)>)/c_k²."""
    from gather_cases import TOLERANCE, filtering, smooth_grid, visible_points

    from explorer.lpv.cascades import CascadeInput, SampledGrid, blend_weights, cascade_specs
    from explorer.lpv.passes.rsm import read_texture

    _, scene, view, shadow, gbuffer, gather, _, spec = setup
    n = spec.resolution
    specs = cascade_specs(spec, 2, (0.1, -0.3, 0.05))
    rng = np.random.default_rng(70)
    base = np.concatenate([smooth_grid(spec), np.zeros((3, n, n, n, 5), np.float32)], -1)
    base[..., 4:] = 0.004 * rng.standard_normal(base[..., 4:].shape)
    values = [base, 0.5 * base[:, ::-1].copy()]
    grids = [LpvGrid(ctx, n, sh_order=2) for _ in range(2)]
    try:
        for grid, value in zip(grids, values):
            grid.write(value)
        cascades = [CascadeInput(s, g.textures) for s, g in zip(specs, grids)]
        with filtering(gather, shader_filter):
            gather.run(gbuffer, ShadowMaps(shadow, view), SampledGrid(cascades, sh_order=2))
        indirect = read_texture(gather.targets["indirect"])[..., :3]
    finally:
        for grid in grids:
            grid.release()
    points, normals, albedo, valid = visible_points(gbuffer)
    weights = blend_weights(specs, points)
    assert np.any((weights[:, 0] > 0.05) & (weights[:, 1] > 0.05))
    expected = twin.indirect_radiance(
        albedo, twin.gather_cascades(values, specs, points, normals))
    assert relative_error(indirect[valid], expected) < TOLERANCE


def test_pipeline_with_l2_cascades(ctx):
    from explorer.lpv.pipeline import Pipeline

    settings = Settings(grid_size=16, iterations=3, rsm_size=16, width=32, height=32,
                        cascades=2, sh_order=2)
    pipeline = Pipeline(settings, ctx=ctx)
    try:
        result = pipeline.run()
        assert [a.shape[-1] for a in result.cascade_accumulated] == [9, 9]
        coarse = result.cascade_accumulated[1]
        assert np.abs(coarse[..., 4:]).max() > 0
        assert (result.indirect.sum(axis=2) > 0).mean() > 0.3
    finally:
        pipeline.release()


# ------------------------------------------------------------------ command line
# (last: the CLI creates and releases contexts of its own)


def test_cli_sh_order_flags(tmp_path, capsys, gl_context):
    import json

    from explorer.cli import main as cli_main

    out = tmp_path / "l2.png"
    assert cli_main(["render", "--sh-order", "2", "--grid", "8", "--iterations", "2",
                     "--rsm-size", "16", "--size", "32x32", "--out", str(out),
                     "--view", "final", "--view", "grid-slice", "--coefficient", "8"]) == 0
    assert (tmp_path / "l2-grid-slice.png").is_file()
    assert cli_main(["render", "--sh-order", "3", "--out", str(out)]) == 2
    assert "sh_order must be one of 1, 2" in capsys.readouterr().err
    # L1 has no coefficient 8: refused before any work
    assert cli_main(["render", "--grid", "8", "--iterations", "1", "--rsm-size", "16",
                     "--size", "32x32", "--out", str(out), "--view", "grid-slice",
                     "--coefficient", "8"]) == 2
    assert "--coefficient must be in [0, 3] with --sh-order 1" in capsys.readouterr().err

    bench = tmp_path / "bench.json"
    assert cli_main(["bench", "--quick", "--grids", "8", "--iterations", "2",
                     "--sh-order", "1,2", "--variants", "none", "--json", str(bench)]) == 0
    rows = json.loads(bench.read_text())["rows"]
    assert [(row["variant"], row["sh_order"]) for row in rows] == [
        ("default", 1), ("default", 2), ("baseline", 1)]   # the baseline kernel is L1
    assert all(row["propagation_gbs"] > 0 for row in rows[:2])
    capsys.readouterr()

    table_dir = tmp_path / "cmp"
    assert cli_main(["compare", "--preset", "corrected", "--sh-order", "1,2", "--width", "24",
                     "--height", "20", "--rsm-size", "8", "--grid-size", "8",
                     "--iterations", "2", "--quiet", "--out", str(table_dir)]) == 0
    table = capsys.readouterr().out
    assert "| corrected L1 | 2 | image |" in table and "| corrected L2 | 2 | image |" in table
    assert (table_dir / "lpv-corrected-L2.png").is_file()
    assert cli_main(["compare", "--sh-order", "1,3", "--quiet", "--out", str(table_dir)]) == 2
    assert "sh_order must be one of 1, 2, got 3" in capsys.readouterr().err
    # the commands made and released contexts of their own: the session's is current again
    gl_context.__enter__()
