"""The pipeline's declared stages and its incremental jobs: which passes a change runs,
progressive frames, cancellation, interruption, and the stage table itself."""

from __future__ import annotations

import dataclasses
import sys
import types

import numpy as np
import pytest

from explorer import schema
from explorer.lpv import cache_keys, stage_list
from explorer.lpv.corrections import CORRECTIONS, preset
from explorer.lpv.passes.rsm import read_texture
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Corrections, Settings

SMALL = Settings(scene="cornell", grid_size=8, iterations=6, rsm_size=32, width=40,
                 height=32)
PASS_OBJECTS = {"rsm": lambda p: p.light_views.rsm,
                "downsample": lambda p: p.light_views.downsample,
                "inject": lambda p: p.stages["inject"].inject,
                "geometry": lambda p: p.stages["geometry"].geometry,
                "gbuffer": lambda p: p.stages["gbuffer"].gbuffer,
                "gather": lambda p: p.stages["gather"].gather,
                "display": lambda p: p.stages["display"].display}
"""Stage -> the pipeline's pass object."""


class PassCounter:
    """Counts the calls of every pass object's ``run`` (and of every cascade level's
    propagation start): what really ran on the GPU, not what the pipeline reports."""

    def __init__(self, pipeline: Pipeline) -> None:
        self.pipeline = pipeline
        self.calls: dict[str, int] = {}
        for stage, owner in PASS_OBJECTS.items():
            self._wrap(owner(pipeline), "run", stage)

    def _wrap(self, obj, method: str, name: str) -> None:
        original = getattr(obj, method)

        def counted(*args, **kwargs):
            self.calls[name] = self.calls.get(name, 0) + 1
            return original(*args, **kwargs)

        setattr(obj, method, counted)

    def ran(self, pipeline_result) -> set[str]:
        """The passes that ran since the last call (propagation: through the levels)."""
        for level in self.pipeline.state.levels:
            if not getattr(level.propagate, "_counted", False):
                self._wrap(level.propagate, "start", "propagate")
                level.propagate._counted = True
        found = {name for name, count in self.calls.items() if count}
        self.calls.clear()
        return found


@pytest.fixture
def pipeline(gl_context, ctx):   # ctx: checks for GL errors
    pipe = Pipeline(SMALL, ctx=gl_context)
    yield pipe
    pipe.release()


def changed_value(name: str, value):
    """Another allowed value of the Settings field ``name``."""
    spec = schema.specs(Settings)[name]
    if spec.kind == "bool":
        return not value
    if spec.kind == "float":
        return value * 2.0 if spec.high is None or value * 2.0 <= spec.high else value / 2.0
    if spec.kind == "choice":
        return next(choice for choice in spec.choices if choice != value)
    raise AssertionError(f"no rule to change {name} ({spec.kind})")


def test_display_only_changes_run_no_pass_but_the_display(pipeline):
    counter = PassCounter(pipeline)
    pipeline.run(SMALL)
    counter.ran(None)
    display_only = [name for name, spec in schema.specs(Settings).items()
                    if spec.stages == ("display",)]
    assert {"exposure", "indirect_only"} <= set(display_only)
    settings = SMALL
    for name in display_only:
        settings = settings.with_changes(**{name: changed_value(name,
                                                                getattr(settings, name))})
        result = pipeline.run(settings)
        assert result.stages_run == ("display",), name
        assert counter.ran(result) == {"display"}, name
    # the picture on screen is the new one: indirect only at the new exposure
    shown = np.frombuffer(pipeline.final_texture.read(), np.uint8).reshape(
        SMALL.height, SMALL.width, 4)[::-1, :, :3] / 255.0
    assert np.allclose(shown, pipeline.view("final"), atol=1.5 / 255)


def test_a_camera_move_runs_only_the_camera_passes(pipeline):
    counter = PassCounter(pipeline)
    pipeline.run(SMALL)
    counter.ran(None)
    moved = pipeline.run(SMALL.with_changes(camera=((0.3, 0.2, 3.5), (0.0, 0.1, 0.0))))
    assert moved.stages_run == ("gbuffer", "gather", "display")
    assert counter.ran(moved) == {"gbuffer", "gather", "display"}
    # with cascades the grids follow the camera: a big move re-runs the LPV stages
    pipeline.run(SMALL.with_changes(cascades=2))
    counter.ran(None)
    far = pipeline.run(SMALL.with_changes(cascades=2, camera=((2.5, 0.2, 3.5),
                                                             (1.5, 0.1, 0.0))))
    assert "grid" in far.stages_run and "propagate" in counter.ran(far)


def test_a_toggle_shows_progressive_frames_that_end_at_the_one_shot_frame(pipeline,
                                                                          gl_context):
    pipeline.run(SMALL)
    toggled = SMALL.with_changes(corrections=dataclasses.replace(Corrections(),
                                                                 side_faces=False))
    job = pipeline.start(toggled, need_audit=False)
    frames, steps = [], []
    while not job.done:
        progress = job.advance(0.0)                      # one unit of work per call
        advanced = progress.stage == "propagate" and progress.done not in steps
        if advanced and job.preview():
            steps.append(progress.done)
            frames.append(np.frombuffer(pipeline.final_texture.read(), np.uint8).copy())
    assert steps == list(range(1, SMALL.iterations + 1))  # then a unit finishes the level
    assert progress.finished and progress.label == "done"
    # the light grows step by step (the last steps may add less than an 8-bit level)
    distinct = {frame.tobytes() for frame in frames}
    assert len(distinct) >= SMALL.iterations - 2
    assert frames[-1].astype(np.int64).sum() > frames[0].astype(np.int64).sum()
    result = job.result
    assert result.stages_run == ("propagate", "gather", "display")   # side_faces: propagate
    with Pipeline(toggled, ctx=gl_context) as fresh:
        once = fresh.run(need_audit=False)
        assert np.allclose(result.accumulated, once.accumulated, rtol=1e-6, atol=1e-9)
        assert np.allclose(result.final_image, once.final_image, rtol=1e-6, atol=1e-9)
        assert np.array_equal(np.frombuffer(pipeline.final_texture.read(), np.uint8),
                              np.frombuffer(fresh.final_texture.read(), np.uint8))


def test_a_budget_does_whole_units_and_the_progress_names_the_step(pipeline):
    pipeline.run(SMALL)
    job = pipeline.start(SMALL.with_changes(iterations=8))
    progress = job.advance(0.0)                           # grid_0 into the accumulation
    assert progress.stage == "propagate" and progress.done == 0 and progress.total == 8
    progress = job.advance(0.0)                           # the first step
    assert progress.done == 1 and progress.label == "propagating 1/8"
    progress = job.advance(1e9)                           # a budget without end finishes
    assert progress.finished and job.done
    assert job.result.audit.per_step.shape == (9, 3)


def test_a_settings_change_mid_propagation_cancels_and_restarts(pipeline, gl_context,
                                                               monkeypatch):
    # one slab per unit: how many steps a unit groups (GROUP_MS) depends on the machine's
    # speed, and this test counts the steps and the progress calls
    monkeypatch.setattr(sys.modules["explorer.lpv.stages.propagate"], "GROUP_MS", 0.0)
    pipeline.run(SMALL)
    first = pipeline.start(SMALL.with_changes(iterations=10))
    for _ in range(40):         # the start and three steps (a call may wait on a read-back)
        if first.progress.done == 3:
            break
        first.advance(0.0)
    assert first.stage == "propagate" and first.progress.done == 3
    calls = []
    other = SMALL.with_changes(iterations=10, bounces=2, geometry_volume="one-sided")
    second = pipeline.start(other, progress=lambda *call: calls.append(call))
    assert first.cancelled and pipeline.job is second
    with pytest.raises(RuntimeError, match="cancelled"):
        first.advance(0.0)
    result = second.advance(None)
    assert result.finished
    # the geometry volume is new, the injection is not: it restarts at the first stage
    # that changed, and propagates all ten steps again
    assert second.result.stages_run == ("geometry", "propagate", "gather", "display")
    assert calls[0] == ("geometry", 0, 2)        # the volume, then its read-back taken
    assert [c for c in calls if c[0] == "propagate"][:3] == [("propagate", 0, 10),
                                                             ("propagate", 0, 10),
                                                             ("propagate", 1, 10)]
    assert calls[-1] == ("display", 3, 3)   # the auto exposure (metered, averaged), the pass
    with Pipeline(other, ctx=gl_context) as fresh:
        assert np.allclose(second.result.accumulated, fresh.run().accumulated, rtol=1e-6,
                           atol=1e-9)
    # asking again for the frame in progress carries on with the same job
    third = pipeline.start(SMALL.with_changes(iterations=12))
    third.advance(0.0)
    assert pipeline.start(SMALL.with_changes(iterations=12)) is third and not third.cancelled
    assert pipeline.start(SMALL.with_changes(iterations=12), keep_steps=True) is not third
    assert third.cancelled
    # going back: the geometry volume (off again) was completed by the third job, the
    # propagation is done again
    back = pipeline.run(SMALL.with_changes(iterations=10))
    assert back.stages_run == ("propagate", "gather", "display")


def test_an_interrupted_run_leaves_the_pipeline_consistent(pipeline, gl_context):
    pipeline.run(SMALL)
    changed = SMALL.with_changes(iterations=5, corrections="original")

    def interrupt(stage: str, done: int, total: int) -> None:
        if stage == "propagate" and done >= 2:     # small steps come in groups
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        pipeline.run(changed, progress=interrupt)
    assert pipeline.job is None
    again = pipeline.run(changed)
    assert again.stages_run == ("propagate", "gather", "display")   # inject was complete
    with Pipeline(changed, ctx=gl_context) as fresh:
        assert np.allclose(again.accumulated, fresh.run().accumulated, rtol=1e-6, atol=1e-9)


def test_the_audit_and_the_steps_are_computed_when_asked(pipeline):
    fast = pipeline.run(SMALL, need_audit=False)
    assert not fast.audit.steps_measured and np.isnan(fast.audit.per_step[1:]).all()
    accumulated = fast.accumulated.copy()
    audited = pipeline.run(SMALL)                  # the same light: only propagate runs
    assert audited.stages_run == ("propagate",)
    assert audited.audit.steps_measured and np.isfinite(audited.audit.per_step).all()
    assert np.allclose(audited.accumulated, accumulated, rtol=1e-6, atol=1e-9)
    assert np.allclose(audited.audit.accumulated, fast.audit.accumulated, rtol=1e-6)
    assert pipeline.run(SMALL, need_audit=False).stages_run == ()   # an audit is enough
    kept = pipeline.run(SMALL, keep_steps=True)
    assert kept.stages_run == ("propagate",) and len(kept.steps) == SMALL.iterations + 1
    assert all(len(level.steps) == SMALL.iterations + 1 for level in kept.cascades)


def test_a_flux_audit_propagates_again_for_the_full_audit_and_not_back(pipeline):
    """Mode flux measures the flux per step with the minimal kernel; asking for the full
    audit then runs the propagation again (and only it), while a full audit already
    covers a later flux or off request."""
    pipeline.run(SMALL, need_audit="off")
    flux = pipeline.run(SMALL, need_audit="flux")
    assert flux.stages_run == ("propagate",) and flux.audit.mode == "flux"
    assert np.isfinite(flux.audit.per_step).all() and flux.audit.border_loss is None
    assert pipeline.run(SMALL, need_audit="off").stages_run == ()
    full = pipeline.run(SMALL, need_audit="full")
    assert full.stages_run == ("propagate",) and full.audit.terms_measured
    assert np.allclose(flux.audit.per_step, full.audit.per_step, rtol=1e-6)
    assert pipeline.run(SMALL, need_audit="flux").stages_run == ()
    with pytest.raises(ValueError, match="audit mode must be one of"):
        pipeline.run(SMALL, need_audit="most")


def test_cascades_are_a_list_of_levels(pipeline):
    result = pipeline.run(SMALL.with_changes(cascades=2))
    assert len(result.cascades) == 2
    assert result.grid_spec is result.cascades[0].spec
    assert result.accumulated is result.cascades[0].accumulated
    assert result.geometry_volume is result.cascades[0].geometry_volume
    assert result.cascade_specs == [level.spec for level in result.cascades]
    assert result.cascades[1].spec.cell_size == pytest.approx(
        2 * result.cascades[0].spec.cell_size)
    with pytest.raises(AttributeError):
        result.accumulated = None                  # level 0's, read-only


def test_stage_keys_come_from_the_schema():
    cache_keys.check_declarations()
    assert [name for name, _ in cache_keys.stage_inputs(SMALL, "display")] == [
        "exposure", "indirect_only", "tone_map", "auto_exposure"]
    for stage in stage_list.STAGES:
        names = [name for name, _ in cache_keys.stage_inputs(SMALL, stage)]
        assert names == list(schema.stages_reading(Settings, stage))
    table = cache_keys.describe()
    for stage in stage_list.STAGES:
        assert table.count(f"\n{stage} ") + table.startswith(f"{stage} ") == 1
    assert "display    (gather, fog) exposure, indirect_only, tone_map, auto_exposure" \
        in table
    assert "rsm        (scene) rsm_size, rsm_snap, light, light_kind, light_flux, lights, " \
        "spot_cone, spot_cone_degrees" in table
    assert "geometry   (downsample, grid, gbuffer if uses_camera_occluders)" in table
    # conditional upstream stages count only while their flag is on
    assert cache_keys.downstream("gbuffer", SMALL) == ("gbuffer", "gather", "display")
    assert cache_keys.downstream("gbuffer", SMALL.with_changes(fog=True, camera_occluders=True,
                                                           geometry_volume="one-sided")) == (
        "geometry", "propagate", "gbuffer", "gather", "fog", "display")
    every_flag = types.SimpleNamespace(**{flag: True for decl in stage_list.STAGE_LIST
                                          for _, flag in decl.upstream_when})
    assert cache_keys.downstream("gbuffer") == cache_keys.downstream("gbuffer", every_flag)


def test_a_remembered_stage_key_is_the_stage_key_of_the_same_inputs():
    """The job reuses a stage's key made of the same Settings object and upstream keys,
    and makes it anew (equal, or not) from any other."""
    memo: dict = {}
    upstream = {"gather": ("g",), "fog": ("f",)}
    first = cache_keys.remembered_stage_key(memo, SMALL, "display", upstream, None)
    assert first == cache_keys.stage_key(SMALL, "display", upstream, None)
    assert cache_keys.remembered_stage_key(memo, SMALL, "display", upstream, None) is first
    equal = dataclasses.replace(SMALL)
    again = cache_keys.remembered_stage_key(memo, equal, "display", upstream, None)
    assert again == first and again is not first
    brighter = SMALL.with_changes(exposure=2.0)
    assert cache_keys.remembered_stage_key(memo, brighter, "display", upstream, None) != first
    moved = {**upstream, "gather": ("g", 1)}
    assert cache_keys.remembered_stage_key(memo, brighter, "display", moved, None) == \
        cache_keys.stage_key(brighter, "display", moved, None)
    assert cache_keys.remembered_stage_key(memo, brighter, "display", moved, 0.5)[2] == 0.5


def test_a_stage_key_holds_only_the_switches_its_programs_read(pipeline):
    """Of the corrections a stage's key holds the switches the registry says its programs
    read (Correction.stages, explorer/lpv/corrections.py), so a switch re-runs only the
    stages that read it, and then everything downstream."""
    for stage in stage_list.STAGES:
        read = [entry.name for entry in CORRECTIONS if stage in entry.stages]
        assert [name for name, _ in cache_keys._nested_inputs(Corrections(), stage)] == read
    in_place = Corrections(ping_pong=False)           # read by the propagation only
    assert cache_keys._nested_inputs(in_place, "inject") == cache_keys._nested_inputs(
        Corrections(), "inject")
    assert cache_keys._nested_inputs(in_place, "propagate") != cache_keys._nested_inputs(
        Corrections(), "propagate")
    # the "original" preset leaves the geometry volume's switch corrected
    assert cache_keys._nested_inputs(preset("original"), "geometry") == cache_keys._nested_inputs(
        Corrections(), "geometry")
    with_volume = SMALL.with_changes(geometry_volume="one-sided")
    pipeline.run(with_volume)
    assert pipeline.run(with_volume.with_changes(corrections={"ping_pong": False})
                        ).stages_run == ("propagate", "gather", "display")
    assert pipeline.run(with_volume.with_changes(corrections={"surfel_area_squared": False})
                        ).stages_run == ("geometry", "propagate", "gather", "display")


def test_render_targets_release_their_scopes(gl_context):
    """Nothing a frame makes is left to the garbage collector (a moderngl object dropped
    without release() leaks its native object; "context_gc" collects them instead)."""
    import gc

    previous = gl_context.gc_mode
    gl_context.gc_mode = "context_gc"
    try:
        with Pipeline(SMALL, ctx=gl_context) as pipe:
            for exposure in (1.0, 2.0):
                pipe.run(SMALL.with_changes(exposure=exposure))
            pipe.run(SMALL.with_changes(width=24, rsm_size=16, downsample="average"))
            job = pipe.start(SMALL.with_changes(iterations=3))
            while job.progress.stage != "propagate" or job.progress.done == 0:
                job.advance(0.0)
            assert job.preview()
        gc.collect()
        # released objects arrive as InvalidObject; anything else was never released
        leaked = [type(obj).__name__ for obj in gl_context.objects
                  if type(obj).__name__ != "InvalidObject"]
        assert leaked == []
    finally:
        gl_context.gc_mode = previous
        for obj in list(gl_context.objects):
            if type(obj).__name__ != "InvalidObject":
                obj.release()
        gl_context.objects.clear()


def test_gather_writes_linear_light_only(pipeline):
    result = pipeline.run(SMALL)
    targets = pipeline.state.gather_pass.targets
    assert set(targets) == {"direct", "indirect", "received"}
    assert np.allclose(read_texture(targets["direct"])[..., :3], result.direct)


def test_the_gather_runs_in_bands_that_make_the_whole_image(gl_context, ctx):
    from explorer.lpv.passes.gather import bands

    assert bands((960, 540)) == [(round(i * 540 / 8), round((i + 1) * 540 / 8))
                                 for i in range(8)]
    assert bands((10, 3), band_pixels=1) == [(0, 1), (1, 2), (2, 3)]   # a row at least
    assert bands((64, 64)) == [(0, 64)]
    settings = SMALL.with_changes(width=300, height=260)              # 78000 pixels
    calls = []
    with Pipeline(settings, ctx=gl_context) as pipe:
        banded = pipe.run(progress=lambda *call: calls.append(call))
        # two bands, the read-backs of direct, indirect and received (copied in one unit,
        # then taken a unit each), then their sums and checks: a unit each
        assert [c for c in calls if c[0] == "gather"] == [("gather", k, 7) for k in range(8)]
        gather = pipe.stages["gather"]
        gather.gather_levels(settings)                                 # all rows at once
        whole = read_texture(gather.gather.targets["indirect"])[..., :3]
        assert np.array_equal(banded.indirect, whole) and banded.indirect.max() > 0
        # one band leaves the other rows alone
        gather.gather._targets.framebuffer.clear(0.0, 0.0, 0.0, 0.0)
        gather.gather_levels(settings, (0, 100))                       # GL rows: bottom up
        band = read_texture(gather.gather.targets["indirect"])[..., :3]
        assert np.array_equal(band[-100:], whole[-100:])
        assert not band[:-100].any()


def test_a_large_step_runs_in_slabs_with_the_same_result(gl_context, ctx, monkeypatch):
    """A propagation step is dispatched in slabs of z layers (units of a time-sliced
    frame): the result is the one-slab result, and the progress counts steps."""
    import sys

    propagate = sys.modules["explorer.lpv.passes.propagate"]   # the package exports a function
    assert propagate.slabs(64) == [(z, z + 8) for z in range(0, 64, 8)]
    assert propagate.slabs(32) == [(0, 32)]
    assert propagate.slabs(128) == [(z, z + 4) for z in range(0, 128, 4)]
    assert propagate.slabs(10, slab_cells=250) == [(0, 4), (4, 8), (8, 10)]
    settings = SMALL.with_changes(geometry_volume="one-sided", bounces=2)
    with Pipeline(settings, ctx=gl_context) as pipe:
        whole = pipe.run(settings)
        monkeypatch.setattr(propagate, "SLAB_CELLS", 8 * 8 * 2)          # 4 z layers
        pipe.invalidate("propagate")
        calls = []
        job = pipe.start(settings, progress=lambda *call: calls.append(call))
        while not job.done:
            job.advance(0.0)     # one unit a call: no budget left to group slabs in
        sliced = job.result
    steps = [done for stage, done, _ in calls if stage == "propagate"]
    # the stage's start, the level's start, after each of the two slabs of every step the
    # steps completed, and the level's audit and read-back (copied in one unit, taken in
    # the next)
    assert steps == [0, 0, 0] + sorted(2 * list(range(1, settings.iterations))) + [
        settings.iterations] * 3
    assert np.allclose(sliced.accumulated, whole.accumulated, rtol=1e-6, atol=1e-9)
    for name in ("per_step", "border_loss", "occluded", "reflected"):
        assert np.allclose(getattr(sliced.audit, name), getattr(whole.audit, name),
                           rtol=1e-5, atol=1e-9), name


def test_a_job_sizes_each_unit_by_the_same_unit_of_the_last_run(pipeline):
    """A stage's units differ (a propagation's start, its steps, its audit and its
    read-backs): the next unit is estimated by the one at the same place last time."""
    def in_units(job):
        while not job.done:
            job.advance(0.0)         # one unit a call (no slabs grouped)

    pipeline.invalidate("propagate")
    in_units(pipeline.start(SMALL))
    last = dict(pipeline.unit_ms_at)
    pipeline.invalidate("propagate")
    job = pipeline.start(SMALL)
    estimates = []
    while not job.done:
        if job.stage == "propagate":
            estimates.append(job.next_unit_ms())
        job.advance(0.0)             # one unit
    assert len(estimates) > SMALL.iterations
    assert estimates == [last[("propagate", unit)] for unit in range(len(estimates))]
    assert len(set(estimates)) > 1          # the units are not all alike


def test_a_grid_stage_is_sized_at_the_grid_it_runs_at(pipeline, monkeypatch):
    """The propagation's first unit at a larger grid is estimated by the same unit at the
    smaller grid scaled up by the cells, and by itself once measured at that grid (the
    first 64³ job after 32³ ones is not sized by the 32³ units)."""
    from explorer.lpv.job import GRID_STAGES, Job

    assert "propagate" in GRID_STAGES and "inject" in GRID_STAGES
    assert not set(GRID_STAGES) & set(stage_list.PIXEL_STAGES)
    estimates: dict[tuple, float] = {}
    run_unit = Job._run_unit

    def recorded(job):
        estimates.setdefault((job.stage, job.settings.grid_size, len(estimates)),
                             job.next_unit_ms())
        run_unit(job)

    pipeline.run(SMALL)
    small_start = pipeline.unit_ms_at[("propagate", 0)]
    monkeypatch.setattr(Job, "_run_unit", recorded)

    def first_propagate_estimate(settings) -> float:
        estimates.clear()
        job = pipeline.start(settings)
        while not job.done:
            job.advance(0.0)
        return next(ms for (stage, _, _), ms in estimates.items() if stage == "propagate")

    big = SMALL.with_changes(grid_size=16)
    assert first_propagate_estimate(big) == small_start * 8       # 16³ / 8³ cells
    big_start = pipeline.unit_ms_sized[("propagate", 0, 16 ** 3)]
    pipeline.invalidate("propagate")
    assert first_propagate_estimate(big) == big_start              # measured there now
