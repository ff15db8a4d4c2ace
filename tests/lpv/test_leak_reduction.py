"""Leak reduction (docs/MODEL.md "Injection" offset, "Final gather" damping): GPU against
the numpy twin, and the Settings checks of the new fields."""

from __future__ import annotations

import numpy as np
import pytest
from lpv_cases import random_vpls, relative_error

from explorer.lpv import inject
from explorer.lpv.grid import GridSpec
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.vpl import VplArrays
from explorer.truth.gbuffer import gbuffer_from_frame

AXES = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)


def axis_aligned(vpls: VplArrays, seed: int) -> VplArrays:
    """The VPLs with axis-aligned normals: a half-cell offset then moves them by exactly
    half a cell, still clear of cell faces (random_vpls keeps 10 % away from them)."""
    normals = AXES[np.random.default_rng(seed).integers(0, 6, vpls.count)]
    return VplArrays(vpls.positions, normals, vpls.flux, vpls.depth, vpls.texel_area)


@pytest.mark.parametrize("mode", ["points", "compute"])
def test_injection_offset_matches_reference(ctx, mode):
    spec = GridSpec((0.5, -1.0, 2.0), 0.25, 8)
    vpls = axis_aligned(random_vpls(41, spec, 120, outside=5), 41)
    for offset in (0.0, 0.5):
        gpu = inject(vpls, spec, mode=mode, ctx=ctx, offset_cells=offset)
        expected = twin.inject(vpls, spec, offset_cells=offset)
        assert relative_error(gpu, expected) < 1e-5
    moved = twin.inject(vpls, spec, offset_cells=0.5)
    assert relative_error(moved, twin.inject(vpls, spec)) > 0.1  # it did move VPLs


def test_offset_of_one_cell_moves_a_vpl_into_the_next_cell(ctx):
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 4)
    vpls = VplArrays(np.array([[1.3, 1.3, 1.3]]), np.array([[0.0, 0.0, 1.0]]),
                     np.ones((1, 3)), np.ones(1), 0.01)
    grid = inject(vpls, spec, ctx=ctx, offset_cells=1.0)
    assert np.argwhere(grid[0, ..., 0] > 0).tolist() == [[1, 1, 2]]


def test_bad_offsets_are_refused(ctx):
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 4)
    vpls = random_vpls(42, spec, 3)
    for bad in (-0.1, float("nan")):
        with pytest.raises(ValueError, match="injection offset"):
            inject(vpls, spec, ctx=ctx, offset_cells=bad)
        with pytest.raises(ValueError, match="injection offset"):
            twin.inject(vpls, spec, offset_cells=bad)


def _frame(ctx, **changes):
    settings = Settings(width=24, height=20, rsm_size=16, grid_size=8, **changes)
    with Pipeline(settings, ctx) as pipeline:
        return pipeline.run()


def test_cornell_walls_on_cell_faces_agree_with_the_reference_once_offset(ctx):
    """GridSpec.enclosing puts the Cornell walls on cell boundaries: with the half-cell
    offset every VPL is half a cell clear of them, so GPU and float64 agree."""
    frame = _frame(ctx, scene="cornell", iterations=0, injection_offset_cells=0.5)
    expected = twin.inject(frame.vpls, frame.grid_spec, offset_cells=0.5)
    assert relative_error(frame.accumulated, expected) < 1e-5
    # Without the offset float32 and float64 put some VPLs on different sides of a wall
    # (llvmpipe: the largest cell differs by 100 % of the largest value); how many depends
    # on the driver's rounding, so that is not asserted here.


@pytest.mark.parametrize("damping", [False, True])
def test_gather_damping_matches_the_numpy_gather(ctx, damping):
    frame = _frame(ctx, scene="room", iterations=2, gather_damping=damping)
    gbuffer = gbuffer_from_frame(frame, ctx=ctx)
    valid = gbuffer.valid
    irradiance = twin.gather(frame.accumulated, frame.grid_spec, gbuffer.position[valid],
                            gbuffer.normal[valid], damping=damping)
    expected = twin.indirect_radiance(gbuffer.albedo[valid], irradiance)
    assert expected.max() > 0
    assert relative_error(frame.indirect[valid], expected) < 1e-5   # as test_pass_gather.py
    if damping:
        undamped = twin.gather(frame.accumulated, frame.grid_spec, gbuffer.position[valid],
                              gbuffer.normal[valid])
        assert np.all(irradiance <= undamped + 1e-12)
        assert irradiance.sum() < 0.99 * undamped.sum()  # it does damp something


@pytest.mark.parametrize("changes, message", [
    ({"injection_offset_cells": -0.5}, "injection_offset_cells"),
    ({"injection_offset_cells": 1.5}, "injection_offset_cells"),
    ({"injection_offset_cells": "half"}, "injection_offset_cells"),
    ({"gather_damping": 1}, "gather_damping"),
    ({"bounces": 0}, "bounces"),
    ({"bounces": 3}, "bounces"),
    ({"bounces": 2}, "geometry_volume"),
])
def test_settings_refuse_out_of_range_values(changes, message):
    with pytest.raises(ValueError, match=message):
        Settings(**changes)


def test_settings_accept_the_new_fields():
    settings = Settings(injection_offset_cells=0, gather_damping=True, bounces=2,
                        geometry_volume="one-sided")
    assert settings.bounces == 2 and settings.injection_offset_cells == 0


def test_render_and_compare_flags(tmp_path, capsys, gl_context):
    from explorer.cli import main

    small = ["--size", "24x20", "--rsm-size", "8", "--grid", "8", "--iterations", "2"]
    out = tmp_path / "f.png"
    assert main(["render", "--out", str(out), *small, "--injection-offset", "0",
                 "--gather-damping", "--bounces", "2", "--geometry-volume", "one-sided",
                 "--audit"]) == 0
    printed = capsys.readouterr().out
    assert out.exists() and "reflected" in printed
    assert main(["render", "--out", str(out), *small, "--bounces", "2"]) == 2
    assert "geometry_volume" in capsys.readouterr().err
    assert main(["render", "--out", str(out), *small, "--injection-offset", "-1"]) == 2
    assert "injection_offset_cells" in capsys.readouterr().err
    tiny = ["--width", "24", "--height", "20", "--rsm-size", "8", "--grid-size", "8",
            "--iterations", "2", "--quiet", "--preset", "corrected"]
    assert main(["compare", "--out", str(tmp_path / "c"), *tiny, "--bounces", "2",
                 "--geometry-volume", "one-sided", "--gather-damping",
                 "--injection-offset", "0.25"]) == 0
    printed = capsys.readouterr().out
    assert "injection offset 0.25 cells, gather damping on, bounces 2" in printed
    assert main(["compare", "--out", str(tmp_path / "c"), *tiny, "--bounces", "2"]) == 2
    assert "geometry_volume" in capsys.readouterr().err
