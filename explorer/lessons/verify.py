"""Verifying a lesson step's checks (:mod:`explorer.lessons.checks`) on the converged
frames of that step, rendered headless: what CI runs for every checked step
(tests/lessons/test_lesson_checks.py) and ``lpv-explorer lessons --check``. Apart from
the checks module, which the reader uses to read the checks, since this renders (at the
sizes of :func:`explorer.lessons.render.shrink_settings`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from explorer.lessons.checks import Check, Outcome, evaluate
from explorer.lessons.render import shrink_settings

CHECK_SIZE = {"size": 64, "max_grid": 48, "rsm_size": 64, "max_iterations": 64}
"""The sizes CI verifies the checks at (``shrink_settings``): small enough to
run every checked step in seconds on llvmpipe, large enough that every claim of the
shipped lessons holds there as it does at the steps' own sizes."""


def verify_step(pipeline: Any, step: Any, sizes: Mapping[str, int] | None = None
                ) -> list[Outcome]:
    """Every check of ``step`` (an ``explorer.lessons.model.Step``) evaluated on converged frames
    that ``pipeline`` (an ``explorer.lpv.pipeline.Pipeline``) renders: the step as it opens,
    after a try-this, or on its compare side, each at ``sizes`` (default
    :data:`CHECK_SIZE`; None values keep the step's own)."""
    from explorer.lessons.live_values import LiveContext, Unavailable, lookup

    sizes = CHECK_SIZE if sizes is None else sizes
    marks = {mark.id: mark for mark in step.marks}
    contexts: dict[tuple[int | None, str], LiveContext] = {}

    def context(after_try: int | None, side: str) -> LiveContext:
        key = (after_try, side)
        if key not in contexts:
            settings = step.settings()
            if after_try is not None:
                settings = step.try_this[after_try - 1].apply(settings)
                if shrink_settings(settings, **sizes) == shrink_settings(step.settings(),
                                                                         **sizes):
                    raise LookupError(f"at the check sizes {dict(sizes)} try-this "
                                      f"{after_try} changes nothing")
            if side == "compare":
                settings = settings.with_changes(corrections=step.compare)
            settings = shrink_settings(settings, **sizes)
            if after_try is not None:
                # as the reader does: the step on screen, then the press (the stages the
                # press runs again are those its change invalidates)
                before = step.settings()
                if side == "compare":
                    before = before.with_changes(corrections=step.compare)
                pipeline.run(shrink_settings(before, **sizes))
            result = pipeline.run(settings)     # to convergence, with the full audit
            contexts[key] = LiveContext(settings=settings, result=result, marks=marks)
        return contexts[key]

    outcomes = []
    for check in step.checks:
        def read(name: str, after: bool, check: Check = check) -> Any:
            live = context(check.after_try if after else None, check.side)
            try:
                return lookup(name, (), step.mark_ids).value(live)
            except Unavailable as exc:
                raise LookupError(str(exc)) from None
        outcomes.append(evaluate(check, read))
    return outcomes
