"""Grids of any shape (docs/MODEL.md "Notation and storage"): a GridSpec of nx × ny × nz
cells, the exact grid a scene file or the settings ask for, and every GPU pass against
the numpy twin on an odd 7 × 12 × 5 grid."""

from __future__ import annotations

import numpy as np
import pytest
from lpv_cases import assert_audits_match, random_vpls, relative_error

from explorer.lpv import inject
from explorer.lpv import inject as gpu_inject
from explorer.lpv.cascades import cascade_specs, frame_specs, texture_bytes
from explorer.lpv.grid import GridSpec
from explorer.lpv.limits import memory_requests
from explorer.lpv.passes.geometry import inject_geometry
from explorer.lpv.passes.propagate import propagate_with_audit, slabs
from explorer.lpv.settings import Corrections, Settings
from explorer.lpv.twin import light_grid as twin
from explorer.schema import SettingError

ODD = GridSpec((-1.6, 0.0, -2.6), 0.4, (7, 12, 5))
ITERATIONS = 3


def test_a_grid_spec_holds_its_cells_per_axis():
    assert ODD.cells == (7, 12, 5) and ODD.cell_count == 420
    np.testing.assert_allclose(ODD.extents, [2.8, 4.8, 2.0])
    assert ODD.inside(np.array([[6, 11, 4], [0, 0, 0]])).tolist() == [True, True]
    assert ODD.inside(np.array([[7, 0, 0], [0, 12, 0], [0, 0, 5], [6, 11, -1]])).tolist() \
        == [False] * 4
    assert ODD.uniforms()["u_grid_cells"] == (7, 12, 5)
    with pytest.raises(ValueError, match="cubic grid.*7x12x5"):
        int(ODD.resolution)
    with pytest.raises(ValueError, match="at least 1 cell"):
        GridSpec((0, 0, 0), 1.0, (4, 0, 4))
    # the cube: the old constructor and the new one are the same grid
    assert GridSpec((0, 0, 0), 0.5, 8) == GridSpec((0, 0, 0), 0.5, (8, 8, 8)) == \
        GridSpec((0, 0, 0), 0.5, resolution=8)
    assert GridSpec((0, 0, 0), 0.5, 8).resolution == 8


def test_the_settings_give_an_exact_grid_all_three_together():
    exact = Settings(grid_cells=(7, 12, 5), grid_origin=(-1.6, 0.0, -2.6), grid_cell_size=0.4)
    assert exact.grid_shape == (7, 12, 5)
    assert Settings().grid_shape == (32, 32, 32)
    for partial in ({"grid_cells": (7, 12, 5)}, {"grid_origin": (0, 0, 0)},
                    {"grid_cells": (7, 12, 5), "grid_cell_size": 0.4}):
        with pytest.raises(SettingError, match="together"):
            Settings(**partial)
    with pytest.raises(SettingError, match="grid_cells must be three whole numbers"):
        Settings(grid_cells=(7, 0, 5), grid_origin=(0, 0, 0), grid_cell_size=0.4)
    with pytest.raises(SettingError, match="grid_cell_size"):
        Settings(grid_cells=(7, 2, 5), grid_origin=(0, 0, 0), grid_cell_size=0.0)

    class Box:
        bounds_min, bounds_max, exact_grid = (0, 0, 0), (1, 1, 1), ((3, 4, 5), (9, 9, 9), 2.0)

    # the settings' grid wins over the scene's, the scene's over the fitted cube
    assert frame_specs(exact, Box)[0] == ODD
    assert frame_specs(Settings(), Box)[0] == GridSpec((9, 9, 9), 2.0, (3, 4, 5))
    Box.exact_grid = None
    assert frame_specs(Settings(grid_size=8), Box)[0] == GridSpec.enclosing(
        (0, 0, 0), (1, 1, 1), 8)


def test_the_budget_counts_every_cell():
    exact = Settings(grid_cells=(7, 12, 5), grid_origin=(0, 0, 0), grid_cell_size=0.4)
    assert texture_bytes((7, 12, 5), 1, "rgba32f", True) == \
        texture_bytes(1, 1, "rgba32f", False) * 420 + 16 * 8 * 13 * 6
    grids = {r.name: r for r in memory_requests(exact)}["grid_cells"]
    assert "7x12x5 cells" in grids.what
    geometry = exact.geometry_volume != "off"
    assert grids.bytes == texture_bytes((7, 12, 5), 1, "rgba32f", geometry) + \
        3 * 420 * 4 * 4 * 2
    assert slabs((7, 12, 5)) == [(0, 5)]
    assert slabs((64, 64, 20), 64 * 64 * 8) == [(0, 8), (8, 16), (16, 20)]


def test_cascades_keep_the_single_grids_cells():
    specs = cascade_specs(ODD, 2, (0.0, 1.0, -1.0))
    assert [s.cells for s in specs] == [(7, 12, 5)] * 2
    assert specs[1].cell_size == pytest.approx(2 * specs[0].cell_size)
    # each cascade is centred on the focus point to within a cell, per axis
    for spec in specs:
        middle = np.asarray(spec.origin) + 0.5 * spec.extents
        assert np.all(np.abs(middle - (0.0, 1.0, -1.0)) <= spec.cell_size)


@pytest.mark.parametrize("mode", ["points", "compute"])
@pytest.mark.parametrize("sh_order", [1, 2])
def test_injection_matches_the_twin_on_an_odd_grid(ctx, mode, sh_order):
    vpls = random_vpls(11, ODD, 300, outside=8)
    grid = gpu_inject(vpls, ODD, mode=mode, ctx=ctx, sh_order=sh_order)
    want = twin.inject(vpls, ODD, mode=mode, sh_order=sh_order)
    assert grid.shape == (3, 7, 12, 5, 4 if sh_order == 1 else 9)
    assert relative_error(grid, want) < 1e-5
    assert np.count_nonzero(want[0, ..., 0]) > 100          # many cells, all three axes


@pytest.mark.parametrize("mode", ["one-sided", "double-sided"])
def test_geometry_injection_matches_the_twin_on_an_odd_grid(ctx, mode):
    vpls = random_vpls(12, ODD, 300, outside=8, texel_area=0.05)
    volume = inject_geometry(vpls, ODD, mode=mode, ctx=ctx)
    want = twin.inject_geometry(vpls, ODD, mode=mode)
    assert volume.shape == (8, 13, 6, 4)
    assert relative_error(volume, want) < 1e-5


@pytest.mark.parametrize("sh_order, geometry_mode, neighbours",
                         [(1, None, 6), (1, "one-sided", 6), (2, None, 6),
                          (2, "double-sided", 6), (1, None, 26), (1, "one-sided", 26),
                          (2, "one-sided", 26)])
def test_propagation_matches_the_twin_on_an_odd_grid(ctx, sh_order, geometry_mode, neighbours):
    corrections = Corrections()
    vpls = random_vpls(13, ODD, 200, outside=5, texel_area=0.05)
    grid = inject(vpls, ODD, corrections, "points", ctx=ctx, sh_order=sh_order)
    geometry = (None if geometry_mode is None
                else inject_geometry(vpls, ODD, corrections, geometry_mode, ctx=ctx))
    steps, accumulated, audit = propagate_with_audit(grid, corrections, ITERATIONS, geometry,
                                                     ctx=ctx, neighbours=neighbours)
    want_steps, want_accumulated, want_audit = twin.propagate_audited(
        grid, corrections, ITERATIONS, geometry, neighbours=neighbours)
    assert accumulated.shape == grid.shape
    for step, want in zip(steps, want_steps):
        assert relative_error(step, want) < 1e-4
    assert relative_error(accumulated, want_accumulated) < 1e-4
    assert_audits_match(audit, want_audit)
    assert audit.border_loss.min() > 0                   # light leaves through the faces
    if geometry_mode is not None:
        assert audit.occluded.min() > 0


def test_the_twin_refuses_a_geometry_volume_of_another_shape():
    with pytest.raises(ValueError, match=r"\(8, 13, 6, 4\) for a 7x12x5 grid"):
        twin.propagate(np.zeros((3, 7, 12, 5, 4)), geometry=np.zeros((8, 8, 8, 4)))


EXACT = ["--grid-cells", "7,12,5", "--grid-origin", "-1.2,-1.3,-0.8",
         "--grid-cell-size", "0.25"]
TINY = ["--scene", "cornell", "--iterations", "2", "--size", "24x20", "--rsm-size", "16",
        "--geometry-volume", "one-sided"]


def test_the_dump_records_the_shape_and_grid0_and_diff_read_it_back(tmp_path, capsys):
    import json

    from explorer.cli import main
    from explorer.exchange.files import read_npz

    dump = tmp_path / "a.npz"
    assert main(["render", *TINY, *EXACT, "--dump", str(dump),
                 "--out", str(tmp_path / "a.png")]) == 0
    grid, = json.loads(dump.with_suffix(".json").read_text(encoding="utf-8"))["grids"]
    assert grid["cells"] == [7, 12, 5] and grid["resolution"] is None
    assert grid["geometry_volume_cells"] == [8, 13, 6]
    assert (grid["origin"], grid["cell_size"]) == ([-1.2, -1.3, -0.8], 0.25)
    arrays = read_npz(dump)
    assert arrays["grid_0"].shape == (3, 7, 12, 5, 4)
    assert arrays["geometry_volume"].shape == (8, 13, 6, 4)
    # the dump's grid_0 fed back propagates to the same accumulation
    again = tmp_path / "b.npz"
    assert main(["render", *TINY, *EXACT, "--grid0", str(dump), "--dump", str(again),
                 "--out", str(tmp_path / "b.png")]) == 0
    np.testing.assert_allclose(read_npz(again)["accumulated"], arrays["accumulated"],
                               rtol=0, atol=1e-6 * np.abs(arrays["accumulated"]).max())
    capsys.readouterr()
    assert main(["render", *TINY, "--grid", "8", "--grid0", str(dump)]) == 2
    err = capsys.readouterr().err
    assert "grid_0 is a 7x12x5 grid, the frame's is 8³ (set --grid-cells 7,12,5" in err
    assert err.count("\n") == 1
    # diff renders our frame with the sidecar's settings: the exact grid again
    assert main(["diff", str(dump), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["settings"]["grid_cells"] == [7, 12, 5]
    stages = {stage["stage"]: stage for stage in report["stages"]}
    assert stages["accumulated"]["shape"] == [3, 7, 12, 5, 4]
    assert stages["accumulated"]["differing"] == 0 and not report["only_theirs"]


def test_per_cell_audit_records_and_the_baseline_on_an_odd_grid(ctx):
    """Every cell's audit record of a 7 × 12 × 5 propagation (cells indexed x fastest, as
    the shader lays them out) is the twin's, and the baseline kernel gives the same
    accumulation."""
    import itertools

    from explorer.gl.program import ProgramCache
    from explorer.lpv.passes.geometry import GeometryVolume
    from explorer.lpv.passes.propagate import PropagatePass
    from explorer.lpv.passes.propagate_baseline import BaselinePropagatePass
    from explorer.lpv.passes.textures import LpvGrid

    corrections = Corrections()
    vpls = random_vpls(14, ODD, 200, texel_area=0.05)
    grid = gpu_inject(vpls, ODD, ctx=ctx).astype(np.float64)
    geometry = inject_geometry(vpls, ODD, corrections, "one-sided", ctx=ctx)
    programs = ProgramCache(ctx)
    propagator, baseline = PropagatePass(ctx, programs), BaselinePropagatePass(ctx, programs)
    injected, volume = LpvGrid(ctx, ODD.cells), GeometryVolume(ctx, ODD.cells)
    try:
        injected.write(grid)
        volume.write(geometry)
        output = propagator.run(injected, ODD, corrections, 2, volume, keep_steps=True)
        _, want = twin.propagation_step_cells(output.steps[1], corrections, geometry)
        scale = float(np.abs(want["received"]).max())
        assert scale > 0
        for cell in itertools.product(*(range(n) for n in ODD.cells)):
            _, last = output.cell_records.read(cell)
            for name in twin.CELL_TERMS:
                assert np.abs(getattr(last, name) - want[name][(slice(None),) + cell]).max() \
                    <= 1e-5 * scale, (cell, name)
        with pytest.raises(IndexError, match="outside the 7x12x5 grid"):
            output.cell_records.read((0, 12, 0))
        accumulated = output.accumulated.read()
        got = baseline.run(injected, ODD, 2, volume).read()
        assert relative_error(got, accumulated) < 1e-5
    finally:
        for item in (injected, volume, propagator, baseline, programs):
            item.release()


@pytest.mark.parametrize("extra", [
    {"sh_order": 2, "bounces": 2, "geometry_volume": "one-sided", "camera_occluders": True},
    {"fog": True, "glossy": True, "injection_mode": "compute", "neighbours": 26},
], ids=["l2-bounces-camera-occluders", "fog-glossy-compute-26"])
def test_every_stage_of_a_frame_runs_on_an_exact_grid(gl_context, extra):
    from lpv_cases import run_frame

    settings = Settings(width=40, height=30, rsm_size=32, iterations=3, grid_cells=(9, 7, 11),
                        grid_origin=(-1.1, -1.05, -1.2), grid_cell_size=0.23, **extra)
    frame = run_frame(gl_context, settings)
    assert frame.grid_spec == GridSpec((-1.1, -1.05, -1.2), 0.23, (9, 7, 11))
    assert frame.accumulated.shape[1:4] == (9, 7, 11)
    assert np.isfinite(frame.final_image).all() and frame.indirect.max() > 0
    if frame.geometry_volume is not None:
        assert frame.geometry_volume.shape == (10, 8, 12, 4)
    assert not frame.warnings, frame.warnings
