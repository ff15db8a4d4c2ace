"""Propagation on the GPU against the numpy twin, every switch combination."""

from __future__ import annotations

import itertools
import time
from contextlib import contextmanager

import numpy as np
import pytest
from lpv_cases import (
    assert_audits_match,
    in_place_schedules,
    random_grid,
    random_vpls,
    relative_error,
)

from explorer.gl.program import ProgramCache
from explorer.lpv import inject, propagate
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes import audit_reduce
from explorer.lpv.passes.geometry import GeometryVolume, inject_geometry
from explorer.lpv.passes.propagate import PropagatePass, propagate_with_audit
from explorer.lpv.passes.textures import LpvGrid
from explorer.lpv.settings import Corrections
from explorer.lpv.twin import light_grid as twin

SPEC = GridSpec(origin=(0.0, 0.0, 0.0), cell_size=0.5, resolution=8)
ITERATIONS = 3
SWITCHES = [name for name in Corrections.names() if name not in ("ping_pong",
                                                                  "model_face_weights")]
"""The switches of the full product (model_face_weights: its own test, below)."""
COMBINATIONS = list(itertools.product((True, False), repeat=len(SWITCHES)))


@pytest.mark.parametrize("index", range(len(COMBINATIONS)))
def test_inject_and_propagate_match_the_reference(ctx, index):
    """All 2^7 combinations of the switches (ping-pong on); the geometry volume alternates
    between one- and double-sided surfels made from the same VPLs, the injection between
    points and compute."""
    corrections = Corrections(**dict(zip(SWITCHES, COMBINATIONS[index])))
    geometry_mode = ("one-sided", "double-sided")[index % 2]
    injection_mode = ("points", "compute")[index // 2 % 2]
    vpls = random_vpls(index, SPEC, 120, outside=5, texel_area=0.05)

    grid = inject(vpls, SPEC, corrections, injection_mode, ctx=ctx)
    geometry = inject_geometry(vpls, SPEC, corrections, geometry_mode, ctx=ctx)
    expected_grid = twin.inject(vpls, SPEC, corrections)
    expected_geometry = twin.inject_geometry(vpls, SPEC, corrections, geometry_mode)
    assert relative_error(grid, expected_grid) < 1e-5
    assert relative_error(geometry, expected_geometry) < 1e-5

    steps, accumulated, audit = propagate_with_audit(grid, corrections, ITERATIONS, geometry,
                                                     ctx=ctx)
    want_steps, want_accumulated, want_audit = twin.propagate_audited(
        grid, corrections, ITERATIONS, geometry)
    assert len(steps) == ITERATIONS + 1
    for step, want in zip(steps, want_steps):
        assert relative_error(step, want) < 1e-4
    assert relative_error(accumulated, want_accumulated) < 1e-4
    assert_audits_match(audit, want_audit)
    assert audit.occluded.min() > 0   # the geometry volume really blocks something


@pytest.mark.parametrize("exact_constants, side_faces", [(True, True), (False, True),
                                                         (True, False), (False, False)])
def test_the_dx11_face_weights_match_the_reference(ctx, exact_constants, side_faces):
    """model_face_weights off: the DX11 shader's Δω_front/(2π), Δω_side/(3π) on the GPU as
    in the twin, with the geometry volume and the audit."""
    corrections = Corrections(model_face_weights=False, exact_constants=exact_constants,
                              side_faces=side_faces)
    vpls = random_vpls(7, SPEC, 120, outside=5, texel_area=0.05)
    grid = inject(vpls, SPEC, corrections, "points", ctx=ctx)
    geometry = inject_geometry(vpls, SPEC, corrections, "one-sided", ctx=ctx)
    steps, accumulated, audit = propagate_with_audit(grid, corrections, ITERATIONS, geometry,
                                                     ctx=ctx)
    want_steps, want_accumulated, want_audit = twin.propagate_audited(
        grid, corrections, ITERATIONS, geometry)
    for step, want in zip(steps, want_steps):
        assert relative_error(step, want) < 1e-4
    assert relative_error(accumulated, want_accumulated) < 1e-4
    assert_audits_match(audit, want_audit)
    model, _, _ = twin.propagate_audited(grid, Corrections(
        exact_constants=exact_constants, side_faces=side_faces), ITERATIONS, geometry)
    assert relative_error(steps[1], model[1]) > 0.1      # the switch changes the step


def test_without_geometry_and_with_many_iterations(ctx):
    grid = random_grid(11, 10)
    steps, accumulated, audit = propagate_with_audit(grid, Corrections(), 12, ctx=ctx)
    want_steps, want_accumulated, want_audit = twin.propagate_audited(grid, iterations=12)
    assert relative_error(steps[-1], want_steps[-1]) < 1e-4
    assert relative_error(accumulated, want_accumulated) < 1e-4
    assert_audits_match(audit, want_audit)
    assert np.all(audit.occluded == 0) and audit.border_loss.min() > 0


def test_in_place_propagation_races_and_double_counts(ctx):
    """ping_pong=False: the reference (race-free reading acc += P(acc)) re-propagates light
    it propagated before; the GPU pass additionally reads neighbours already updated in the
    same dispatch, so it differs from both."""
    grid = np.zeros((3, 12, 12, 12, 4))
    grid[:, 4:8, 4:8, 4:8] = random_grid(12, 4, band1=0.1)
    # Clamp off so that P is linear and the double counting can be written down exactly.
    ping_pong = Corrections(clamp_front_face=False)
    in_place = Corrections(ping_pong=False, clamp_front_face=False)

    ping_pong_steps = twin.propagate(grid, ping_pong, 3)
    in_place_steps = twin.propagate(grid, in_place, 3)
    # acc_2 = acc_1 + P(acc_1) = g0 + 2·P(g0) + P²(g0): step 1's light is counted twice.
    p1, p2 = ping_pong_steps[1], ping_pong_steps[2]
    assert np.allclose(sum(in_place_steps[:3]), grid + 2 * p1 + p2)
    flux_ping_pong = twin.flux(sum(ping_pong_steps))
    flux_in_place = twin.flux(sum(in_place_steps))
    assert np.all(flux_in_place > 1.5 * flux_ping_pong)

    gpu_steps, gpu_accumulated, gpu_audit = propagate_with_audit(grid, in_place, 3, ctx=ctx)
    gpu_in_place = sum(gpu_steps)
    assert relative_error(gpu_accumulated, gpu_in_place) < 1e-5
    # each cell's step is the shader's formula for one schedule of neighbour reads
    assert in_place_schedules(gpu_steps, in_place)[0] < 1e-5
    # The audit measures what the racing dispatch really added.
    assert np.allclose(gpu_audit.per_step, [twin.flux(step) for step in gpu_steps],
                       rtol=1e-4)
    gpu_ping_pong = sum(propagate(grid, ping_pong, 3, ctx=ctx))
    assert relative_error(gpu_ping_pong, sum(ping_pong_steps)) < 1e-4
    assert relative_error(gpu_in_place, sum(ping_pong_steps)) > 1e-2
    assert np.all(twin.flux(gpu_in_place) > 1.5 * flux_ping_pong)


def test_half_float_grids_propagate(ctx):
    grid = random_grid(13, 8)
    steps = propagate(grid, Corrections(), 4, ctx=ctx, fmt="rgba16f")
    want = twin.propagate(grid, Corrections(), 4)
    for step, expected in zip(steps, want):
        assert relative_error(step, expected) < 5e-3


def test_pass_object_keeps_steps_only_when_asked_and_returns_the_accumulation(ctx):
    grid = random_grid(14, 8)
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 8)
    injected = LpvGrid(ctx, 8)
    propagator = PropagatePass(ctx, ProgramCache(ctx))
    try:
        injected.write(grid)
        output = propagator.run(injected, spec, Corrections(), 2)
        assert output.steps is None
        want = twin.propagate(grid, Corrections(), 2)
        assert relative_error(output.accumulated.read(), sum(want)) < 1e-4
        assert relative_error(injected.read(), grid) < 1e-7   # the input is left alone
        zero = propagator.run(injected, spec, Corrections(), 0, keep_steps=True)
        assert len(zero.steps) == 1 and zero.audit.border_loss.shape == (0, 3)
        assert relative_error(zero.accumulated.read(), grid) < 1e-7
    finally:
        propagator.release()
        injected.release()


def test_bad_input_is_named(ctx):
    with pytest.raises(ValueError, match=r"\(3, nx, ny, nz, 4\)"):
        propagate(np.zeros((8, 8, 8, 4)), ctx=ctx)
    with pytest.raises(ValueError, match=r"\(9, 9, 9, 4\)"):
        propagate(np.zeros((3, 8, 8, 8, 4)), geometry=np.zeros((8, 8, 8, 4)), ctx=ctx)
    with pytest.raises(ValueError, match="iterations"):
        propagate(np.zeros((3, 4, 4, 4, 4)), iterations=-1, ctx=ctx)
    with pytest.raises(ValueError, match=r"\(3, nx, ny, nz, 4\)"):
        twin.propagate(np.zeros((3, 4, 4, 5, 5)))        # 5 coefficients: neither L1 nor L2
    with pytest.raises(ValueError, match=r"\(5, 5, 5, 4\)"):
        twin.propagate(np.zeros((3, 4, 4, 4, 4)), geometry=np.zeros((4, 4, 4, 4)))
    volume = GeometryVolume(ctx, 4)
    injected = LpvGrid(ctx, 8)
    try:
        with pytest.raises(ValueError, match="geometry volume"):
            PropagatePass(ctx, ProgramCache(ctx)).run(injected, SPEC, Corrections(), 1, volume)
    finally:
        volume.release()
        injected.release()


def injected_case(ctx, seed: int, mode: str):
    """(grid, geometry volume or None) injected on the GPU from random VPLs."""
    vpls = random_vpls(seed, SPEC, 150, texel_area=0.05)
    grid = inject(vpls, SPEC, Corrections(), ctx=ctx)
    geometry = None if mode == "off" else inject_geometry(vpls, SPEC, Corrections(), mode,
                                                          ctx=ctx)
    return grid, geometry


@contextmanager
def on_gpu(ctx, grid: np.ndarray, geometry: np.ndarray | None):
    """The grid and the geometry volume as GPU textures, released afterwards."""
    injected = LpvGrid(ctx, SPEC.resolution)
    volume = None
    try:
        injected.write(grid)
        if geometry is not None:
            volume = GeometryVolume(ctx, SPEC.resolution)
            volume.write(geometry)
        yield injected, volume
    finally:
        injected.release()
        if volume is not None:
            volume.release()


@pytest.mark.parametrize("mode", ["off", "one-sided"])
def test_without_the_audit_the_accumulation_is_the_same(ctx, mode):
    """need_audit=False compiles the audit out (PROPAGATE_AUDIT 0): same grids, and only
    the injected and accumulated flux are measured."""
    grid, geometry = injected_case(ctx, 31, mode)
    want_steps, want_accumulated, want_audit = twin.propagate_audited(
        grid, Corrections(), 5, geometry)
    propagator = PropagatePass(ctx, ProgramCache(ctx))
    try:
        with on_gpu(ctx, grid, geometry) as (injected, volume):
            output = propagator.run(injected, SPEC, Corrections(), 5, volume,
                                    keep_steps=True, audit=False)
            accumulated = output.accumulated.read()
        assert relative_error(accumulated, want_accumulated) < 1e-4
        for step, want in zip(output.steps, want_steps):
            assert relative_error(step, want) < 1e-4
        audit = output.audit
        assert not audit.steps_measured
        assert np.allclose(audit.injected, want_audit.injected, rtol=1e-5)
        assert np.allclose(audit.accumulated, want_audit.accumulated, rtol=1e-5)
        assert audit.per_step.shape == (6, 3) and np.all(np.isnan(audit.per_step[1:]))
    finally:
        propagator.release()


@pytest.mark.parametrize("mode", ["off", "one-sided", "double-sided"])
def test_baseline_kernel_propagates_like_the_corrected_pass(ctx, mode):
    """shaders/propagate_minimal.glsl, the bench's baseline, computes the corrected
    propagation: the same accumulation as propagate.glsl and the numpy twin."""
    from explorer.lpv.passes.propagate_baseline import BaselinePropagatePass

    grid, geometry = injected_case(ctx, 32, mode)
    _, want = propagate_with_audit(grid, Corrections(), 6, geometry, ctx=ctx)[:2]
    expected = twin.propagate_audited(grid, Corrections(), 6, geometry)[1]
    baseline = BaselinePropagatePass(ctx, ProgramCache(ctx))
    try:
        with on_gpu(ctx, grid, geometry) as (injected, volume):
            got = baseline.run(injected, SPEC, 6, volume).read()
        assert relative_error(got, want) < 1e-5
        assert relative_error(got, expected) < 1e-4
        l2 = LpvGrid(ctx, 4, sh_order=2)
        with pytest.raises(ValueError, match="L1 only"):
            baseline.run(l2, GridSpec((0, 0, 0), 1.0, 4), 1)
        l2.release()
    finally:
        baseline.release()


@pytest.mark.parametrize("ping_pong", [True, False])
def test_the_flux_only_audit_measures_the_full_audits_flux_per_step(ctx, ping_pong):
    """audit="flux" runs the minimal kernel (PROPAGATE_AUDIT 0) and reduces each step's
    grid: the same grids as the full audit, the same flux per step (1e-6 relative), and
    the terms only the full audit measures are None (with no per-cell records)."""
    grid, geometry = injected_case(ctx, 31, "one-sided")
    corrections = Corrections(ping_pong=ping_pong)
    propagator = PropagatePass(ctx, ProgramCache(ctx))
    try:
        with on_gpu(ctx, grid, geometry) as (injected, volume):
            outputs = {}
            for mode in ("full", "flux"):
                output = propagator.run(injected, SPEC, corrections, 5, volume,
                                        keep_steps=True, audit=mode)
                outputs[mode] = (output, output.accumulated.read())
        (full, full_acc), (flux, flux_acc) = outputs["full"], outputs["flux"]
        if ping_pong:
            assert np.array_equal(flux_acc, full_acc)
            assert all(np.array_equal(a, b) for a, b in zip(flux.steps, full.steps))
            scale = np.abs(full.audit.per_step).max()
            assert np.abs(flux.audit.per_step - full.audit.per_step).max() <= 1e-6 * scale
            assert np.allclose(flux.audit.accumulated, full.audit.accumulated, rtol=1e-6)
        else:
            # in place races (its grids differ from run to run): the flux per step is
            # that of the run's own steps (acc_t − acc_{t−1}, kept), float64 numpy sums
            want = np.array([twin.flux(step) for step in flux.steps])
            assert np.allclose(flux.audit.per_step, want, rtol=1e-4)
        assert flux.audit.mode == "flux" and flux.audit.steps_measured
        assert not flux.audit.terms_measured and flux.cell_records is None
        assert all(getattr(flux.audit, name) is None for name in
                   ("border_loss", "clamp_gain", "occluded", "reflected", "blocked",
                    "budget_withheld"))
    finally:
        propagator.release()


def test_an_unknown_audit_mode_is_refused_by_name(ctx):
    grid, geometry = injected_case(ctx, 7, "off")
    with pytest.raises(ValueError, match="audit mode must be one of off, flux, full"):
        propagate_with_audit(grid, iterations=1, ctx=ctx, audit="some")


@pytest.mark.parametrize("mode", ["full", "flux", "off"])
def test_steps_in_a_row_give_what_one_step_at_a_time_gives(ctx, mode, monkeypatch):
    """``advance_for`` (a unit's steps in a row, the lean loop of one-slab steps, with
    ping and pong on units of their own and a second program, or without where the
    context has 8 image units) gives the accumulation, the audit and the per-cell records
    bit for bit as ``step()`` one at a time; a limit of 0 still advances one slab per
    call."""
    grid, geometry = injected_case(ctx, 33, "one-sided")
    propagator = PropagatePass(ctx, ProgramCache(ctx))
    try:
        with on_gpu(ctx, grid, geometry) as (injected, volume):
            got = {}
            for way in ("one at a time", "in a row", "limit 0", "8 image units",
                        "records of 2 steps kept"):
                if way == "8 image units":
                    monkeypatch.setattr(propagator, "image_units", lambda: 8)
                if way == "records of 2 steps kept":    # reduced 2, 2, then 1 at a time
                    monkeypatch.setattr(audit_reduce, "KEPT_RECORDS_BYTES",
                                        2 * 21 * 4 * SPEC.resolution ** 3 + 256)
                run = propagator.start(injected, SPEC, Corrections(), 6, volume, audit=mode)
                calls = 0
                while not run.finished:
                    if way == "one at a time":
                        run.step()
                    else:
                        run.advance_for(0.0 if way == "limit 0" else 1e9,
                                        time.perf_counter())
                    calls += 1
                output = run.finish()
                records = (output.cell_records.read((1, 2, 3))
                           if output.cell_records is not None else None)
                got[way] = (calls, output.accumulated.read(), output.audit, records)
        (_, want, audit, records), (calls, *rest) = got["one at a time"], got["in a row"]
        assert calls == 1 == got["8 image units"][0] == got["records of 2 steps kept"][0]
        for accumulated, got_audit, got_records in (rest, got["limit 0"][1:],
                                                    got["8 image units"][1:],
                                                    got["records of 2 steps kept"][1:]):
            assert np.array_equal(accumulated, want)
            assert np.array_equal(got_audit.per_step, audit.per_step, equal_nan=True)
            assert np.array_equal(got_audit.accumulated, audit.accumulated)
            assert (got_records is None) == (records is None) == (mode != "full")
            for got_record, want_record in zip(got_records or (), records or ()):
                assert all(np.array_equal(getattr(got_record, name), getattr(want_record, name))
                           for name in ("received", "border_loss", "clamp_gain", "occluded"))
        assert got["limit 0"][0] == 6
    finally:
        propagator.release()


def test_the_programs_a_run_makes_do_not_depend_on_its_units_time(ctx, monkeypatch):
    """A run that is given no time beyond one slab a unit (a slow machine's, a frame
    already spent) makes the same programs as one whose unit runs every step in a row:
    both the odd and the even steps' programs, got when the run starts (issue #31: the
    soak's program count rose by one where a variant's first visit never had time for two
    steps in a unit). On a context too short of image units for the layout, one program."""
    grid, geometry = injected_case(ctx, 34, "one-sided")
    with on_gpu(ctx, grid, geometry) as (injected, volume):
        made = {}
        for way in ("limit 0", "in a row", "8 image units"):
            programs = ProgramCache(ctx)
            propagator = PropagatePass(ctx, programs)
            if way == "8 image units":
                monkeypatch.setattr(propagator, "image_units", lambda: 8)
            try:
                run = propagator.start(injected, SPEC, Corrections(), 4, volume, audit="off")
                at_start = set(programs._programs)
                while not run.finished:
                    run.advance_for(0.0 if way == "limit 0" else 1e9, time.perf_counter())
                run.finish()
                made[way] = (at_start, set(programs._programs))
            finally:
                propagator.release()
                for program in programs._programs.values():
                    program.release()
    propagation = {way: [{key for key in keys if key[0] == "propagate.glsl"}
                         for keys in both] for way, both in made.items()}
    assert made["limit 0"] == made["in a row"]
    for way, (at_start, at_end) in propagation.items():
        assert at_start == at_end, way          # none made after the start
        assert len(at_end) == (1 if way == "8 image units" else 2), way
