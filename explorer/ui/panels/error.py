"""Error panel: configuration A against the one-bounce reference renderer.

The measurement (``explorer/truth/progressive.py``) renders A's LPV frame at a small size
(the reference costs pixels × VPLs), then the reference a few tiles per frame, then the
relative L2 error, the flux ratio and a false-colour log2 error image. It runs in the
background of the app loop (an :class:`ErrorService` in ``runtime.tasks``), is cancelled
when the settings change before it finishes, and every finished measurement is cached per
measured settings, so switching back and forth costs nothing the second time. Lessons
read the numbers through ``{{error.*}}`` placeholders.
"""

from __future__ import annotations

import time
from collections import OrderedDict
from typing import Any

import numpy as np
from imgui_bundle import imgui

from explorer.truth.progressive import (
    LOG2_SCALE,
    REFERENCE_MODES,
    ErrorJob,
    ErrorResult,
    Measurement,
    measured_settings,
)
from explorer.ui import widgets

DEBOUNCE_S = 0.4
"""A configuration must stay unchanged this long before an automatic measurement starts
(orbiting the camera would otherwise start one per frame)."""
CACHE_SIZE = 32
SIZES = (48, 64, 96, 128, 192, 256)
RSM_SIZES = (16, 32, 64, 128)


class ErrorService:
    """Measures configuration A when asked (or whenever it changes, with ``auto``)."""

    def __init__(self, state) -> None:
        self.state = state
        self.measurement = Measurement()
        self.auto = False
        """The reader asked to measure every configuration shown."""
        self.lesson_wants = False
        """The lesson step on screen shows the error (its plot is "error")."""
        self.requested: Any = None
        self.cache: OrderedDict[Any, ErrorResult] = OrderedDict()
        self.job: ErrorJob | None = None
        self.job_key: Any = None
        self.pipeline = None
        self.problem: str | None = None
        self.last: ErrorResult | None = None
        self._seen: Any = None
        self._seen_at = 0.0

    # -- what is measured ----------------------------------------------------------------
    def key(self, settings=None) -> Any:
        settings = self.state.settings if settings is None else settings
        aspect = settings.width / max(settings.height, 1)
        measured = measured_settings(settings.with_changes(exposure=1.0,
                                                           indirect_only=False),
                                     self.measurement, aspect)
        return (measured, self.measurement)

    def result_for(self, settings=None) -> ErrorResult | None:
        return self.cache.get(self.key(settings))

    @property
    def running(self) -> bool:
        return self.job is not None

    def measure(self) -> None:
        """Measure the current configuration now (the panel's button)."""
        self.requested = self.key()
        self.problem = None

    def cancel(self) -> None:
        if self.job is not None:
            self.job.release()
        self.job = self.job_key = None
        self.requested = None

    # -- the app loop's task interface -------------------------------------------------
    def advance(self, ctx, budget_s: float) -> None:
        key = self.key()
        now = time.monotonic()
        if key != self._seen:
            self._seen, self._seen_at = key, now
        if self.job is not None and self.job_key != key:
            self.cancel()                         # the settings moved on: stop
        if self.job is None:
            every = self.auto or self.lesson_wants
            wanted = key == self.requested or (every and now - self._seen_at >= DEBOUNCE_S)
            if not wanted or key in self.cache or self.problem:
                return
            settings = self.state.settings
            self.job = ErrorJob(settings.with_changes(exposure=1.0, indirect_only=False),
                                self.measurement, settings.width / max(settings.height, 1))
            self.job_key = key
        try:
            if self.pipeline is None:
                from explorer.lpv.pipeline import Pipeline

                self.pipeline = Pipeline(self.job.settings, ctx=ctx)
            done = self.job.advance(ctx, self.pipeline, budget_s)
        except Exception as exc:  # noqa: BLE001 - shown in the panel, the app goes on
            self.problem = f"{type(exc).__name__}: {exc}"
            self.cancel()
            return
        if done:
            self.cache[key] = self.last = self.job.result
            self.cache.move_to_end(key)
            while len(self.cache) > CACHE_SIZE:
                self.cache.popitem(last=False)
            self.job.release()
            self.job = self.job_key = None
            self.requested = None

    def release(self) -> None:
        self.cancel()
        if self.pipeline is not None:
            self.pipeline.release()
            self.pipeline = None


def error_service(state) -> ErrorService:
    """The state's ErrorService, made and handed to the app loop on first use."""
    rt = state.runtime
    for task in rt.tasks:
        if isinstance(task, ErrorService):
            return task
    service = ErrorService(state)
    rt.tasks.append(service)
    return service


def want_measurement(state, wanted: bool = True) -> None:
    """A lesson step shows the error (or no longer does): measure every configuration
    it shows while it is on screen."""
    error_service(state).lesson_wants = wanted


def current_stats(state):
    """ErrorStats of configuration A when measured, else None (lesson placeholders)."""
    result = error_service(state).result_for()
    return None if result is None else result.stats


# --- the panel ------------------------------------------------------------------------

def gui_error(state) -> None:
    service = error_service(state)
    result = service.result_for()
    _controls(service)
    if service.problem:
        imgui.text_colored(widgets.ERROR, service.problem)
    if result is None and service.last is not None:
        widgets.dim_text_wrapped("Not measured for the settings shown; below: the last "
                                 "measurement (other settings).")
        result = service.last
    if result is None:
        widgets.dim_text_wrapped(
            "Press Measure to compare configuration A with the one-bounce reference: "
            "the same VPLs summed at every pixel without a grid (explorer/truth).")
        return
    _numbers(result)
    _images(state, result)


def _controls(service: ErrorService) -> None:
    if service.running:
        job = service.job
        # leave room on the line for the Cancel button and the "every change" checkbox
        style = imgui.get_style()
        after = (imgui.calc_text_size("Cancel").x + 2 * style.frame_padding.x
                 + imgui.get_frame_height() + style.item_inner_spacing.x
                 + imgui.calc_text_size("every change").x + 2 * style.item_spacing.x)
        imgui.progress_bar(job.fraction, (-after, 0), f"{job.stage} {job.fraction:.0%}")
        imgui.same_line()
        if imgui.button("Cancel"):
            service.cancel()
            service.auto = service.lesson_wants = False
    elif service.result_for() is None:
        if imgui.button("Measure"):
            service.measure()
    else:
        imgui.text_colored(widgets.GOOD, "measured")
    imgui.same_line()
    changed, every = imgui.checkbox("every change", service.auto or service.lesson_wants)
    if changed:
        service.auto, service.lesson_wants = every, False
    if imgui.is_item_hovered():
        imgui.set_tooltip("measure each configuration shown, once it has stayed unchanged "
                          f"for {DEBOUNCE_S:g} s; results are cached per settings"
                          + ("\n(on while the lesson step shows the error)"
                             if service.lesson_wants and not service.auto else ""))
    m = service.measurement
    imgui.set_next_item_width(70)
    changed_size, size = widgets.combo("px", str(m.size), [str(v) for v in SIZES])
    imgui.same_line()
    imgui.set_next_item_width(60)
    changed_rsm, rsm = widgets.combo("RSM", str(m.rsm_size), [str(v) for v in RSM_SIZES])
    imgui.same_line()
    imgui.set_next_item_width(100)
    changed_ref, reference = widgets.combo("reference", m.reference, REFERENCE_MODES)
    if changed_size or changed_rsm or changed_ref:
        service.measurement = Measurement(int(size), int(rsm), reference)
        service.problem = None
    if imgui.is_item_hovered():
        imgui.set_tooltip("visible: a shadow ray for every VPL and pixel; unoccluded: no "
                          "visibility, what an LPV without a geometry volume approximates")


def _numbers(result: ErrorResult) -> None:
    stats = result.stats
    s, m = result.settings, result.measurement
    imgui.text("relative L2")
    imgui.same_line()
    imgui.text_colored(widgets.ACCENT, f"{stats.relative_l2:.3f}")
    imgui.same_line(0, 18)
    imgui.text("flux ratio LPV/ref")
    imgui.same_line()
    imgui.text_colored(widgets.ACCENT, f"{stats.flux_ratio:.3f}")
    imgui.text_disabled("flux ratio per channel (r, g, b): "
                        + ", ".join(f"{v:.2f}" for v in stats.flux_ratio_rgb))
    widgets.dim_text_wrapped(
        f"{s.width}×{s.height} px, RSM {s.rsm_size}², {m.reference} reference, "
        f"{stats.pixels} pixels see a surface; indirect light only (no exposure).")


def _images(state, result: ErrorResult) -> None:
    from explorer.ui.textures import robust_max, tonemap

    rt = state.runtime
    exposure = 1.0 / robust_max(result.reference[result.valid], 99.0)
    version = id(result)
    pictures = (("LPV", tonemap(result.lpv, exposure)),
                ("reference", tonemap(result.reference, exposure)),
                ("log2(LPV / reference)", np.asarray(result.error.rgb, np.float32)))
    avail = imgui.get_content_region_avail()
    bar = 70.0
    height_px, width_px = result.lpv.shape[:2]
    side = max(min((avail.x - bar - 16) / 3.0, (avail.y - 40) * width_px / height_px), 24.0)
    size = imgui.ImVec2(side, side * height_px / width_px)
    for index, (title, image) in enumerate(pictures):
        if index:
            imgui.same_line()
        imgui.begin_group()
        imgui.text_disabled(title)
        tex = rt.textures.upload(f"error-{index}", image, version=version)
        pos = imgui.get_cursor_screen_pos()
        imgui.image(imgui.ImTextureRef(tex), size)
        imgui.end_group()
    _stops_bar(imgui.ImVec2(pos.x + size.x + 6, pos.y), size.y)
    imgui.dummy((bar, 1))
    widgets.dim_text_wrapped("Blue: the LPV is darker than the reference, red: brighter; "
                             f"saturates at ±{LOG2_SCALE:g} stops. Grey: background.")


def _stops_bar(pos, height: float, width: float = 14.0) -> None:
    """The error image's colour scale (metrics.diverging_colormap), labelled in stops."""
    from explorer.truth.metrics import diverging_colormap

    draw = imgui.get_window_draw_list()
    values = np.linspace(LOG2_SCALE, -LOG2_SCALE, 25)
    colours = diverging_colormap(values, LOG2_SCALE)
    step = height / (len(values) - 1)
    for i in range(len(values) - 1):
        top, bottom = (imgui.get_color_u32(imgui.ImVec4(*map(float, c), 1.0))
                       for c in (colours[i], colours[i + 1]))
        draw.add_rect_filled_multi_color((pos.x, pos.y + i * step),
                                         (pos.x + width, pos.y + (i + 1) * step),
                                         top, top, bottom, bottom)
    white = imgui.get_color_u32(imgui.ImVec4(1, 1, 1, 0.9))
    for stops in (LOG2_SCALE, 0.0, -LOG2_SCALE):
        y = pos.y + (LOG2_SCALE - stops) / (2 * LOG2_SCALE) * height
        draw.add_text((pos.x + width + 4, min(max(y - 7, pos.y), pos.y + height - 14)), white,
                      f"{stops:+g}" if stops else "0")
