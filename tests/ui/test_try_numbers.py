"""A try-this prompt keeps the numbers of its press after Undo and names the step's own
numbers before the press (explorer/ui/try_numbers.py), read on real frames."""

from __future__ import annotations

from dataclasses import replace

from explorer.lessons import find_lesson, live_values, load_all, preview_settings
from explorer.lpv.pipeline import Pipeline
from explorer.ui.try_numbers import KEPT_FRAMES, TryFrames


def test_the_prompt_keeps_both_frames_numbers(ctx):
    lessons, _ = load_all(check_formula=None)
    step = find_lesson("spherical-harmonics", lessons).step(5)     # the front-face clamp
    item = step.try_this[0]
    settings = preview_settings(step, max_iterations=4)
    after = item.apply(settings)
    with Pipeline(settings, ctx=ctx) as pipeline:
        before_frame = pipeline.run(settings)
        after_frame = pipeline.run(after)
    frames = TryFrames()
    key, step_key = ("spherical-harmonics", 5, 1), ("spherical-harmonics", 5)
    frames.keep_step(step_key, before_frame)
    frames.keep_after(key, after_frame)
    base = live_values.LiveContext(settings=settings, result=before_frame)
    pending = replace(base, settings=after, result=None)
    kept = frames.after_context(key, pending)                       # after Undo
    assert kept.result is frames.after[key] and kept.result.settings == after_frame.settings
    shown_after = live_values.render("audit.clamp_gain", ".3g", kept)
    shown_before = live_values.render("audit.clamp_gain", ".3g", base)
    assert shown_after != shown_before and live_values.PENDING not in shown_after
    note = frames.before_note(step_key, item.prompt, base)
    assert note.startswith("before the press: ") and f"{shown_before} W" in note
    # a frame of other settings (the reader changed the window size) is not used
    other = replace(pending, settings=after.with_changes(width=after.width + 2))
    assert frames.after_context(key, other).result is None
    # pressed in a grid of views (side by side), the frame rendered at its cell's size:
    # the full view after Undo still gets the press's numbers
    frames.keep_after(key, after_frame, any_size=True)
    assert frames.after_context(key, other).result is frames.after[key]
    other_config = replace(pending, settings=after.with_changes(iterations=after.iterations + 1))
    assert frames.after_context(key, other_config).result is None
    assert TryFrames().before_note(step_key, item.prompt, base) == ""


def test_kept_frames_hold_no_steps_and_are_bounded(ctx):
    """The window keeps a frame per step visited: without this bound each held its
    propagation steps (about 200 MiB a cascade at 64³) for the rest of the session."""
    lessons, _ = load_all(check_formula=None)
    step = find_lesson("propagation", lessons).step(1)
    settings = preview_settings(step, max_iterations=4)
    with Pipeline(settings, ctx=ctx) as pipeline:
        frame = pipeline.run(settings, keep_steps=True)
    assert frame.steps is not None
    frames = TryFrames()
    for number in range(KEPT_FRAMES + 5):
        frames.keep_step(("propagation", number), frame)
        frames.keep_after(("propagation", number, 1), frame)
    assert len(frames.before) == len(frames.after) == KEPT_FRAMES
    assert ("propagation", 0) not in frames.before                 # the oldest went first
    kept = frames.before[("propagation", KEPT_FRAMES + 4)]
    assert all(level.steps is None and level.cell_records is None for level in kept.cascades)
    assert frame.steps is not None                                  # the shown frame keeps its own
    base = live_values.LiveContext(settings=settings, result=frame)
    lean = replace(base, result=kept)
    for name in ("audit.clamp_gain", "audit.accumulated", "frame.rsm_views"):
        assert live_values.render(name, ".6g", lean) == live_values.render(name, ".6g", base)
    again = frames.before[("propagation", KEPT_FRAMES + 4)]
    frames.keep_step(("propagation", KEPT_FRAMES + 4), frame)      # the same frame redrawn
    assert frames.before[("propagation", KEPT_FRAMES + 4)] is again


def test_kept_frames_are_bounded_in_bytes(ctx, monkeypatch):
    """Twelve 64³ two-cascade frames of each kind held over a gigabyte of accumulated grids
    and images (issue #31): the kept frames of one kind hold at most KEPT_BYTES of arrays,
    the newest whatever its size, the oldest going first."""
    import explorer.ui.try_numbers as try_numbers

    lessons, _ = load_all(check_formula=None)
    step = find_lesson("propagation", lessons).step(1)
    settings = preview_settings(step, max_iterations=2)
    with Pipeline(settings, ctx=ctx) as pipeline:
        frames_made = [pipeline.run(settings.with_changes(iterations=2 + number))
                       for number in range(4)]
    one = try_numbers.held_bytes(try_numbers.lean_frame(frames_made[0]))
    assert one >= frames_made[0].accumulated.nbytes + frames_made[0].direct.nbytes
    monkeypatch.setattr(try_numbers, "KEPT_BYTES", 2 * one + one // 2)   # room for two
    kept = TryFrames()
    for number, frame in enumerate(frames_made):
        kept.keep_step(("propagation", number), frame)
    assert list(kept.before) == [("propagation", 2), ("propagation", 3)]
    assert set(kept.sizes) == set(kept.before)
    monkeypatch.setattr(try_numbers, "KEPT_BYTES", 1)                  # smaller than any
    kept.keep_step(("propagation", 9), frames_made[0])
    assert list(kept.before) == [("propagation", 9)]                   # the newest stays
