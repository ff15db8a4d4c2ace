"""Verifying a lesson step's checks (:mod:`explorer.lessons.checks`) on the converged
frames of that step, rendered headless at the sizes of
:func:`explorer.lessons.render.shrink_settings`: what CI runs for every checked step
(tests/lessons/test_lesson_checks.py) and ``lpv-explorer lessons --check``. It lives apart
from the checks module, which the reader imports to read the checks, because it renders.

Three kinds of numbers besides the frame's own:

* ``figure.<id>.<readout>``: the figure as the step declares it (its parameters, nothing
  dragged), through a ``figure_readouts(spec, results)`` function the caller hands in
  (the figures draw with imgui, a layer above the lessons: ``lpv-explorer lessons
  --check`` and the tests pass :func:`explorer.ui.figures.declared_readouts`). The
  figures that plot frames (``FigureKindDecl.results``) get the check's frame as
  configuration A, and the compare side's as B when the step's view compares.
* ``error.*``: the Error panel's measurement (:class:`explorer.truth.progressive.ErrorJob`,
  the one-bounce reference with shadow rays) of the check's settings at
  :data:`ERROR_MEASUREMENT`, computed only for a frame whose checks name it.
* ``mark.*`` and the rest: the check's converged frame.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from explorer.lessons.checks import Check, Outcome, evaluate
from explorer.lessons.render import shrink_settings

CHECK_SIZE = {"size": 64, "max_grid": 48, "rsm_size": 64, "max_iterations": 64}
"""The sizes CI verifies the checks at (``shrink_settings``): small enough to
run every checked step in seconds on llvmpipe, large enough that every claim of the
shipped lessons holds there as it does at the steps' own sizes."""
ERROR_SIZE = {"size": 64, "rsm_size": 32}
"""The Error panel's measurement as the checks make it (``Measurement(size, rsm_size)``,
reference ``visible``; sizes the panel offers): a 64² image against 32² VPLs costs under
a second per measurement on llvmpipe, its LPV frame included (against 64² VPLs the
reference alone takes one to five seconds). Its numbers differ from those at the panel's
default 128² × 64² by up to about a tenth (a 48² image: up to a sixth), less than any
claim of the shipped lessons needs."""

FigureReadouts = Callable[[Any, tuple], Mapping[str, float]]
"""(figure spec, FrameResults: A first, B while comparing) -> the figure's readouts."""


@dataclass
class FrameCache:
    """Converged frames and error measurements shared by the steps of one verification
    (consecutive steps often render the same settings): a frame by the settings it
    converged at, and for a try-this by the settings on screen before the press too
    (the press runs again only what its change invalidates); a measurement by its
    settings. A frame's arrays are its own: a later run leaves them as they were."""

    frames: dict[tuple[Any, Any], Any] = field(default_factory=dict)
    errors: dict[Any, Any] = field(default_factory=dict)


def _error_measurement():
    from explorer.truth.progressive import Measurement

    return Measurement(size=ERROR_SIZE["size"], rsm_size=ERROR_SIZE["rsm_size"],
                       reference="visible")


def measure_error(pipeline: Any, settings: Any) -> Any:
    """The Error panel's measurement of ``settings`` at :data:`ERROR_SIZE` (an
    ``explorer.truth.metrics.ErrorStats``): its LPV frame rendered by ``pipeline``, the
    reference with shadow rays, the metrics over the pixels that see a surface."""
    from explorer.truth.progressive import ErrorJob

    settings = settings.with_changes(exposure=1.0, indirect_only=False)
    job = ErrorJob(settings, _error_measurement(), settings.width / max(settings.height, 1))
    try:
        while not job.advance(pipeline.ctx, pipeline, 60.0):
            pass
        return job.result.stats
    finally:
        job.release()


# complexity: one branch per check kind, all measured on the one frame
def verify_step(pipeline: Any, step: Any, sizes: Mapping[str, int] | None = None,  # noqa: C901
                figure_readouts: FigureReadouts | None = None,
                cache: FrameCache | None = None) -> list[Outcome]:
    """Every check of ``step`` (an ``explorer.lessons.model.Step``) evaluated on converged frames
    that ``pipeline`` (an ``explorer.lpv.pipeline.Pipeline``) renders: the step as it opens,
    after a try-this, or on its compare side, each at ``sizes`` (default
    :data:`CHECK_SIZE`; None values keep the step's own). ``figure_readouts`` reads the
    step's figures (module docstring); without it a ``figure.*`` check fails saying so.
    Frames and error measurements are made only for what the checks read, and taken
    from ``cache`` when an earlier step made them (its own when None)."""
    from explorer.figure_params import FIGURE_KINDS
    from explorer.lessons.live_values import LiveContext, Unavailable, lookup
    from explorer.lessons.model import COMPARE_VIEWS

    sizes = CHECK_SIZE if sizes is None else sizes
    marks = {mark.id: mark for mark in step.marks}
    plots_frames = {decl.name for decl in FIGURE_KINDS if decl.results}
    specs = {spec.instance_id: spec for spec in step.figures}
    cache = FrameCache() if cache is None else cache
    frames: dict[tuple[int | None, str], tuple[Any, Any]] = {}
    figures: dict[tuple[int | None, str], Mapping[str, float]] = {}

    def settings_of(after_try: int | None, side: str) -> Any:
        settings = step.settings()
        if after_try is not None:
            settings = step.try_this[after_try - 1].apply(settings)
            if shrink_settings(settings, **sizes) == shrink_settings(step.settings(),
                                                                     **sizes):
                raise LookupError(f"at the check sizes {dict(sizes)} try-this "
                                  f"{after_try} changes nothing")
        if side == "compare":
            settings = settings.with_changes(corrections=step.compare)
        return shrink_settings(settings, **sizes)

    def frame(after_try: int | None, side: str) -> tuple[Any, Any]:
        key = (after_try, side)
        if key not in frames:
            settings = settings_of(after_try, side)
            before = None
            if after_try is not None:
                # as the reader does: the step on screen, then the press (the stages the
                # press runs again are those its change invalidates)
                before = step.settings()
                if side == "compare":
                    before = before.with_changes(corrections=step.compare)
                before = shrink_settings(before, **sizes)
            made = (before, settings)
            if made not in cache.frames:
                if before is not None:
                    pipeline.run(before)
                cache.frames[made] = pipeline.run(settings)   # converged, full audit
            frames[key] = (settings, cache.frames[made])
        return frames[key]

    def error(after_try: int | None, side: str) -> Any:
        settings = settings_of(after_try, side)
        if settings not in cache.errors:
            cache.errors[settings] = measure_error(pipeline, settings)
        return cache.errors[settings]

    def figure(after_try: int | None, figure_id: str) -> Mapping[str, float]:
        key = (after_try, figure_id)
        if key not in figures:
            if figure_readouts is None:
                raise LookupError("no figure readouts were handed in (figure_readouts: "
                                  "explorer.ui.figures.declared_readouts)")
            spec = specs[figure_id]
            results: tuple = ()
            if spec.kind in plots_frames:
                results = (frame(after_try, "step")[1],)
                if step.view in COMPARE_VIEWS and step.compare is not None:
                    results += (frame(after_try, "compare")[1],)
            figures[key] = dict(figure_readouts(spec, results))
        return figures[key]

    outcomes = []
    for check in step.checks:
        def read(name: str, after: bool, check: Check = check) -> Any:
            after_try = check.after_try if after else None
            source = name.split(".", 1)[0]
            if source == "figure":
                figure_id, readout = name.split(".")[1:]
                values = figure(after_try, figure_id)
                if readout not in values:
                    raise LookupError(f"the figure {figure_id!r} shows no {readout!r} (its "
                                      f"readouts: {', '.join(sorted(values)) or 'none'})")
                live = LiveContext(figures={figure_id: values})
            elif source == "derived":
                live = LiveContext()             # an exact constant: no frame needed
            else:
                settings, result = frame(after_try, check.side)
                live = LiveContext(settings=settings, result=result, marks=marks,
                                   error=error(after_try, check.side) if source == "error"
                                   else None)
            try:
                return lookup(name, step.figure_ids, step.mark_ids).value(live)
            except Unavailable as exc:
                raise LookupError(str(exc)) from None
        outcomes.append(evaluate(check, read))
    return outcomes
