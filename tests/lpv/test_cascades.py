"""Cascaded LPV (docs/MODEL.md "Cascades"): nesting and snapping of the grids, the
partition-of-unity blend on the CPU and in the gather shader, and cascaded frames."""

from __future__ import annotations

import json

import numpy as np
import pytest
from gather_cases import (
    FILTERS,
    TOLERANCE,
    filtering,
    smooth_grid,
    visible_points,
)
from lpv_cases import relative_error

from explorer.cli import main as cli_main
from explorer.lpv.cascades import (
    CASCADE_BAND_CELLS,
    CASCADE_EDGE_CELLS,
    CascadeInput,
    SampledGrid,
    blend_weights,
    cascade_specs,
    check_limits,
    own_weight,
)
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.gather import GatherInputs
from explorer.lpv.passes.light_records import ShadowMaps
from explorer.lpv.passes.rsm import read_texture
from explorer.lpv.passes.textures import LpvGrid
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.views import CASCADE_COLOURS
from explorer.lpv.vpl import VplArrays

SINGLE = GridSpec((-1.2, -1.0, -1.1), 0.25, 16)
SMALL = Settings(scene="cornell", grid_size=16, iterations=6, rsm_size=32, width=48,
                 height=48)


def inside(inner: GridSpec, outer: GridSpec, margin_cells: float) -> bool:
    """Whether ``inner`` lies in ``outer`` with ``margin_cells`` of ``outer`` to spare."""
    lo_in, lo_out = np.asarray(inner.origin), np.asarray(outer.origin)
    margin = margin_cells * outer.cell_size
    return bool(np.all(lo_in >= lo_out + margin - 1e-9) and np.all(
        lo_in + inner.extent <= lo_out + outer.extent - margin + 1e-9))


@pytest.mark.parametrize("count", [2, 3, 4])
def test_cascades_nest_double_and_snap_to_their_cells(count):
    rng = np.random.default_rng(count)
    for centre in rng.uniform(-3.0, 3.0, (50, 3)):
        specs = cascade_specs(SINGLE, count, centre)
        assert len(specs) == count
        assert specs[-1].cell_size == pytest.approx(SINGLE.cell_size)  # default extent
        for k, spec in enumerate(specs):
            assert spec.resolution == SINGLE.resolution
            assert spec.cell_size == pytest.approx(specs[0].cell_size * 2 ** k)
            # on the lattice of its own cells, anchored at the single grid's origin
            steps = (np.asarray(spec.origin) - SINGLE.origin) / spec.cell_size
            assert np.allclose(steps, np.round(steps), atol=1e-9)
            # the centre lies within a cell of the cascade's middle
            middle = np.asarray(spec.origin) + 0.5 * spec.extent
            assert np.all(np.abs(middle - centre) <= spec.cell_size + 1e-9)
        for fine, coarse in zip(specs, specs[1:]):
            # N/2 − 1 fine cells of room = N/4 − 1/2 coarse cells, more than the blend band
            assert inside(fine, coarse, SINGLE.resolution / 4 - 0.5)
    # moving the centre by less than it takes to reach the next lattice point keeps
    # every grid still; moving it by one coarse cell moves every grid by whole cells
    lattice_point = np.asarray(SINGLE.origin) + 10 * SINGLE.cell_size
    specs = cascade_specs(SINGLE, 3, lattice_point)
    finest = specs[0].cell_size
    for nudge in rng.uniform(-0.45 * finest, 0.45 * finest, (10, 3)):
        assert cascade_specs(SINGLE, 3, lattice_point + nudge) == specs
    moved = cascade_specs(SINGLE, 3, lattice_point + (specs[-1].cell_size, 0.0, 0.0))
    for before, after in zip(specs, moved):
        shift = (np.asarray(after.origin) - before.origin) / before.cell_size
        assert np.allclose(shift, np.round(shift)) and shift[0] >= 1


def test_one_cascade_is_the_single_grid_and_the_extent_setting_sets_the_finest_cells():
    assert cascade_specs(SINGLE, 1, (5.0, 5.0, 5.0)) == [SINGLE]
    specs = cascade_specs(SINGLE, 2, (0.0, 0.0, 0.0), finest_extent=2.0)
    assert specs[0].extent == pytest.approx(2.0) and specs[1].extent == pytest.approx(4.0)
    with pytest.raises(ValueError, match="cascades must be"):
        cascade_specs(SINGLE, 5, (0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="cascades must be"):
        Settings(cascades=0)
    with pytest.raises(ValueError, match="cascade_focus"):
        Settings(cascade_focus=2.0)


def test_blend_weights_are_a_continuous_partition_of_unity():
    specs = cascade_specs(SINGLE, 3, (0.3, -0.2, 0.1))
    rng = np.random.default_rng(7)
    points = rng.uniform(-8.0, 8.0, (20000, 3))
    weights = blend_weights(specs, points)
    assert np.all(weights >= 0.0) and np.allclose(weights.sum(axis=-1), 1.0)
    # a point in the fine cascade's band is covered by two cascades: both weigh in, the
    # weights sum to 1
    fine = specs[0]
    band = np.array(fine.origin) + (CASCADE_EDGE_CELLS + 0.5 * CASCADE_BAND_CELLS) \
        * fine.cell_size + np.array([0.0, 0.5, 0.5]) * fine.extent
    w = blend_weights(specs, band[None])[0]
    assert 0.1 < w[0] < 0.9 and 0.1 < w[1] < 0.9 and w[2] == 0.0
    assert w.sum() == pytest.approx(1.0)
    deep = np.array(fine.origin) + 0.5 * fine.extent
    assert blend_weights(specs, deep[None])[0] == pytest.approx([1.0, 0.0, 0.0])
    # continuity: along a line through every band, no weight jumps between samples
    # (smoothstep slope 1.5 per band width)
    line = np.linspace(-6.0, 6.0, 24001)
    points = np.stack([line, np.full_like(line, 0.31), np.full_like(line, -0.17)], axis=-1)
    weights = blend_weights(specs, points)
    step = line[1] - line[0]
    steepest = 1.5 / (CASCADE_BAND_CELLS * specs[0].cell_size)
    assert np.max(np.abs(np.diff(weights, axis=0))) <= 1.01 * steepest * step
    assert own_weight(fine, np.array(fine.origin)[None])[0] == 0.0


@FILTERS
@pytest.mark.parametrize("model", [True, False], ids=["irradiance", "dx11-gather"])
def test_gather_shader_blends_like_numpy(setup, ctx, model,  # noqa: F811 (fixture)
                                         shader_filter):
    _, scene, view, shadow, gbuffer, gather, grid, spec = setup
    n = spec.resolution
    specs = cascade_specs(spec, 2, (0.1, -0.3, 0.05))
    values = [smooth_grid(spec), 0.5 * smooth_grid(spec)[:, ::-1].copy()]
    coarse = LpvGrid(ctx, n)
    try:
        grid.write(values[0])
        coarse.write(values[1])
        cascades = [CascadeInput(specs[0], grid.textures), CascadeInput(specs[1],
                                                                         coarse.textures)]
        with filtering(gather, shader_filter):
            gather.run(gbuffer, ShadowMaps(shadow, view), SampledGrid(cascades),
                       GatherInputs(switches=(("u_irradiance_gather", int(model)),)))
        indirect = read_texture(gather.targets["indirect"])[..., :3]
    finally:
        coarse.release()
    points, normals, albedo, valid = visible_points(gbuffer)
    weights = blend_weights(specs, points)
    assert np.any((weights[:, 0] > 0.05) & (weights[:, 1] > 0.05))   # the band is on screen
    expected = twin.indirect_radiance(albedo, twin.gather_cascades(
        values, specs, points, normals, irradiance=model))
    assert relative_error(indirect[valid], expected) < TOLERANCE


@FILTERS
@pytest.mark.parametrize("count", [1, 2])
def test_gather_reads_a_grid_of_any_shape_like_numpy(setup, ctx,  # noqa: F811 (fixture)
                                                     count, shader_filter):
    """A 14 × 19 × 11 grid (and two cascades of it) around the gather scene: the GPU's
    trilinear lookups and blend weights per axis equal the twin's."""
    _, scene, view, shadow, gbuffer, gather, _, cube = setup
    single = GridSpec(np.asarray(cube.origin) + (0.1, -0.3, 0.2), 0.9 * cube.cell_size,
                      (14, 19, 11))
    specs = cascade_specs(single, count, (0.1, -0.3, 0.05))
    values = [smooth_grid(single), 0.5 * smooth_grid(single)[:, ::-1].copy()][:count]
    grids = [LpvGrid(ctx, single.cells) for _ in specs]
    try:
        for grid, value in zip(grids, values):
            grid.write(value)
        cascades = [CascadeInput(spec, grid.textures) for spec, grid in zip(specs, grids)]
        with filtering(gather, shader_filter):
            gather.run(gbuffer, ShadowMaps(shadow, view), SampledGrid(cascades),
                       GatherInputs())
        indirect = read_texture(gather.targets["indirect"])[..., :3]
    finally:
        for grid in grids:
            grid.release()
    points, normals, albedo, valid = visible_points(gbuffer)
    expected = twin.indirect_radiance(albedo, twin.gather_cascades(
        values, specs, points, normals))
    assert np.abs(expected).max() > 0
    assert relative_error(indirect[valid], expected) < TOLERANCE


def test_one_cascade_reproduces_the_single_grid_exactly(gl_context, ctx):   # ctx: no GL errors
    with Pipeline(SMALL, ctx=gl_context) as pipeline:
        one = pipeline.run(SMALL.with_changes(cascades=1))
        assert one.cascade_specs == [one.grid_spec]
        scene = pipeline.scene_state.scene
        assert one.grid_spec == GridSpec.enclosing(scene.bounds_min, scene.bounds_max, 16)
        image = one.final_image.copy()
        # the cascade code path with two identical cascades gives the same image
        gather = pipeline.state.gather_pass
        grid = pipeline.state.levels[0].output.accumulated
        twice = [CascadeInput(one.grid_spec, grid.textures)] * 2
        lights = pipeline.light_views
        gather.run(pipeline.state.gbuffer_pass, lights.shadow_maps, SampledGrid(twice))
        blended = sum(read_texture(gather.targets[name])[..., :3]
                      for name in ("direct", "indirect"))
        assert np.allclose(SMALL.exposure * blended, image, rtol=1e-5, atol=1e-7)
        # one cascade ignores the cascade placement settings
        other = pipeline.run(SMALL.with_changes(cascades=1, cascade_focus=0.2,
                                                cascade_extent=0.7,
                                                cascade_iterations="same-distance"))
        assert other.grid_spec == one.grid_spec
        assert np.array_equal(other.final_image, image)


def test_two_cascade_cornell_is_lit_and_the_coarse_cascade_sees_outer_light(gl_context, ctx):
    with Pipeline(SMALL, ctx=gl_context) as pipeline:
        result = pipeline.run(SMALL.with_changes(cascades=2))
        fine, coarse = result.cascade_specs
        assert coarse.cell_size == pytest.approx(2 * fine.cell_size)
        assert len(result.cascade_accumulated) == 2 and len(result.cascade_audits) == 2
        assert result.accumulated is result.cascade_accumulated[0]
        assert result.direct.mean() > 0.05
        visible = result.albedo.sum(axis=-1) > 0
        assert (result.indirect.sum(axis=-1)[visible] > 0).mean() > 0.9   # lit everywhere
        assert np.all(result.audit.gathered > 0)
        # the coarse cascade holds every RSM VPL, the fine one only those inside it
        audits = result.cascade_audits
        assert np.all(audits[1].injected >= audits[0].injected * (1 - 1e-5))
        assert np.allclose(audits[1].injected, result.audit.rsm, rtol=1e-4)
        weights = pipeline.view("cascade-weights")
        assert weights.shape == (48, 48, 3)
        colours = CASCADE_COLOURS[:2]
        seen = weights[visible]
        for colour in colours:   # some pixels use only the fine, some only the coarse one
            assert np.any(np.all(np.abs(seen - colour) < 1e-5, axis=-1))
        mixed = ~np.any(np.all(np.abs(seen[:, None] - colours) < 1e-5, axis=-1), axis=-1)
        assert mixed.any()       # and the blend band is on screen
        slices = [pipeline.view("grid-slice", cascade=k) for k in (0, 1)]
        assert not np.array_equal(*slices)
        with pytest.raises(ValueError, match="cascade 2 does not exist"):
            pipeline.view("grid-slice", cascade=2)

        # one VPL outside the fine cascade, inside the coarse one
        where = np.asarray(coarse.origin) + 0.5 * coarse.extent
        where[0] = coarse.origin[0] + 1.5 * coarse.cell_size
        assert fine.inside(fine.cell_index(where)) == np.False_
        outer = VplArrays(where[None], np.array([[1.0, 0.0, 0.0]]), np.ones((1, 3)),
                          np.ones(1), 1e-4)
        lit = pipeline.run(SMALL.with_changes(cascades=2), vpls=outer)
        assert np.allclose(lit.cascade_audits[0].injected, 0.0)
        assert np.allclose(lit.cascade_audits[1].injected, 1.0, rtol=1e-4)
        assert lit.cascade_audits[1].accumulated.sum() > 3.0   # propagated in the coarse
        assert lit.indirect.max() > 0
        # same-distance: the finer cascade propagates twice the steps
        far = pipeline.run(SMALL.with_changes(cascades=2, cascade_iterations="same-distance"))
        steps = [audit.per_step.shape[0] - 1 for audit in far.cascade_audits]
        assert steps == [2 * SMALL.iterations, SMALL.iterations]


def test_camera_moves_shift_cascades_by_whole_cells_only(gl_context, ctx):   # ctx: no GL errors
    with Pipeline(SMALL, ctx=gl_context) as pipeline:
        settings = SMALL.with_changes(cascades=2)
        first = pipeline.run(settings)
        camera = pipeline.scene_state.scene.camera
        fine = first.cascade_specs[0].cell_size
        # the focus point at the lattice point its cascades snapped to: nudges below half
        # a fine cell move no grid, so only the camera's own stages run again
        target = np.asarray(first.cascade_specs[1].origin) + 8 * 2 * fine   # both lattices
        eye = np.asarray(camera.eye) + target - np.asarray(camera.target)
        centred = pipeline.run(settings.with_changes(camera=(tuple(eye), tuple(target))))
        nudge = np.array([0.3, -0.2, 0.25]) * fine
        moved = pipeline.run(settings.with_changes(
            camera=(tuple(eye + nudge), tuple(target + nudge))))
        assert moved.cascade_specs == centred.cascade_specs
        assert moved.stages_run == ("gbuffer", "gather", "display")   # the camera's only
        # a whole coarse cell: every cascade moves by whole cells, and the LPV runs again
        step = np.array([2 * fine, 0.0, 0.0])
        far = pipeline.run(settings.with_changes(camera=(tuple(eye + step),
                                                         tuple(target + step))))
        assert "propagate" in far.stages_run
        for before, after in zip(centred.cascade_specs, far.cascade_specs):
            shift = (np.asarray(after.origin) - before.origin) / before.cell_size
            assert np.allclose(shift, np.round(shift), atol=1e-6)
            assert np.allclose(shift, [2 * fine / before.cell_size, 0, 0], atol=1e-6)


def test_settings_beyond_the_limits_are_refused(gl_context):
    with pytest.raises(ValueError, match="budget"):
        check_limits(256, 4, "rgba32f", False, 4 << 30, 32)
    check_limits(128, 4, "rgba32f", True, 4 << 30, 32)   # 1.8 GiB: fits
    with pytest.raises(ValueError, match="GL_MAX_TEXTURE_IMAGE_UNITS"):
        check_limits(16, 4, "rgba32f", False, 4 << 30, 16)
    with pytest.raises(ValueError, match="grid_size >= 8"):
        check_limits(4, 2, "rgba32f", False, 4 << 30, 32)
    with Pipeline(SMALL, ctx=gl_context) as pipeline:
        pipeline.memory_budget_bytes = 1 << 20
        with pytest.raises(ValueError, match="more than the memory budget of 1.0 MiB"):
            pipeline.run(SMALL.with_changes(cascades=2))


def test_cli_render_compare_and_bench_take_cascades(tmp_path, capsys, gl_context):
    out = tmp_path / "c.png"
    assert cli_main(["render", "--cascades", "2", "--grid", "8", "--iterations", "2",
                     "--rsm-size", "16", "--size", "24x24", "--view", "grid-slice",
                     "--cascade", "1", "--audit", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert out.exists() and "cascade 1" in printed
    code = cli_main(["compare", "--preset", "corrected", "--reference", "unoccluded",
                     "--width", "16", "--height", "16", "--rsm-size", "8", "--grid-size",
                     "8", "--iterations", "2", "--cascades", "1,2", "--quiet",
                     "--out", str(tmp_path / "cmp")])
    printed = capsys.readouterr()
    assert code == 0, printed.err
    assert "| corrected | 2, 1 cascade | image |" in printed.out
    assert "| corrected | 2, 2 cascades | image |" in printed.out
    assert (tmp_path / "cmp" / "lpv-corrected-c2.png").exists()
    assert cli_main(["compare", "--cascades", "9", "--quiet"]) == 2
    assert "cascades must be" in capsys.readouterr().err
    bench = tmp_path / "bench.json"
    assert cli_main(["bench", "--quick", "--grids", "8", "--iterations", "2",
                     "--cascades", "1,2", "--variants", "none", "--json", str(bench)]) == 0
    rows = json.loads(bench.read_text())["rows"]
    assert [(row["variant"], row["grid"], row["cascades"]) for row in rows] == [
        ("default", 8, 1), ("default", 8, 2), ("baseline", 8, 1)]


def test_gather_damping_acts_in_every_cascade(gl_context, ctx):   # ctx: no GL errors
    """Damping multiplies each cascade's irradiance by a factor in [0, 1]: with cascades it
    can only darken the indirect light, and it must change it somewhere."""
    with Pipeline(SMALL, ctx=gl_context) as pipeline:
        plain = pipeline.run(SMALL.with_changes(cascades=2)).indirect.copy()
        damped = pipeline.run(SMALL.with_changes(cascades=2, gather_damping=True)).indirect
    assert np.all(damped <= plain * (1 + 1e-5) + 1e-7)
    assert np.abs(damped - plain).max() > 1e-3 * plain.max()
