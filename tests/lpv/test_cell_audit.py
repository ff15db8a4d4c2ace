"""Per-cell audit records: the propagation books each audit term to one cell
(shaders/propagate.glsl), keeps the last step's records and their sums over the steps on
the GPU, and the window reads one picked cell's (explorer/lpv/audit.py CellAuditRecords).
Summed over the cells they are the audit's totals; one cell's equals the numpy
reference's per-cell terms (explorer/lpv/twin/light_grid.py propagation_step_cells)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from lpv_cases import random_grid

from explorer.gl.program import ProgramCache
from explorer.lpv.audit import CellAudit
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.geometry import GeometryVolume
from explorer.lpv.passes.propagate import PropagatePass
from explorer.lpv.passes.textures import LpvGrid
from explorer.lpv.settings import PRESETS, Corrections
from explorer.lpv.twin import light_grid as R

SPEC = GridSpec(origin=(0.0, 0.0, 0.0), cell_size=0.5, resolution=6)
ITERATIONS = 3
CASES = {"corrected, two bounces": (Corrections(), 2, False),
         "original": (PRESETS["original"], 1, False),
         "no clamp, front faces only": (Corrections(side_faces=False,
                                                    clamp_front_face=False), 1, False),
         "corrected, flux budget": (Corrections(), 1, True)}


def _scene(seed: int):
    """(grid, geometry volume, albedo sums): a random grid and blockers with a clear
    normal per corner, so that every term of the record is non-zero somewhere."""
    rng = np.random.default_rng(seed)
    n = SPEC.resolution
    grid = random_grid(seed, n, band1=0.6)
    normals = rng.standard_normal((n + 1,) * 3 + (3,))
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    geometry = 0.8 * rng.random((n + 1,) * 3)[..., None] * R.cosine_lobe(normals)
    area = rng.random((n + 1,) * 3)
    albedo = np.concatenate([area[..., None] * rng.random((n + 1,) * 3 + (3,)),
                             area[..., None]], -1)
    return grid, geometry, albedo


def _reference_cells(grid, corrections, geometry, albedo, bounces, flux_budget=False):
    """(per-cell sums over the steps, the last step's per-cell terms, acc_N), ping-pong."""
    source, accumulated = grid, grid.copy()
    sums = {name: np.zeros((3,) + grid.shape[1:4]) for name in R.CELL_TERMS}
    last = None
    for _ in range(ITERATIONS):
        source, last = R.propagation_step_cells(source, corrections, geometry, albedo,
                                                bounces, flux_budget=flux_budget)
        accumulated = accumulated + source
        for name in R.CELL_TERMS:
            sums[name] += last[name]
    return sums, last, accumulated


@pytest.fixture(scope="module", params=list(CASES), ids=list(CASES))
def propagated(request, gl_context):
    """The GPU propagation of one case and its inputs; its buffers stay alive for the
    module's tests of this case."""
    gl_context.__enter__()
    corrections, bounces, flux_budget = CASES[request.param]
    grid, geometry, albedo = _scene(7)
    programs = ProgramCache(gl_context)
    propagator = PropagatePass(gl_context, programs)
    injected = LpvGrid(gl_context, SPEC.resolution)
    volume = GeometryVolume(gl_context, SPEC.resolution)
    injected.write(grid)
    volume.write(geometry, albedo)
    output = propagator.run(injected, SPEC, corrections, ITERATIONS, volume, keep_steps=True,
                            bounces=bounces, flux_budget=flux_budget)
    yield dict(output=output, grid=grid, geometry=geometry, albedo=albedo,
               corrections=corrections, bounces=bounces, flux_budget=flux_budget,
               propagator=propagator)
    for item in (injected, volume, propagator, programs):
        item.release()


def _records(output) -> tuple[dict, dict]:
    """Every cell's (sums, last) record as (3, N, N, N) arrays per term."""
    n = SPEC.resolution
    sums = {name: np.zeros((3, n, n, n)) for name in R.CELL_TERMS}
    last = {name: np.zeros((3, n, n, n)) for name in R.CELL_TERMS}
    for cell in itertools.product(range(n), repeat=3):
        total, final = output.cell_records.read(cell)
        for name in R.CELL_TERMS:
            sums[name][(slice(None),) + cell] = getattr(total, name)
            last[name][(slice(None),) + cell] = getattr(final, name)
    return sums, last


def test_the_record_fields_follow_the_reference_terms():
    assert tuple(CellAudit.__dataclass_fields__) == R.CELL_TERMS


@pytest.mark.parametrize("case", list(CASES))
def test_numpy_cell_terms_sum_to_the_step_terms(case):
    corrections, bounces, flux_budget = CASES[case]
    grid, geometry, albedo = _scene(3)
    out, cells = R.propagation_step_cells(grid, corrections, geometry, albedo, bounces,
                                          flux_budget=flux_budget)
    want_out, terms = R.propagation_step(grid, corrections, geometry, albedo, bounces,
                                         flux_budget=flux_budget)
    assert np.array_equal(out, want_out)
    for name in ("border_loss", "clamp_gain", "occluded", "reflected", "blocked",
                 "budget_withheld"):
        assert np.allclose(cells[name].reshape(3, -1).sum(1), terms[name], rtol=1e-12,
                           atol=1e-15), name
    assert np.allclose(cells["received"].reshape(3, -1).sum(1), R.flux(out), rtol=1e-12)
    # only border cells send light out of the grid
    inner = (slice(None),) + (slice(1, -1),) * 3
    assert np.all(cells["border_loss"][inner] == 0) and cells["border_loss"].max() > 0
    # per cell, the accumulated flux is the injected flux plus all the steps delivered
    sums, _, accumulated = _reference_cells(grid, corrections, geometry, albedo, bounces,
                                            flux_budget)
    cell_flux = 2.0 * np.sqrt(np.pi) * accumulated[..., 0]
    injected = 2.0 * np.sqrt(np.pi) * grid[..., 0]
    assert np.allclose(cell_flux, injected + sums["received"], rtol=1e-12, atol=1e-15)


def test_gpu_records_summed_over_the_cells_are_the_audit_totals(propagated):
    output = propagated["output"]
    audit = output.audit
    sums, last = _records(output)
    scale = float(np.abs(audit.injected).max())

    def total(values: np.ndarray) -> np.ndarray:
        return values.reshape(3, -1).sum(1)

    pairs = [("received", audit.per_step[1:]), ("border_loss", audit.border_loss),
             ("clamp_gain", audit.clamp_gain), ("occluded", audit.occluded),
             ("reflected", audit.reflected), ("blocked", audit.blocked),
             ("budget_withheld", audit.budget_withheld)]
    for name, per_step in pairs:
        assert np.abs(total(sums[name]) - per_step.sum(0)).max() <= 1e-5 * scale, name
        assert np.abs(total(last[name]) - per_step[-1]).max() <= 1e-5 * scale, name
    assert audit.occluded.sum() > 0 and audit.border_loss.sum() > 0
    if propagated["bounces"] == 2:
        assert audit.reflected.sum() > 0
    # the budget's term is booked only under the budget, and there it withholds flux
    if propagated["flux_budget"]:
        assert audit.budget_withheld.sum() > 0
    else:
        assert np.all(audit.budget_withheld == 0)


def test_a_picked_cells_record_is_the_references(propagated):
    output = propagated["output"]
    want_sums, want_last, _ = _reference_cells(
        propagated["grid"], propagated["corrections"], propagated["geometry"],
        propagated["albedo"], propagated["bounces"], propagated["flux_budget"])
    scale = float(np.abs(want_sums["received"]).max())
    received = want_sums["received"].sum(0)
    picks = {"brightest": np.unravel_index(np.argmax(received), received.shape),
             "corner": (0, 0, 0), "border": (5, 2, 3), "inside": (2, 3, 2)}
    for label, cell in picks.items():
        cell = tuple(int(v) for v in cell)
        total, final = output.cell_records.read(cell)
        for name in R.CELL_TERMS:
            where = (slice(None),) + cell
            assert np.abs(getattr(total, name) - want_sums[name][where]).max() \
                <= 1e-5 * scale, (label, name)
            assert np.abs(getattr(final, name) - want_last[name][where]).max() \
                <= 1e-5 * scale, (label, name)


def test_records_are_read_once_and_go_stale_when_the_pass_runs_again(ctx):
    grid, geometry, albedo = _scene(11)
    programs = ProgramCache(ctx)
    propagator = PropagatePass(ctx, programs)
    injected = LpvGrid(ctx, SPEC.resolution)
    try:
        injected.write(grid)
        first = propagator.run(injected, SPEC, Corrections(), ITERATIONS)
        records = first.cell_records
        seen = records.read((1, 2, 3))
        assert records.current and records.read((1, 2, 3)) is seen      # cached
        with pytest.raises(IndexError, match="outside the 6\\^3 grid"):
            records.read((6, 0, 0))
        propagator.run(injected, SPEC, Corrections(), ITERATIONS + 1)
        assert not records.current
        assert records.read((2, 2, 2)) is None          # overwritten: not this frame's
        assert records.read((1, 2, 3)) is seen          # read while it was current
        none = propagator.run(injected, SPEC, Corrections(), 0)
        total, last = none.cell_records.read((2, 2, 2))
        assert last is None and not np.any(total.received)
        assert propagator.run(injected, SPEC, Corrections(), 2, audit=False).cell_records \
            is None
    finally:
        injected.release()
        propagator.release()
        programs.release()


def test_every_cascade_of_a_frame_has_its_records(ctx):
    from explorer.lpv.pipeline import Pipeline
    from explorer.lpv.settings import Settings

    settings = Settings(grid_size=8, cascades=2, iterations=2, width=32, height=32,
                        rsm_size=32)
    pipeline = Pipeline(settings, ctx=ctx)
    try:
        result = pipeline.run(settings)
        for level in result.cascades:
            n = level.spec.resolution
            received = sum(level.cell_records.read(cell)[0].received
                           for cell in itertools.product(range(n), repeat=3))
            delivered = level.audit.per_step[1:].sum(0)
            assert np.allclose(received, delivered, rtol=1e-4)
        # without the per-step audit there are no records, and the Picked panel says why
        from explorer.ui.overlays.picking import cell_audit

        bare = pipeline.run(settings.with_changes(iterations=3), need_audit=False)
        assert all(level.cell_records is None for level in bare.cascades)
        assert "without the per-step energy audit" in cell_audit(bare, 0, (1, 1, 1))
    finally:
        pipeline.release()


def test_the_budgets_term_is_shown_where_it_withheld_flux():
    """The picked cell's rows and ``render --audit``'s table name the flux the budget
    withheld; the cell's row only where the budget withheld some."""
    from explorer.commands.render import format_audit
    from explorer.ui.overlays.describe import cell_audit_rows
    from explorer.ui.overlays.picking import CellAuditInfo

    grid, geometry, _ = _scene(5)
    rows = {}
    for flux_budget in (False, True):
        _, cells = R.propagation_step_cells(grid, Corrections(), geometry,
                                            flux_budget=flux_budget)
        record = CellAudit(*(cells[name][(slice(None), 2, 3, 2)] for name in R.CELL_TERMS))
        info = CellAuditInfo(steps=1, total=record, last=None, injected=np.zeros(3))
        rows[flux_budget] = dict(cell_audit_rows(info))
    assert "withheld by the budget, all 1 steps" not in rows[False]
    assert float(rows[True]["withheld by the budget, all 1 steps"].split()[0].strip("(,")) > 0
    _, _, audit = R.propagate_audited(grid, Corrections(), 2, geometry, flux_budget=True)
    line = next(line for line in format_audit(audit_with_pipeline_terms(audit)).splitlines()
                if "withheld by the budget" in line)
    np.testing.assert_allclose([float(v) for v in line.split()[-3:]],
                               audit.budget_withheld.sum(0), rtol=1e-3)


def audit_with_pipeline_terms(audit):
    """``audit`` as the frame's EnergyAudit (the RSM and gathered flux zero)."""
    from explorer.lpv.audit import EnergyAudit

    return EnergyAudit.from_grid_audit(audit, rsm=np.zeros(3), gathered=np.zeros(3))
