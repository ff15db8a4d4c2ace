"""What a frame costs besides the GPU's work: the propagation's small steps grouped into
units with the bindings a level's steps share kept, the GL calls the overhead counter
sees, the same numbers whatever the units (explorer/lpv/stages/propagate.py
``advance_group``, explorer/gl/call_counter.py)."""

import numpy as np
import pytest

from explorer.gl.call_counter import GlCallCounter
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings

TINY = Settings(scene="cornell", grid_size=8, iterations=16, rsm_size=32, width=48,
                height=32)


@pytest.fixture
def pipeline(gl_context, ctx):   # ctx: checks for GL errors
    pipe = Pipeline(TINY, ctx=gl_context)
    pipe.run(TINY)
    pipe.timer.queued = True          # the passes queued, as on a GPU (bench --overhead)
    yield pipe
    pipe.release()


def counted_frame(pipeline, first_stage: str, budget_ms: float | None, audit="full"):
    """One frame re-run from ``first_stage``: its result and what the counter saw.
    ``budget_ms`` 0.0: one unit of work a call (no budget left to group in)."""
    pipeline.invalidate(first_stage)
    with GlCallCounter() as counter:
        job = pipeline.start(TINY, need_audit=audit)
        units = 0
        while not job.done:
            job.advance(budget_ms)
            units += 1
    return job.result, counter.tally.calls, units


@pytest.mark.parametrize("audit", ["full", "flux"])
def test_small_steps_grouped_keep_their_bindings_and_their_numbers(pipeline, audit,
                                                                   monkeypatch):
    import sys

    one_by_one, single, _ = counted_frame(pipeline, "propagate", 0.0, audit)
    # every step in one unit (on this loaded machine 2 ms may hold only a few)
    monkeypatch.setattr(sys.modules["explorer.lpv.stages.propagate"], "GROUP_MS", 1e9)
    grouped, calls, units = counted_frame(pipeline, "propagate", None, audit)
    assert units == 1
    # the accumulation images, the audit's buffers and the geometry volume stay bound
    # between a level's steps in one unit, and ping and pong stay on units of their own
    # (flux: each step binds its target images and the reduction's textures, which are
    # the next step's source): fewer bindings; as many dispatches, but that the full
    # audit reduces the records of the unit's steps after its first in one dispatch
    grouped_reductions = TINY.iterations - 2 if audit == "full" else 0
    assert calls["dispatches"] == single["dispatches"] - grouped_reductions
    assert calls["bindings"] < single["bindings"]
    assert calls["bindings"] <= 6 * TINY.iterations + 50     # + the other stages
    # the same work in the same order: the same numbers, exactly
    assert np.array_equal(grouped.accumulated, one_by_one.accumulated)
    assert np.array_equal(grouped.final_image, one_by_one.final_image)
    assert np.array_equal(grouped.audit.per_step, one_by_one.audit.per_step)


def test_a_budget_of_no_time_runs_one_slab_a_unit(pipeline):
    """Within a frame budget a unit groups no more than the budget left allows: with
    none left, every step is a unit of its own (a progressive picture per step)."""
    pipeline.invalidate("propagate")
    job = pipeline.start(TINY, need_audit="flux")
    done = []
    while not job.done:
        progress = job.advance(0.0)
        if progress.stage == "propagate":
            done.append(progress.done)
    assert [d for d in done if 0 < d < TINY.iterations] == list(range(1, TINY.iterations))


def test_the_counter_counts_the_timer_queries_of_a_camera_frame(pipeline):
    """The timer queries (explorer/gl/gpu_sync.py calls them through ctypes) are GL calls
    of the frame: a camera frame times its three passes with one query each."""
    _, calls, _ = counted_frame(pipeline, "gbuffer", None)
    assert calls["queries"] == 3                     # G-buffer, gather, display
    assert calls["uniform uploads"] <= 2             # the camera's two matrices
    assert calls["GL calls"] > calls["queries"] + calls["bindings"]


DEFAULT_SMALL = Settings(grid_size=8, iterations=8, rsm_size=32, width=48, height=32)
"""The default Settings at sizes where a frame is quick."""


def window_frames(pipe, settings, audit="flux", budget_ms=30.0, first_stage=None):
    """A job run as the window runs it (``budget_ms`` a frame until done): the result and
    the most finishes and synchronous read-backs any one of its frames issued."""
    if first_stage is not None:
        pipe.invalidate(first_stage)
    job = pipe.start(settings, need_audit=audit)
    worst = {"finishes": 0, "read-backs": 0}
    waited = 0
    for _ in range(500):
        with GlCallCounter() as counter:
            job.advance(budget_ms)
        for kind in worst:
            worst[kind] = max(worst[kind], counter.tally.calls.get(kind, 0))
        if job.done:
            break
        waited += job.gpu_pending
    return job.result, worst, waited


@pytest.fixture
def queued_pipeline(gl_context, ctx):
    pipe = Pipeline(DEFAULT_SMALL, ctx=gl_context)
    pipe.run(DEFAULT_SMALL)
    pipe.timer.queued = True
    yield pipe
    pipe.release()


@pytest.mark.parametrize("first_stage", ["rsm", "inject", "gbuffer", "display"])
@pytest.mark.parametrize("audit", ["full", "flux"])
def test_a_default_frame_neither_waits_nor_reads_back_at_once(queued_pipeline, first_stage,
                                                              audit):
    """Every kind of frame at the default settings (full, light, camera, display), its
    passes queued: no finish (the window's swap is a frame's one wait) and no synchronous
    read-back in any of its window frames."""
    _, worst, _ = window_frames(queued_pipeline, DEFAULT_SMALL, audit, first_stage=first_stage)
    assert worst == {"finishes": 0, "read-backs": 0}


@pytest.fixture
def fences_late(monkeypatch):
    """A fence reads unsignaled the first time it is asked (a GPU still copying): a job
    within a budget then takes its read-backs in a later frame."""
    from explorer.gl import gpu_sync

    signaled, asked = gpu_sync.Fence.signaled, set()

    def late(fence) -> bool:
        if id(fence) in asked:
            return signaled(fence)
        asked.add(id(fence))
        return False

    monkeypatch.setattr(gpu_sync.Fence, "signaled", late)


def test_a_moved_object_queues_its_upload(queued_pipeline):
    """Posing an object (the scene stage) writes its corners without waiting for the GPU
    when the passes are queued."""
    scene = queued_pipeline.base_scene
    moved = DEFAULT_SMALL.with_changes(object_transforms={scene.objects[0].name:
                                                          (0.05, 0.0, 0.0)})
    result, worst, _ = window_frames(queued_pipeline, moved)
    assert "scene" in result.stages_run
    assert worst == {"finishes": 0, "read-backs": 0}


def test_the_geometry_volume_read_a_frame_late_is_the_synchronous_one(queued_pipeline,
                                                                       fences_late):
    s = DEFAULT_SMALL.with_changes(geometry_volume="double-sided", cascades=2)
    result, worst, waited = window_frames(queued_pipeline, s, audit="full")
    assert worst == {"finishes": 0, "read-backs": 0}
    assert waited > 0, "no frame ended on a read-back still in flight"
    assert "geometry" in result.stages_run and len(result.cascades) == 2
    for level, kept in zip(queued_pipeline.state.cascades, result.cascades):
        assert np.array_equal(kept.geometry_volume, level.volume.read())   # synchronous
        assert kept.geometry_volume.any()


def test_the_light_records_are_written_once_per_light_change(queued_pipeline):
    """A camera frame binds the gather's light records without writing them again; views
    made anew (the light views of another RSM size) are written."""
    from explorer.lpv.passes.light_records import LightRecordBuffer
    from explorer.lpv.passes.rsm import light_views

    scene = queued_pipeline.scene_state.scene
    views = light_views(scene, 32)
    buffer = LightRecordBuffer(queued_pipeline.ctx)

    def calls(bound) -> int:
        with GlCallCounter() as counter:
            buffer.bind(bound)
        return counter.tally.calls["GL calls"]

    try:
        made = calls(views)                       # made, written, bound
        assert calls(list(views)) == made - 2     # bound only
        assert calls(light_views(scene, 16)) == made - 1     # written and bound
    finally:
        buffer.release()


def test_the_rgb_sums_add_in_row_order_as_before():
    """The gathered and the RSM flux: the rgb channels' float64 sums taken without copying
    the rgb slice give the bits of the sums of the slice, on values over 40 decades (where
    another order of the additions gives other bits)."""
    from explorer.lpv.audit import rgb_sums

    rng = np.random.default_rng(32)
    for trial in range(40):
        h, w = rng.integers(1, 90, 2)
        image = (rng.random((h, w, 4)) * 10.0 ** rng.uniform(-20, 20, (h, w, 4))
                 ).astype(np.float32)
        if trial % 2:
            image = image[::-1]                                  # a flipped view
        rows = np.add.reduce(image[..., :3].reshape(-1, 3), axis=0, dtype=np.float64)
        assert rgb_sums(image).tobytes() == rows.tobytes()
    pairwise = np.add.reduce(np.ascontiguousarray(image[..., :3].reshape(-1, 3).T), axis=1,
                             dtype=np.float64)
    assert pairwise.tobytes() != rows.tobytes()       # the order matters on such values
