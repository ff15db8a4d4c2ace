"""A window frame queues its GPU work without waiting (explorer/gl/gpu_sync.py): read-backs
are copied behind fences and taken a frame later, and what they give is what the
synchronous read-back gives (the audit, the exposure, the picked values)."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.commands.overhead_bench import WINDOW_TARGET, measure_window_frames
from explorer.gl import gpu_sync
from explorer.gl.gpu_sync import DeferredRead, issue_together
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.ui.controller import PipelineController
from explorer.ui.overlays.picking import pick_pixel
from explorer.ui.state import AppState

SMALL = Settings(scene="cornell", grid_size=8, iterations=6, rsm_size=32, width=48,
                 height=36)


def test_a_default_window_frame_waits_at_most_once_and_reads_nothing_back_at_once(
        gl_context):
    """The window's frames for toggles (the passes queued as on a GPU): no finish, no
    synchronous read-back, every read-back a copy taken later."""
    row = measure_window_frames(gl_context, SMALL, toggles=2)
    assert row["frames"] >= 2
    for kind, most in WINDOW_TARGET.items():
        assert row["max"][kind] <= most, (kind, row["max"])
    assert row["target_met"]
    assert row["counts"]["queued copies"] > 0 and row["counts"]["deferred reads"] > 0


def test_a_deferred_read_gives_the_synchronous_bytes_and_waits_only_when_asked(gl_context):
    data = np.arange(5 * 3 * 4, dtype=np.float32).reshape(3, 5, 4)
    texture = gl_context.texture((5, 3), 4, data.tobytes(), dtype="f4")
    read = DeferredRead(gl_context)
    try:
        assert read.result() is None and not read.issued       # nothing issued yet
        read.issue(texture, (3, 5, 4), "f4")
        assert np.array_equal(read.wait(), np.frombuffer(texture.read(), "f4").reshape(3, 5, 4))
        assert np.array_equal(read.result(), data)
        before = read.serial
        read.issue(texture, (3, 5, 4), "f4")
        assert read.serial == before + 1
    finally:
        read.release()
        texture.release()


def test_a_deferred_read_reissued_with_another_shape_or_type_reads_that(gl_context):
    """A read keeps the shape, type and buffer of its last copy while they are the same
    (a stage's frames); another shape, type or size is read as asked."""
    data = np.arange(6 * 4 * 4, dtype=np.float32).reshape(4, 6, 4)
    texture = gl_context.texture((6, 4), 4, data.tobytes(), dtype="f4")
    read = DeferredRead(gl_context)
    try:
        for shape, dtype in (((4, 6, 4), "f4"), ((4, 6, 4), "f4"), ((24, 4), "f4"),
                             ((4, 6, 4), np.dtype("i4")), ((4, 6, 4), "f4")):
            read.issue(texture, shape, dtype)
            got = read.wait()
            assert got.shape == shape and got.dtype == np.dtype(dtype)
            assert np.array_equal(got.view("f4").reshape(data.shape), data)
        small = gl_context.texture((2, 2), 4, data[:2, :2].tobytes(), dtype="f4")
        read.issue(small, (2, 2, 4))                  # fewer bytes: a buffer of its size
        assert np.array_equal(read.wait(), data[:2, :2])
        small.release()
    finally:
        read.release()
        texture.release()


def test_reads_issued_together_share_one_fence_held_until_the_last_lets_go(gl_context):
    """issue_together: each read gets its texture's bytes, behind one fence after the last
    copy; a read issued anew or released lets go of it, and the last one deletes it."""
    arrays = [np.arange(5 * 3 * 4, dtype=np.float32).reshape(3, 5, 4) + k for k in range(3)]
    textures = [gl_context.texture((5, 3), 4, a.tobytes(), dtype="f4") for a in arrays]
    reads = [DeferredRead(gl_context) for _ in textures]
    try:
        issue_together(reads, textures, [(3, 5, 4)] * 3)
        fence = reads[0]._fence
        assert fence is not None and all(read._fence is fence for read in reads)
        assert all(read.serial == 1 for read in reads)
        reads[1].issue(textures[1], (3, 5, 4))            # its own fence now
        assert reads[1]._fence is not fence and fence._sync is not None
        reads[0].release()
        assert fence._sync is not None                    # reads[2] still holds it
        assert np.array_equal(reads[2].wait(), arrays[2])
        assert np.array_equal(reads[1].wait(), arrays[1])
        reads[2].release()
        assert fence._sync is None
    finally:
        for read, texture in zip(reads, textures):
            read.release()
            texture.release()


@pytest.fixture
def late_fences(monkeypatch):
    """Every fence reads unsignaled the first two times it is asked (a GPU still
    copying), so that a window job takes its read-backs a frame after it issued them:
    the job's own check of its unit's reads asks once, the test's look at
    ``gpu_pending`` after the frame a second time (a stage's reads share one fence,
    ``issue_together``)."""
    signaled = gpu_sync.Fence.signaled
    asked: dict[int, int] = {}

    def late(fence) -> bool:
        asked[id(fence)] = asked.get(id(fence), 0) + 1
        if asked[id(fence)] <= 2:
            return False
        return signaled(fence)

    monkeypatch.setattr(gpu_sync.Fence, "signaled", late)


def test_read_backs_taken_a_frame_late_give_the_synchronous_numbers(gl_context, late_fences):
    state = AppState(settings=SMALL)
    state.follow_view_size = False
    controller = PipelineController(gl_context, Pipeline)
    waited = 0
    try:
        for _ in range(400):
            status = controller.update(state, 50.0, need_audit="full")
            side = controller.sides["A"]
            if side.job is not None:
                side.pipeline.timer.queued = True           # as on a GPU: nothing waited
                waited += side.job.gpu_pending
            done = side.done
            if not status.busy and done is not None and done.settings.width == SMALL.width:
                break
        late = controller.sides["A"].result
        exposures = state.runtime.frame.side_exposures
        with Pipeline(SMALL, ctx=gl_context) as pipeline:
            pipeline.timer.queued = False
            synchronous = pipeline.run(need_audit="full")
    finally:
        controller.release()
    assert waited > 0, "no frame ended on a read-back still in flight"
    assert late is not None and late.settings == synchronous.settings
    for name in ("direct", "indirect", "received", "albedo", "gbuffer_position",
                 "gbuffer_normal", "accumulated"):
        assert np.array_equal(getattr(late, name), getattr(synchronous, name)), name
    # the audit
    for name in ("per_step", "border_loss", "occluded", "reflected", "injected"):
        assert np.array_equal(getattr(late.audit, name), getattr(synchronous.audit, name)), name
    assert np.array_equal(late.audit.gathered, synchronous.audit.gathered)
    # the exposure: the display stage's and the window's auto exposure of the frame
    assert late.display_scale == synchronous.display_scale
    from explorer.ui.side_display import result_scale

    assert result_scale(late, False) == result_scale(synchronous, False)
    assert exposures[0] > 0
    # the picked values of a lit pixel
    y, x = np.argwhere(synchronous.gbuffer_position[..., 3] > 0.5)[len(late.direct) // 2]
    picked, expected = pick_pixel(late, int(x), int(y)), pick_pixel(synchronous, int(x), int(y))
    assert picked.surface and np.array_equal(picked.indirect, expected.indirect)
    assert np.array_equal(picked.indirect_from_grid, expected.indirect_from_grid)
