"""Error panel: configuration A against the one-bounce reference renderer.

The measurement (``explorer/truth/progressive.py``) renders A's LPV frame at a small size
(the reference costs pixels × VPLs), then the reference a few tiles per frame, then the
relative L2 error, the flux ratio and a false-colour log2 error image. It runs in the
background of the app loop (an :class:`ErrorService` in ``runtime.services.tasks``), is cancelled
when the settings change before it finishes, and every finished measurement is cached per
measured settings, so switching back and forth costs nothing the second time. Lessons
read the numbers through ``{{error.*}}`` placeholders.

With the truth set to *reference + Mitsuba* (Mitsuba 3 installed), each finished
measurement is also rendered by Mitsuba in a child process (explorer/truth/mitsuba_job.py)
at the same pixels, and the LPV and the reference are held against its one bounce and
all bounces (``{{error.mitsuba_*}}``, ``{{error.reference_mitsuba_*}}``); a change of
the settings ends that render like the reference's.
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
from explorer.ui.kept_answers import KeptAnswers

TRUTHS = ("reference", "reference + Mitsuba")
MITSUBA_SPP = 64
"""Mitsuba's samples per pixel per seed in the panel (noise about 0.1 relative L2 at
128² on the Cornell box, well below the LPV's error; flux noise below 1 %)."""
DEBOUNCE_S = 0.4
"""A configuration must stay unchanged this long before an automatic measurement starts
(orbiting the camera would otherwise start one per frame)."""
CACHE_SIZE = 32
PIPELINE_IDLE_S = 20.0
"""Seconds the measuring pipeline stays made after its last measurement (as the
controller's idle sides): at the grid shown it holds a frame's GPU grids and arrays,
hundreds of MiB at 64³ with two cascades, which a reader who moved on does not need."""
SIZES = (48, 64, 96, 128, 192, 256)
RSM_SIZES = (16, 32, 64, 128)
KEYS_KEPT = 64
"""Configurations whose measurement key :meth:`ErrorService.key` keeps."""


class ErrorService:
    """Measures configuration A when asked (or whenever it changes, with ``auto``)."""

    def __init__(self, state) -> None:
        self.state = state
        self.measurement = Measurement()
        self.auto = False
        """The reader asked to measure every configuration shown."""
        self.lesson_wants = False
        self.enlarged = False
        """The reader clicked an image: the three are drawn large in a window of their own."""
        """The lesson step on screen shows the error (its plot is "error")."""
        self.requested: Any = None
        self.cache: OrderedDict[Any, ErrorResult] = OrderedDict()
        self.job: ErrorJob | None = None
        self.job_key: Any = None
        self.pipeline = None
        self.problem: str | None = None
        self.last: ErrorResult | None = None
        self.truth = TRUTHS[0]
        self.lesson_truth = False
        """The lesson step on screen quotes ``{{error.mitsuba_*}}``: measure against
        Mitsuba (when installed) while it shows, whatever the combo says."""
        self.truths: OrderedDict[Any, Any] = OrderedDict()
        """key -> TruthStats (explorer/truth/mitsuba_job.py) of a finished measurement."""
        self.truth_job = None
        self.truth_key: Any = None
        self.truth_problem: str | None = None
        self._keys = KeptAnswers(most=KEYS_KEPT)
        """:meth:`key`'s recent answers, by the settings they were made of."""
        self._seen: Any = None
        self._seen_at = 0.0
        self._idle_since: float | None = None
        """When the pipeline last finished or stopped a measurement (None: none made)."""
        self.idle_release_s = PIPELINE_IDLE_S
        """How long the idle pipeline stays made (the soak sets 0 for a frame, as it does
        the controller's ``idle_release_s``, so that its GL counts do not depend on how
        long a step took)."""

    # -- what is measured ----------------------------------------------------------------
    def key(self, settings=None) -> Any:
        """What a measurement of ``settings`` (default: A's) is cached by: the settings as
        measured and the measurement. The window asks every frame for the same few
        configurations (A, each try-this's): the key of each is kept while the settings
        object and the measurement are the same ones (both frozen), not copied again."""
        settings = self.state.settings if settings is None else settings
        measurement = self.measurement
        return self._keys.answer(id(settings), (settings, measurement),
                                 lambda: self._measured_key(settings, measurement))

    @staticmethod
    def _measured_key(settings, measurement: Measurement) -> Any:
        aspect = settings.width / max(settings.height, 1)
        measured = measured_settings(settings.with_changes(exposure=1.0,
                                                           indirect_only=False),
                                     measurement, aspect)
        return (measured, measurement)

    def result_for(self, settings=None) -> ErrorResult | None:
        return self.cache.get(self.key(settings))

    @property
    def running(self) -> bool:
        return self.job is not None

    def measure(self) -> None:
        """Measure the current configuration now (the panel's button)."""
        self.requested = self.key()
        self.problem = None

    def truth_for(self, settings=None):
        """TruthStats of the configuration shown, when Mitsuba has measured it."""
        return self.truths.get(self.key(settings))

    def cancel(self) -> None:
        if self.job is not None:
            self.job.release()
        self.job = self.job_key = None
        self.requested = None
        self.cancel_truth()

    def cancel_truth(self) -> None:
        if self.truth_job is not None:
            self.truth_job.release()
        self.truth_job = self.truth_key = None

    @property
    def against_mitsuba(self) -> bool:
        """Measurements are held against Mitsuba (the combo, or the lesson step asks and
        Mitsuba is installed)."""
        if self.truth != TRUTHS[0]:
            return True
        if not self.lesson_truth:
            return False
        from explorer.truth.mitsuba_render import mitsuba_available

        return mitsuba_available() is None

    def _advance_truth(self, key: Any) -> None:
        """Start, poll or end Mitsuba's render of the measurement of ``key``."""
        wanted = self.against_mitsuba
        if self.truth_job is not None and (self.truth_key != key or not wanted):
            self.cancel_truth()                   # the settings moved on: stop
        result = self.cache.get(key)
        if not wanted or result is None or key in self.truths or self.truth_problem:
            return
        from explorer.truth.mitsuba_job import MitsubaJob, TruthStats

        if self.truth_job is None:
            from explorer.truth.gbuffer import scene_for

            s = result.settings
            self.truth_job = MitsubaJob(scene_for(s, getattr(self.pipeline, "base_scene",
                                                             None)),
                                        s.width, s.height, MITSUBA_SPP)
            self.truth_key = key
        if not self.truth_job.poll():
            return
        if self.truth_job.problem:
            self.truth_problem = f"Mitsuba: {self.truth_job.problem}"
        else:
            self.truths[key] = TruthStats(result.lpv, result.reference, result.valid,
                                          self.truth_job.result)
            while len(self.truths) > CACHE_SIZE:
                self.truths.popitem(last=False)
        self.truth_job = self.truth_key = None

    # -- the app loop's task interface -------------------------------------------------
    def advance(self, ctx, budget_s: float) -> None:
        key = self.key()
        now = time.monotonic()
        if key != self._seen:
            self._seen, self._seen_at = key, now
        if self.job is not None and self.job_key != key:
            self.cancel()                         # the settings moved on: stop
        try:
            self._advance_truth(key)
        except Exception as exc:  # noqa: BLE001 - shown in the panel, the app goes on
            self.truth_problem = f"Mitsuba: {type(exc).__name__}: {exc}"
            self.cancel_truth()
        if self.job is None:
            every = self.auto or self.lesson_wants
            wanted = key == self.requested or (every and now - self._seen_at >= DEBOUNCE_S)
            if not wanted or key in self.cache or self.problem:
                self._release_idle_pipeline(now)
                return
            settings = self.state.settings
            self.job = ErrorJob(settings.with_changes(exposure=1.0, indirect_only=False),
                                self.measurement, settings.width / max(settings.height, 1))
            self.job_key = key
            self._idle_since = None
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

    def _release_idle_pipeline(self, now: float) -> None:
        """Release the measuring pipeline ``idle_release_s`` (:data:`PIPELINE_IDLE_S`)
        after its last measurement (the next one makes a new one)."""
        if self.pipeline is None or self.truth_job is not None:
            self._idle_since = None
            return
        if self._idle_since is None:
            self._idle_since = now
        if now - self._idle_since >= self.idle_release_s:
            self.pipeline.release()
            self.pipeline, self._idle_since = None, None

    def release(self) -> None:
        self.cancel()
        if self.pipeline is not None:
            self.pipeline.release()
            self.pipeline = None


def error_service(state) -> ErrorService:
    """The state's ErrorService, made and handed to the app loop on first use."""
    rt = state.runtime
    for task in rt.services.tasks:
        if isinstance(task, ErrorService):
            return task
    service = ErrorService(state)
    rt.services.tasks.append(service)
    return service


def want_measurement(state, wanted: bool = True) -> None:
    """A lesson step shows the error (or no longer does): measure every configuration
    it shows while it is on screen. A new step drops the previous one's wish for Mitsuba
    (:func:`want_truth`)."""
    service = error_service(state)
    service.lesson_wants = wanted
    service.lesson_truth = False


def want_truth(state) -> None:
    """The lesson step on screen quotes Mitsuba's numbers: measure against Mitsuba too."""
    error_service(state).lesson_truth = True


def current_stats(state):
    """An :class:`ErrorReadout` of configuration A when measured, else None (lesson
    placeholders)."""
    service = error_service(state)
    from explorer.truth.mitsuba_job import ErrorReadout

    result = service.result_for()
    return None if result is None else ErrorReadout(result.stats, service.truth_for())


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
            "the same VPLs summed at every pixel without a grid.")
        return
    _numbers(result)
    _truth(service)
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
    # the third combo wraps in the narrow tool column (1280 px window)
    widgets.same_line_if_fits("reference", field=100 + imgui.get_style().item_inner_spacing.x)
    imgui.set_next_item_width(100)
    changed_ref, reference = widgets.combo("reference", m.reference, REFERENCE_MODES)
    if changed_size or changed_rsm or changed_ref:
        service.measurement = Measurement(int(size), int(rsm), reference)
        service.problem = None
    if imgui.is_item_hovered():
        imgui.set_tooltip("visible: a shadow ray for every VPL and pixel; unoccluded: no "
                          "visibility, what an LPV without a geometry volume approximates")
    _truth_controls(service)


def _truth_controls(service: ErrorService) -> None:
    """The truth combo (Mitsuba only when installed) and the Mitsuba render's progress."""
    from explorer.truth.mitsuba_render import mitsuba_available

    missing = mitsuba_available()
    imgui.set_next_item_width(170)
    imgui.begin_disabled(missing is not None)
    shown = TRUTHS[1] if service.against_mitsuba else service.truth
    changed, truth = widgets.combo("truth", shown, TRUTHS)
    imgui.end_disabled()
    if changed:
        service.truth, service.truth_problem = truth, None
        service.lesson_truth = False
    if imgui.is_item_hovered(imgui.HoveredFlags_.allow_when_disabled):
        imgui.set_tooltip(missing or "also render the measured frame with Mitsuba 3 (a "
                          f"physically based path tracer, {MITSUBA_SPP} spp × 2 seeds, in "
                          "the background) and hold the LPV and the reference against its "
                          "one bounce and all bounces")
    job = service.truth_job
    if job is not None:
        imgui.same_line()
        imgui.progress_bar(job.fraction, (-1, 0), f"Mitsuba {job.fraction:.0%}")
    if service.truth_problem:
        imgui.text_colored(widgets.ERROR, service.truth_problem)


def _truth(service: ErrorService) -> None:
    truth = service.truth_for()
    if truth is None:
        return
    one, multi, ref = truth.one_bounce, truth.multi_bounce, truth.reference
    imgui.text("Mitsuba 1 bounce: flux")
    imgui.same_line()
    imgui.text_colored(widgets.ACCENT, f"{one.flux_ratio:.3f}")
    imgui.same_line()
    imgui.text(f"rel. L2 {one.relative_l2:.3f}")
    widgets.dim_text_wrapped("per channel (r, g, b): "
                             + ", ".join(f"{v:.2f}" for v in one.flux_ratio_rgb)
                             + f"; all bounces: flux ratio {multi.flux_ratio:.3f}")
    widgets.dim_text_wrapped(
        f"The reference itself against Mitsuba's one bounce: flux ratio "
        f"{ref.flux_ratio:.3f}, relative L2 {ref.relative_l2:.3f} (Mitsuba's noise "
        f"{truth.noise[0]:.3f}): what the RSM's sampling costs; the rest of the LPV's "
        f"error is the grid's.")


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


IMAGE_MIN_PX = 128.0
"""The Error panel's images are at least this wide where the panel allows: three in a row,
else the LPV and the reference side by side with the error image under them."""
BAR_PX = 40.0
"""Room right of the error image for its colour scale and its labels."""
IMAGE_GAP_PX = 8.0
ENLARGED_SHARE = 0.9
"""The enlarged view covers this share of the window."""


def image_layout(avail: float, width_px: int, height_px: int) -> tuple[int, float]:
    """(images per row, width of each) of the Error panel's three images in a panel
    ``avail`` pixels wide: a row of three when each is :data:`IMAGE_MIN_PX` wide or more,
    else two rows (LPV | reference, then the error image), else one a row."""
    three = (avail - BAR_PX - 2 * IMAGE_GAP_PX) / 3.0
    if three >= IMAGE_MIN_PX:
        return 3, three
    two = (avail - IMAGE_GAP_PX) / 2.0
    if two >= IMAGE_MIN_PX and two + BAR_PX <= avail:
        return 2, two
    return 1, max(avail - BAR_PX, 24.0)


def enlarged_layout(window_w: float, window_h: float, width_px: int, height_px: int,
                    line_px: float = 24.0) -> float:
    """The width of each image of the enlarged view in a window ``window_w`` × ``window_h``:
    the three side by side, as large as :data:`ENLARGED_SHARE` of the window holds (the
    title bar, a line of titles above and two of text under them, ``line_px`` each; the
    colour scale right)."""
    room_w = ENLARGED_SHARE * window_w - BAR_PX - 4 * IMAGE_GAP_PX
    room_h = ENLARGED_SHARE * window_h - 5 * line_px
    return max(min(room_w / 3.0, room_h * width_px / height_px), 24.0)


def _pictures(state, result: ErrorResult):
    from explorer.ui.textures import robust_max, tonemap

    textures = state.runtime.services.textures
    exposure = 1.0 / robust_max(result.reference[result.valid], 99.0)
    version = id(result)
    pictures = (("LPV", tonemap(result.lpv, exposure)),
                ("reference", tonemap(result.reference, exposure)),
                ("log2(LPV / reference)", np.asarray(result.error.rgb, np.float32)))
    return [(title, textures.upload(f"error-{index}", image, version=version))
            for index, (title, image) in enumerate(pictures)]


def _images(state, result: ErrorResult) -> None:
    service = error_service(state)
    height_px, width_px = result.lpv.shape[:2]
    per_row, side = image_layout(imgui.get_content_region_avail().x, width_px, height_px)
    size = imgui.ImVec2(side, side * height_px / width_px)
    for index, (title, tex) in enumerate(_pictures(state, result)):
        if index % per_row:
            imgui.same_line(0.0, IMAGE_GAP_PX)
        pos = _titled_image(title, tex, size)
        if imgui.is_item_hovered():
            imgui.set_mouse_cursor(imgui.MouseCursor_.hand)
            imgui.set_tooltip("click to enlarge")
            if imgui.is_mouse_clicked(0):
                service.enlarged = True
    _stops_bar(imgui.ImVec2(pos.x + size.x + 6, pos.y), size.y)
    widgets.dim_text_wrapped("Blue: the LPV is darker than the reference, red: brighter; "
                             f"saturates at ±{LOG2_SCALE:g} stops. Grey: background. "
                             "Click an image to enlarge it.")
    if service.enlarged:
        _enlarged(state, service, result)


def _titled_image(title: str, tex, size) -> imgui.ImVec2:
    """One error image under its title, as one item (hover and click test the pair); the
    image's top-left corner, where the stops bar lines up."""
    imgui.begin_group()
    imgui.text_disabled(title)
    pos = imgui.get_cursor_screen_pos()
    imgui.image(imgui.ImTextureRef(tex), size)
    imgui.end_group()
    return pos


def _enlarged(state, service: ErrorService, result: ErrorResult) -> None:
    """The three images side by side in a window of their own, as large as the window
    allows; closed by its button, Escape or a click on an image."""
    viewport = imgui.get_main_viewport()
    width, height = viewport.work_size.x, viewport.work_size.y
    height_px, width_px = result.lpv.shape[:2]
    side = enlarged_layout(width, height, width_px, height_px, imgui.get_frame_height())
    size = imgui.ImVec2(side, side * height_px / width_px)
    imgui.set_next_window_pos((viewport.work_pos.x + width / 2, viewport.work_pos.y
                               + height / 2), imgui.Cond_.always, (0.5, 0.5))
    style, line = imgui.get_style(), imgui.get_frame_height()
    # sized from the first frame (an auto-sized window measures itself one frame late)
    imgui.set_next_window_size((3 * side + 2 * IMAGE_GAP_PX + BAR_PX + 2 * style.window_padding.x,
                                size.y + 4 * line + 2 * style.window_padding.y),
                               imgui.Cond_.always)
    imgui.set_next_window_focus()
    flags = (imgui.WindowFlags_.no_docking | imgui.WindowFlags_.no_collapse
             | imgui.WindowFlags_.no_resize | imgui.WindowFlags_.no_saved_settings)
    expanded, still_open = imgui.begin("Error images##enlarged", True, flags)
    if expanded:
        for index, (title, tex) in enumerate(_pictures(state, result)):
            if index:
                imgui.same_line(0.0, IMAGE_GAP_PX)
            pos = _titled_image(title, tex, size)
            if imgui.is_item_hovered() and imgui.is_mouse_clicked(0):
                still_open = False
        _stops_bar(imgui.ImVec2(pos.x + size.x + 6, pos.y), size.y)
        imgui.dummy((BAR_PX, 1))
        widgets.dim_text_wrapped("Blue: the LPV is darker than the reference, red: "
                                 f"brighter; saturates at ±{LOG2_SCALE:g} stops. Close: "
                                 "Escape, or click an image.")
    imgui.end()
    if not still_open or imgui.is_key_pressed(imgui.Key.escape, False):
        service.enlarged = False


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
