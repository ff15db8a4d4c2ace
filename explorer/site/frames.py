"""The pictures of a step, rendered headlessly (EGL) at build time, as the window shows
them: the step's view buffer with its camera (``Step.settings``) and the in-scene
overlays its ``[steps.show]`` sets, drawn by the window's own compositor
(explorer/ui/overlays/compositor.py) over the frame; split and difference views as the
View panel composes them; the Inspect panel's image for RSM and grid views; and the
error measurement against the one-bounce reference (the Error panel's ErrorJob) for a
step that quotes ``{{error.*}}``.

Every picture comes from a converged frame (``Pipeline.run``: the whole job), so the
numbers baked from its result are the ones the window shows once the frame has settled.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from explorer.lessons import COMPARE_VIEWS, Step
from explorer.lessons import text as lesson_text
from explorer.lpv.settings import Settings

MAIN_VIEW_BUFFERS = ("final", "direct", "indirect", "albedo")
"""Step views the main view shows itself (the others go to the Inspect panel, the main
view then shows the final image), as explorer/ui/lesson_panel.py ``step_screen``."""
MIN_INSPECT_SIZE = 256
"""Inspect images (a 16² grid slice, a 32² RSM) are enlarged by whole pixels to this."""
ERROR_BUDGET_S = 30.0


@dataclass(frozen=True)
class Screen:
    """What one picture shows: configuration A, how it is viewed, B when comparing."""

    settings: Settings
    mode: str = "single"
    """single | split | difference."""
    compare: Settings | None = None


@dataclass
class Shot:
    """A rendered picture and the frame it was made from."""

    image: np.ndarray
    """(H, W, 3) uint8, top row first."""
    result: Any
    """Configuration A's FrameResult (what the live numbers read)."""
    settings: Settings
    inspect: np.ndarray | None = None
    """The Inspect panel's image for RSM and grid views (uint8), else None."""
    error: Any = None
    """What ``{{error.*}}`` reads (an ErrorReadout: the ErrorStats against the one-bounce
    reference, and against Mitsuba when asked for), when measured."""
    compare_result: Any = None
    """Configuration B's FrameResult of a split or difference view."""
    error_result: Any = None
    """The whole measurement (``explorer.truth.progressive.ErrorResult``: the LPV's and
    the reference's indirect light, the false-colour error), when measured."""


def step_screen(step: Step) -> Screen:
    """The step as it opens (explorer/ui/lesson_panel.py ``step_screen``)."""
    settings = step.settings()
    if step.view in COMPARE_VIEWS:
        return Screen(settings, step.view, step.compare_settings())
    return Screen(settings)


def try_screen(step: Step, index: int) -> Screen:
    """Configuration A of the step with its ``index``-th (1-based) try-this pressed,
    shown whole: the page's swipe puts it against the step's configuration A (the
    window's before | after split), so neither side is itself a split view."""
    item = step.try_this[index - 1]
    return Screen(item.apply(step.settings()))


def uses_error(texts: list[str]) -> bool:
    return any(name.startswith("error.") for text in texts
               for name, _ in lesson_text.placeholders(text))


def uses_truth(texts: list[str]) -> bool:
    """The texts quote numbers against Mitsuba (the Error panel's "reference + Mitsuba")."""
    return any(name.startswith(("error.mitsuba_", "error.reference_mitsuba_"))
               for text in texts for name, _ in lesson_text.placeholders(text))


def to_bytes(image: np.ndarray) -> np.ndarray:
    return (np.clip(np.nan_to_num(image), 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)


def enlarge(image: np.ndarray, size: int = MIN_INSPECT_SIZE) -> np.ndarray:
    repeat = max(1, -(-size // max(image.shape[:2])))
    return image.repeat(repeat, axis=0).repeat(repeat, axis=1) if repeat > 1 else image


class FrameRenderer:
    """One headless context, the pipeline and the overlay compositor, kept for a whole
    build so each shader compiles once and unchanged stages are not run again."""

    def __init__(self, width: int, height: int) -> None:
        from explorer.gl.context import create_headless_context

        self.width, self.height = int(width), int(height)
        self.ctx = create_headless_context()
        self.renderer = self.ctx.info.get("GL_RENDERER", "")
        self._pipeline = None
        self._error_pipeline = None
        self._compositor = None
        self.problems: list[str] = []
        """What could not be measured (Mitsuba missing), for the build's report."""

    def sized(self, settings: Settings) -> Settings:
        return settings.with_changes(width=self.width, height=self.height)

    @property
    def pipeline(self):
        return self._pipeline

    def _run(self, settings: Settings, keep_steps: bool):
        from explorer.lpv.pipeline import Pipeline

        if self._pipeline is None:
            self._pipeline = Pipeline(settings, ctx=self.ctx)
        return self._pipeline.run(settings, keep_steps=keep_steps, need_audit="full")

    def shot(self, screen: Screen, view: str, overlays, want_error: bool = False,
             want_truth: bool = False) -> Shot:
        """The picture of ``screen`` with ``view`` (the step's view name) and
        ``overlays`` (an OverlayState)."""
        settings = self.sized(screen.settings)
        buffer = view if view in MAIN_VIEW_BUFFERS else "final"
        keep = bool(overlays.needs_steps)
        result = self._run(settings, keep)
        pipeline = self._pipeline
        mine = self._composed("A", result, pipeline.view(buffer), overlays)
        inspect = None
        if view not in MAIN_VIEW_BUFFERS and view not in COMPARE_VIEWS:
            inspect = enlarge(to_bytes(pipeline.view(view)))
        image, other = mine, None
        if screen.mode in COMPARE_VIEWS and screen.compare is not None:
            mine_linear = np.array(result.final_image, copy=True)
            other_settings = self.sized(screen.compare)
            other = self._run(other_settings, keep)
            if screen.mode == "split":
                theirs = self._composed("B", other, pipeline.view(
                    "final", display_scale=result.display_scale), overlays)
                image = np.array(mine, copy=True)
                half = image.shape[1] // 2
                image[:, half:] = theirs[:, half:]
                image[:, half] = 255                    # the divider
            else:
                from explorer.lpv.twin.tonemap import linear_to_srgb

                difference = np.abs(mine_linear - other.final_image)
                scale = float(difference.max())
                image = to_bytes(linear_to_srgb(difference / scale) if scale > 0
                                 else np.zeros_like(difference))
        measured = self.error(screen.settings) if want_error or want_truth else None
        readout = None
        if measured is not None:
            from explorer.truth.mitsuba_job import ErrorReadout

            readout = ErrorReadout(measured.stats, self.truth(measured) if want_truth else None)
        return Shot(image, result, settings, inspect, readout, other, measured)

    def _composed(self, side: str, result, display: np.ndarray, overlays) -> np.ndarray:
        """``display`` with the overlays drawn in the scene (the View panel's
        compositor), as uint8."""
        pixels = to_bytes(display)
        if not overlays.any_shown or result.gbuffer_position is None:
            return pixels
        from explorer.ui.overlays.compositor import Compositor

        if self._compositor is None:
            self._compositor = Compositor(self.ctx)
        height, width = pixels.shape[:2]
        rgba = np.concatenate([pixels, np.full((height, width, 1), 255, np.uint8)], axis=2)
        texture = self.ctx.texture((width, height), 4, rgba.tobytes(), dtype="f1")
        try:
            self._compositor.compose(side, result, texture.glo, True, overlays)
            return self._compositor.read(side)
        finally:
            self._compositor.forget_base(texture.glo)
            texture.release()

    def error(self, settings: Settings):
        """The Error panel's measurement of ``settings`` (its ErrorResult): the LPV and
        the visible one-bounce reference at the panel's default Measurement, the image's
        aspect kept."""
        from explorer.lpv.pipeline import Pipeline
        from explorer.truth.progressive import ErrorJob, Measurement

        settings = self.sized(settings).with_changes(exposure=1.0, indirect_only=False)
        job = ErrorJob(settings, Measurement(), settings.width / max(settings.height, 1))
        if self._error_pipeline is None:
            self._error_pipeline = Pipeline(job.settings, ctx=self.ctx)
        try:
            while not job.advance(self.ctx, self._error_pipeline, ERROR_BUDGET_S):
                pass
            return job.result
        finally:
            job.release()

    def truth(self, measured):
        """The Error panel's measurement held against Mitsuba (its TruthStats: the same
        pixels rendered by Mitsuba 3, one bounce and all bounces), or None when Mitsuba
        cannot render (not installed): the numbers then stay "…" and the build says
        why."""
        from explorer.truth.gbuffer import scene_for
        from explorer.truth.mitsuba_job import MitsubaJob, TruthStats
        from explorer.ui.panels.error import MITSUBA_SPP

        s = measured.settings
        try:
            job = MitsubaJob(scene_for(s, getattr(self._error_pipeline, "base_scene", None)),
                             s.width, s.height, MITSUBA_SPP)
        except Exception as exc:  # noqa: BLE001 - Mitsuba missing or refusing the scene
            self.problems.append(f"Mitsuba: {type(exc).__name__}: {exc}")
            return None
        try:
            while not job.poll():
                time.sleep(0.2)
            if job.problem:
                self.problems.append(f"Mitsuba: {job.problem}")
                return None
            return TruthStats(measured.lpv, measured.reference, measured.valid, job.result)
        finally:
            job.release()

    def release(self) -> None:
        for owned in (self._compositor, self._pipeline, self._error_pipeline):
            if owned is not None:
                owned.release()
        self._compositor = self._pipeline = self._error_pipeline = None
        from explorer.gl.context import release_headless_context

        release_headless_context(self.ctx)
