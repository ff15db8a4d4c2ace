"""``lpv-explorer bench --overhead``: what a frame costs besides the GPU's work, on sizes
where that work is negligible (an 8³ grid, a 64² image and RSM unless given).

Each row re-runs one kind of frame ``--repeat`` times (default
:data:`DEFAULT_FRAMES`) with the moderngl calls counted (:class:`GlCallCounter`) and
prints per frame: the wall time, the Python time outside GL calls (the CPU side a GPU
would not hide), and the GL calls, dispatches, draws, barriers, finishes, read-backs,
uniform uploads and bindings issued. Rows (:data:`FRAMES`): ``full`` (every stage from
the RSM on, as ``bench`` times a frame), ``light`` (a correction or the light changed:
from the injection on), ``camera`` (the camera moved: G-buffer, gather, display) and
``display`` (an exposure change: the display pass only). These rows run each job to its
end with the passes queued as on a GPU (``PassTimer.queued``: no ``finish`` around a
pass, timer queries read later), so that their counts are what a GPU would be sent.

The ``window`` row is a default window frame: the window's pipeline controller
(explorer/ui/controller.py) at the default settings and these sizes, a correction toggled
and every frame given the default frame budget until the picture has converged; its
counts are per frame and its ``max`` the worst frame. Target (:data:`WINDOW_TARGET`): at
most one finish (a wait for the GPU: ``ctx.finish`` or a fence waited on) and no
synchronous read-back in any such frame; the command's exit status is 1 when it is
missed.
"""

from __future__ import annotations

import argparse
import time

from explorer.commands import options
from explorer.gl.call_counter import GlCallCounter

DEFAULT_FRAMES = 20
TINY = {"grid_size": 8, "width": 64, "height": 64, "rsm_size": 64}
"""Sizes of the overhead rows unless --grids, --size or --rsm-size give others."""
FRAMES = (("full", "rsm"), ("light", "inject"), ("camera", "gbuffer"), ("display", "display"))
"""Row name -> the first stage it re-runs (``Pipeline.invalidate``)."""
COUNTED = ("GL calls", "dispatches", "draws", "barriers", "finishes", "read-backs",
           "queued copies", "deferred reads", "uniform uploads", "bindings")
"""``read-backs`` are the synchronous ones (explorer/gl/call_counter.py)."""
WINDOW_TARGET = {"finishes": 1, "read-backs": 0}
"""The most of each a default window frame may issue."""
WINDOW_BUDGET_MS = 30.0
"""The frame budget of the ``window`` row (``AppState.frame_budget_ms``' default)."""
WINDOW_FRAMES = 200
"""The ``window`` row gives up after this many frames of one toggle."""


def tiny_settings(args: argparse.Namespace):
    """The settings of the overhead rows: the command line's, with :data:`TINY` sizes
    where it gives none."""
    base = options.settings_from_args(args)
    changes = {"grid_size": (args.grid_size or (TINY["grid_size"],))[0]}
    if args.size is None:
        changes.update(width=TINY["width"], height=TINY["height"])
    if args.rsm_size is None:
        changes["rsm_size"] = TINY["rsm_size"]
    return base.with_changes(**changes)


def measure_overhead(pipeline, settings, frames: int) -> list[dict]:
    """One row per entry of :data:`FRAMES`: per-frame wall and outside-GL milliseconds,
    call counts, and the outside-GL milliseconds by stage (``python_by_stage_ms``: each
    unit of work's; ``job`` is the time between units), over ``frames`` frames after two
    warm-up frames."""
    options.run_pipeline(pipeline, settings)
    options.run_pipeline(pipeline, settings)
    rows = []
    queued, pipeline.timer.queued = pipeline.timer.queued, True
    try:
        for name, first_stage in FRAMES:
            rows.append(_row(pipeline, settings, frames, name, first_stage))
    finally:
        pipeline.timer.queued = queued
    return rows


def _row(pipeline, settings, frames: int, name: str, first_stage: str) -> dict:
    wall = 0.0
    with GlCallCounter() as counter, _UnitTimes(counter) as units:
        for _ in range(frames):
            pipeline.invalidate(first_stage)
            start = time.perf_counter()
            pipeline.start(settings).advance(None)
            wall += time.perf_counter() - start
    per_frame = counter.tally.per(frames)
    outside_ms = (wall - counter.tally.inside_s) / frames * 1e3
    by_stage = {stage: ms / frames for stage, ms in units.python_ms.items()}
    by_stage["job"] = max(outside_ms - sum(by_stage.values()), 0.0)
    return {"frame": name, "reruns_from": first_stage,
            "wall_ms": wall / frames * 1e3, "outside_gl_ms": outside_ms,
            "counts": {kind: per_frame.get(kind, 0.0) for kind in COUNTED},
            "python_by_stage_ms": by_stage}


def measure_window_frames(ctx, settings, toggles: int) -> dict:
    """The ``window`` row (module docstring): ``toggles`` times a correction switched
    (off, then on again) and the controller's frames counted until each converged."""
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.controller import PipelineController
    from explorer.ui.state import AppState

    state = AppState(settings=settings)
    controller = PipelineController(ctx, Pipeline)
    try:
        for _ in range(WINDOW_FRAMES):          # the first picture, then the full size
            if not controller.update(state, WINDOW_BUDGET_MS, need_audit="flux").busy \
                    and controller.sides["A"].done is not None \
                    and controller.sides["A"].done.settings.width == settings.width:
                break
        controller.sides["A"].pipeline.timer.queued = True
        worst: dict[str, float] = {kind: 0.0 for kind in COUNTED}
        frames, wall, inside = 0, 0.0, 0.0
        total = GlCallCounter().tally.calls
        for toggle in range(toggles):
            state.set_corrections(propagation_4pi=toggle % 2 == 1)
            for _ in range(WINDOW_FRAMES):
                with GlCallCounter() as counter:
                    start = time.perf_counter()
                    status = controller.update(state, WINDOW_BUDGET_MS, need_audit="flux")
                    wall += time.perf_counter() - start
                inside += counter.tally.inside_s
                frames += 1
                total.update(counter.tally.calls)
                for kind in COUNTED:
                    worst[kind] = max(worst[kind], counter.tally.calls.get(kind, 0))
                if not status.busy:
                    break
    finally:
        controller.release()
    per_frame = {kind: total.get(kind, 0) / max(frames, 1) for kind in COUNTED}
    met = all(worst[kind] <= most for kind, most in WINDOW_TARGET.items())
    return {"frame": "window", "reruns_from": "a toggle", "frames": frames,
            "wall_ms": wall / max(frames, 1) * 1e3,
            "outside_gl_ms": (wall - inside) / max(frames, 1) * 1e3,
            "counts": per_frame, "max": worst, "target": dict(WINDOW_TARGET),
            "target_met": met, "python_by_stage_ms": {}}


class _UnitTimes:
    """While active, the Python milliseconds (outside the counted GL calls) of every unit
    of a job, summed by stage: ``Job._run_unit`` wrapped (one job's units at a time)."""

    def __init__(self, counter: GlCallCounter) -> None:
        self.counter = counter
        self.python_ms: dict[str, float] = {}

    def __enter__(self) -> _UnitTimes:
        from explorer.lpv.job import Job

        self._original = original = Job._run_unit
        tally, totals = self.counter.tally, self.python_ms

        def timed_unit(job) -> None:
            stage, inside, start = job.stage, tally.inside_s, time.perf_counter()
            try:
                original(job)
            finally:
                spent = time.perf_counter() - start - (tally.inside_s - inside)
                totals[stage] = totals.get(stage, 0.0) + spent * 1e3

        Job._run_unit = timed_unit
        return self

    def __exit__(self, *exc_info) -> None:
        from explorer.lpv.job import Job

        Job._run_unit = self._original


def format_overhead(rows: list[dict]) -> str:
    header = ["frame", "wall ms", "python ms", *COUNTED]
    widths = [8, 9, 10] + [max(9, len(kind)) for kind in COUNTED]
    lines = ["  ".join(f"{h:>{w}}" for h, w in zip(header, widths))]
    for row in rows:
        cells = [row["frame"], f"{row['wall_ms']:.2f}", f"{row['outside_gl_ms']:.2f}"]
        cells += [f"{row['counts'][kind]:.0f}" for kind in COUNTED]
        lines.append("  ".join(f"{c:>{w}}" for c, w in zip(cells, widths)))
    for row in rows:
        if "max" in row:
            cells = [f"{row['frame']} max", "", ""]
            cells += [f"{row['max'][kind]:.0f}" for kind in COUNTED]
            lines.append("  ".join(f"{c:>{w}}" for c, w in zip(cells, widths)))
    for row in rows:
        stages = sorted(row["python_by_stage_ms"].items(), key=lambda item: -item[1])
        if stages:
            lines.append(f"  python ms of a {row['frame']} frame by stage: " + ", ".join(
                f"{stage} {ms:.2f}" for stage, ms in stages if ms >= 0.005))
    for row in rows:
        if "target_met" in row:
            wanted = ", ".join(f"{kind} ≤ {most}" for kind, most in row["target"].items())
            lines.append(f"  a default window frame ({row['frames']} frames of toggles): "
                         f"{wanted} in every frame: "
                         + ("met" if row["target_met"] else "NOT met"))
    return "\n".join(lines)
