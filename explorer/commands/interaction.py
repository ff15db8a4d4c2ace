"""The interaction benchmark's driver: a real explorer window taken through a scripted
session, run as a script in a child process (``lpv-explorer bench --interactive`` starts
it and reads its JSON). It only uses what every version of the window has (``App``,
``app.frame()``, ``app.state.settings``, ``set_corrections``, ``update``, the runtime's
result and view rectangle, imgui mouse events), so the same driver measures an older
checkout too (``--root``); what only the responsive window offers (its pictures, its
per-frame work log) is read when present.

The session: launch, converge, idle, orbit N frames by dragging the mouse
over the view, an exposure sweep, each correction toggled, a slider dragged (the light's
flux) and an object moved over a few frames, the grid at 64³. Times are
wall-clock on this machine, to be compared only with another run on the same machine.

Soak (``--soak MINUTES``): what a user does, pass after pass through the course: every
lesson's every step opened in turn (and its first try-this pressed and undone), then by
the step's place in the course a correction toggled, the grid size one of 8, 16, 32, 48,
64, one or two cascades, the single, split or difference view and one of the four
buffers, a click in the view (a picked pixel), the Error panel measuring (every fifth
step), a camera move. Every pass repeats the first one exactly, and the first one starts
after the course's last step as the later ones do. The first pass is the warm-up (it
typesets the course's formulas and compiles the programs its settings need); passes
follow for MINUTES after it, at least one whole pass. Resident memory and the GL
objects alive of each kind are sampled every minute and after every step (the GL objects
once the sides not on screen are given back, :func:`release_unshown_sides`).

The growth rule (:func:`growth`), after the warm-up, the same for GL objects and for
resident memory: at the end of each pass no kind of GL object above the warm-up pass's
end and resident memory not above it by more than :data:`SOAK_RSS_SLACK` (the same step
after the same course: what the caches keep is made by then), and from the third pass on
no count above the highest of its kind after any step of the second pass, nor resident
memory above the second pass's peak by more than the slack. (The second pass's count after
the same step is no bound: the program caches keep the 48 programs got last, and which
ones those are after a step differs by one or two between the second pass and the later
ones, which agree with each other; a count that grows from pass to pass passes the second
pass's highest, and its end. Nor is the warm-up's peak a bound for the later passes: a
step early in the course holds, from the second pass on, what the caches filled with
over the whole course, the programs of every cache (2.5 MiB each on llvmpipe,
scripts/program_memory.py), llvmpipe's state of every variant compiled, the kept frames
and figures; BENCHMARKS.md "What the second pass holds that the first did not".)
Resident memory above :data:`SOAK_RSS_BUDGET_MIB` after any step, the warm-up's
included, is reported apart (:func:`over_budget`).
"""

from __future__ import annotations

import argparse
import ctypes
import inspect
import json
import os
import statistics
import sys
import time

LIT_LEVEL = 100
"""A view pixel with a channel above this is lit (the dark background is about 25)."""
LIT_SHARE = 0.05
SETTLE_LIMIT_S = 120.0
INTERACTING_S = 0.15
"""A frame that starts within this of an input counts as one while the user interacts
(the window's quiet budget begins after as long without input)."""
IDLE_S = 3.0
DRAG_PIXELS = 6.0
EXPOSURES = (0.5, 1.0, 2.0, 4.0, 1.0)
RENDER_SIZE = (960, 540)
WINDOW_SIZE = (1600, 960)


# --- what the window offers -------------------------------------------------------------
def picture_serial(app) -> object:
    """What changes whenever the view gets a new picture: the responsive window's picture
    stamp, else the identity of the frame result (a synchronous window)."""
    pictures = app.state.runtime.frame.pictures
    if "A" in pictures:
        return pictures["A"].stamp.serial
    return id(app.state.runtime.frame.result)


def poke(app) -> None:
    """Count an injected imgui event as window input, as glfw's callback would (a
    window that waits for events when idle must wake for it)."""
    getattr(app.window, "_on_event", lambda: None)()


def busy(app) -> bool:
    """Work in flight, or the camera still counts as moving (the full size follows)."""
    status = getattr(app, "status", None)
    return bool(status is not None and status.active) or bool(getattr(app, "_interacted",
                                                                     False))


def draw(app) -> float:
    """One frame that draws (an idle responsive window would skip it); milliseconds."""
    start = time.perf_counter()
    try:
        app.frame(force=True)
    except TypeError:                  # a window whose frame() always draws
        app.frame()
    return (time.perf_counter() - start) * 1e3


def display_pass_ms(app) -> float | None:
    """The view composer's pass alone for an exposure change (median of the sweep, timed
    between two glFinish), in a window that has one."""
    import dataclasses

    rt = app.state.runtime
    composer, pictures = rt.services.composer, rt.frame.pictures
    if composer is None or "A" not in pictures or "A" not in rt.frame.displays:
        return None
    times = []
    for value in EXPOSURES:
        display = dataclasses.replace(rt.frame.displays["A"], exposure=value * 1.01)
        app.ctx.finish()
        start = time.perf_counter()
        composer.side_image("A", pictures["A"], display, "final")
        app.ctx.finish()
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times)


def painted_percent(app) -> float | None:
    """The share of the window the last frame repainted, in a window that paints its
    lists where they changed (explorer/ui/partial_paint.py)."""
    painter = getattr(app, "painter", None)
    return None if painter is None else 100.0 * painter.painted_share


def frame_profile(app) -> str:
    """The last drawn frame by phase, wall and CPU ms (a window with a frame profile)."""
    profile = getattr(app, "profile", None)
    return profile.summary() if profile is not None and profile.wall_ms else ""


def frame_detail(app) -> str:
    """The pipeline's units of the last frame and its profile by phase, as far as the
    window offers them."""
    status = getattr(app, "status", None)
    parts = []
    if status is not None:
        parts.append(", ".join(f"{unit.side} {unit.what} {unit.ms:.0f} ms"
                               for unit in status.work) or "no pipeline work")
    panels = getattr(getattr(app, "panels", None), "panel_ms", None)
    if panels:
        title, slowest = max(panels.items(), key=lambda item: item[1])
        parts.append(f"slowest panel {title} {slowest:.0f} ms")
    profile = frame_profile(app)
    if profile:
        parts.append(profile)
    return "; ".join(parts)


def lit(app) -> bool:
    import numpy as np

    rect = app.state.runtime.view.view_rect
    pixels = app.last_pixels
    if rect is None or pixels is None:
        return False
    x0, y0, x1, y1 = (int(round(v)) for v in rect)
    view = pixels[y0 + 2:y1 - 2, x0 + 2:x1 - 2]
    return view.size > 0 and float(np.mean(view.max(axis=2) > LIT_LEVEL)) > LIT_SHARE


IDLE_FRAMES = 200
"""Frames the soak waits at most for the window to fall idle after a step."""


class Recorder:
    """Times frames and keeps the longest one with what ran in it."""

    def __init__(self, app) -> None:
        self.app = app
        self.longest = (0.0, "")
        self.frames = 0
        self.phase = "launch"
        self.slow: list[tuple[float, str]] = []
        """The five longest frames with their phase and what ran in them."""
        self.input_at = 0.0
        """perf_counter() of the last input the session gave (:meth:`input`)."""
        self.interacting = (0.0, "", "")
        """The longest frame within :data:`INTERACTING_S` of an input (a drag's frames, a
        click's and those right after it), with its phase and :func:`frame_detail`."""
        self.panels = (0.0, "")
        """The longest building of the panels in a frame, with the slowest panel."""
        self.cpu = {"interacting": 0.0, "any": 0.0}
        """The most CPU milliseconds (the process's, the software renderer's threads
        included) a frame took, within :data:`INTERACTING_S` of an input and of all: what
        a quiet machine's wall time would be near, on a machine shared with other work."""

    def input(self) -> None:
        """The session gives input now (a mouse event, a click that changes a setting)."""
        poke(self.app)
        self.input_at = time.perf_counter()

    def frame(self) -> float:
        """One frame() call; milliseconds it blocked (without an idle wait for events,
        which input ends at once)."""
        start, cpu = time.perf_counter(), time.process_time()
        self.app.frame()
        ms = (time.perf_counter() - start - getattr(self.app, "last_wait_s", 0.0)) * 1e3
        cpu_ms = (time.process_time() - cpu) * 1e3
        self.frames += 1
        self.cpu["any"] = max(self.cpu["any"], cpu_ms)
        if start - self.input_at < INTERACTING_S:
            self.cpu["interacting"] = max(self.cpu["interacting"], cpu_ms)
        if start - self.input_at < INTERACTING_S and ms > self.interacting[0]:
            self.interacting = (ms, self.phase, frame_detail(self.app))
        phases = getattr(self.app, "draw_phases_ms", None) or {}
        panels = getattr(getattr(self.app, "panels", None), "panel_ms", None) or {}
        if phases.get("panels", 0.0) > self.panels[0]:
            slowest = max(panels.items(), key=lambda item: item[1], default=("-", 0.0))
            self.panels = (phases["panels"], f"{self.phase}: {slowest[0]} {slowest[1]:.0f} ms")
        if ms > self.longest[0]:
            status = getattr(self.app, "status", None)
            if status is None:
                work = "(no work log: a synchronous window runs the pipeline in its frame)"
            else:
                work = ", ".join(f"{unit.side} {unit.what} {unit.ms:.0f} ms"
                                 for unit in status.work) or "no pipeline work"
                work += f"; window drawing and the rest {ms - status.work_ms:.0f} ms"
                phases = getattr(self.app, "draw_phases_ms", None)
                if phases:      # a window that times its own drawing by phase
                    work += " (" + ", ".join(f"{name.replace('_', ' ')} {value:.0f} ms"
                                             for name, value in phases.items()) + ")"
                panels = getattr(getattr(self.app, "panels", None), "panel_ms", None)
                if panels:      # a window that times each panel it drew
                    title, slowest = max(panels.items(), key=lambda item: item[1])
                    work += f"; slowest panel {title} {slowest:.0f} ms"
            profile = frame_profile(self.app)
            work += f"; {profile}" if profile else ""
            self.longest = (ms, f"{self.phase}: {work}")
        if len(self.slow) < 5 or ms > self.slow[-1][0]:
            status = getattr(self.app, "status", None)
            rest = "" if status is None else f" (pipeline {status.work_ms:.0f} ms)"
            profile = frame_profile(self.app)
            rest += f" [{profile}]" if profile else ""
            self.slow = sorted(self.slow + [(ms, f"{self.phase}{rest}")], reverse=True)[:5]
        return ms

    def until_idle(self, limit: int = IDLE_FRAMES) -> None:
        """Frames until the window falls idle (nothing to draw, no work: it releases what
        only a job uses and trims its heaps), as a reader's window is while the step is
        read; at most ``limit``. A window that does not count its idle falls: none."""
        if not hasattr(self.app, "fallen_idle"):
            return
        for _ in range(limit):
            if self.app.fallen_idle:
                return
            self.frame()

    def converge(self) -> float:
        """Frames until the picture has converged; milliseconds to the end of the frame
        that found nothing left to do (one more frame is drawn, not counted)."""
        start = time.perf_counter()
        self.frame()
        while busy(self.app) and time.perf_counter() - start < SETTLE_LIMIT_S:
            self.frame()
        elapsed = (time.perf_counter() - start) * 1e3
        self.frame()
        return elapsed

    def until_new_picture(self, before: object) -> tuple[float, float]:
        """(ms to the first new picture, ms until converged) from now."""
        start = time.perf_counter()
        first = None
        while time.perf_counter() - start < SETTLE_LIMIT_S:
            self.frame()
            now = (time.perf_counter() - start) * 1e3
            if first is None and picture_serial(self.app) != before:
                first = now
            if first is not None and not busy(self.app):
                return first, now
        return (first or float("nan")), float("nan")


# --- the session ------------------------------------------------------------------------
def open_app(grid: int, window: tuple[int, int] = WINDOW_SIZE,
             render: tuple[int, int] = RENDER_SIZE):
    from explorer.lpv.settings import Settings
    from explorer.ui.app import App
    from explorer.ui.state import AppState

    state = AppState(settings=Settings(grid_size=grid, width=render[0], height=render[1]))
    state.follow_view_size = False
    options = dict(width=window[0], height=window[1], visible=True, vsync=False,
                   persist_settings=False)
    try:
        from explorer.ui.window_options import WindowOptions
    except ImportError:     # a checkout (--root) from before the window's options object
        return App(state, **options)
    return App(state, WindowOptions(**options))


def session(spawned: float, frames: int, grid: int, finish_phases: bool = False) -> dict:
    """The session (module docstring): its phases in order, their figures in one dict.
    ``finish_phases``: each phase of a frame ends with ``glFinish`` (a window with a
    frame profile: explorer/ui/frame_profile.py), so that its GPU work lands in it."""
    app = open_app(grid)
    if finish_phases and getattr(app, "profile", None) is not None:
        app.profile.finish = app.ctx.finish
    try:
        rec = Recorder(app)
        figures = launch_phase(app, rec, spawned)
        figures.update(idle_phase(app))
        figures.update(orbit_phase(app, rec, frames))
        figures.update(display_phase(app, rec, figures["idle_frame_ms"]))
        figures.update(toggle_phase(app, rec))
        figures.update(iterations8_phase(app, rec))
        figures.update(drag_phase(app, rec, "slider", "light_flux", _flux_values(app),
                                  held=_window_marks_setting_drags()))
        figures.update(drag_phase(app, rec, "object", "object_transforms", _object_moves(),
                                  held=True))
        figures.update(grid64_phase(app, rec, next(iter(figures["toggles"]))))
        figures.update(session_summary(app, rec))
    finally:
        app.close()
    return figures


def launch_phase(app, rec: Recorder, spawned: float) -> dict:
    """Seconds from the process start (``spawned``) to the first lit frame and to the
    converged picture."""
    figures = {}
    while time.time() - spawned < SETTLE_LIMIT_S:
        app.frame(capture=True)
        if lit(app):
            break
    figures["launch_to_first_lit_frame_s"] = time.time() - spawned
    rec.phase = "converge"
    rec.converge()
    figures["launch_to_converged_s"] = time.time() - spawned
    return figures


def idle_phase(app) -> dict:
    """The loop as a user leaves it (CPU share, frames drawn), then the cost of a redraw
    with nothing new (``idle_frame_ms``, the baseline of the display changes)."""
    figures = {}
    drawn = app.state.runtime.frame.frame_index
    cpu, wall = time.process_time(), time.perf_counter()
    while time.perf_counter() - wall < IDLE_S:
        app.frame()
    wall = time.perf_counter() - wall
    figures["idle_cpu_percent"] = 100.0 * (time.process_time() - cpu) / wall
    figures["idle_frames_drawn_per_s"] = (app.state.runtime.frame.frame_index - drawn) / wall
    phases: dict[str, list[float]] = {}
    redraws, painted = [], []
    for _ in range(10):
        redraws.append(draw(app))
        painted.append(painted_percent(app))
        for phase, ms in getattr(app, "draw_phases_ms", {}).items():
            phases.setdefault(phase, []).append(ms)
    figures["idle_frame_ms"] = statistics.median(redraws)
    if None not in painted:
        figures["idle_painted_percent"] = statistics.median(painted)
    if phases:        # a window that times its own drawing by phase
        figures["window_drawing_ms"] = statistics.median(
            sum(values) for values in zip(*phases.values()))
        for phase, values in phases.items():
            figures[f"window_drawing_{phase}_ms"] = statistics.median(values)
    return figures


def orbit_phase(app, rec: Recorder, frames: int) -> dict:
    """Drag the mouse across the view for ``frames`` frames: new pictures and window
    frames per second, the size rendered while dragging, then the refinement's time."""
    from imgui_bundle import imgui

    figures = {}
    rec.phase = "orbit"
    x0, y0, x1, y1 = app.state.runtime.view.view_rect
    scale = imgui.get_io().display_framebuffer_scale.x or 1.0
    x, y = (x0 + x1) / 2 / scale, (y0 + y1) / 2 / scale
    io = imgui.get_io()
    io.add_mouse_pos_event(x, y)
    rec.input()
    rec.frame()
    io.add_mouse_button_event(0, True)
    rec.input()
    rec.frame()
    pictures, last = 0, picture_serial(app)
    start = time.perf_counter()
    first = None
    for step in range(1, frames + 1):
        io.add_mouse_pos_event(x + DRAG_PIXELS * (step % 60) - 180.0, y)
        rec.input()
        rec.frame()
        serial = picture_serial(app)
        pictures += serial != last
        if first is None and serial != last:
            first = (time.perf_counter() - start) * 1e3
        last = serial
    figures["orbit_first_update_ms"] = first if first is not None else float("nan")
    orbit_s = time.perf_counter() - start
    figures["orbit_fps"] = pictures / orbit_s
    figures["orbit_window_fps"] = frames / orbit_s
    result = app.state.runtime.frame.result
    figures["orbit_render_size"] = list(result.direct.shape[1::-1]) if result else None
    io.add_mouse_button_event(0, False)
    rec.input()
    figures["orbit_refine_ms"] = rec.converge()
    return figures


def display_phase(app, rec: Recorder, redraw_ms: float) -> dict:
    """Display-only changes (the exposure sweep): what a frame with the change costs
    over a plain redraw (``redraw_ms``), and the view composer's pass alone."""
    figures = {}
    rec.phase = "display"
    changed, phases, cpu, painted = [], {}, [], []
    for value in EXPOSURES:
        rec.input()                 # the slider's drag
        app.state.update(exposure=value)
        began = time.process_time()
        changed.append(rec.frame())
        cpu.append((time.process_time() - began) * 1e3)
        painted.append(painted_percent(app))
        profile = getattr(app, "profile", None)
        for phase, ms in (profile.wall_ms.items() if profile is not None else ()):
            phases.setdefault(phase, []).append(ms)
    figures["display_change_frame_ms"] = statistics.median(changed)
    figures["display_change_frame_cpu_ms"] = statistics.median(cpu)
    if None not in painted:
        figures["display_change_painted_percent"] = statistics.median(painted)
    for phase, values in phases.items():      # a window with a frame profile
        figures[f"display_change_{phase}_ms"] = statistics.median(values)
    figures["display_change_ms"] = max(statistics.median(changed) - redraw_ms, 0.0)
    figures["display_pass_ms"] = display_pass_ms(app)
    rec.converge()
    return figures


def toggle_phase(app, rec: Recorder) -> dict:
    """Each correction toggled and back (:func:`toggles`), with the medians."""
    rec.phase = "toggles"
    times = toggles(app, rec)
    return {"toggles": times,
            "toggle_first_update_ms": statistics.median(
                t["first_update_ms"] for t in times.values()),
            "toggle_converged_ms": statistics.median(t["converged_ms"] for t in times.values())}


def iterations8_phase(app, rec: Recorder) -> dict:
    """The issue's 32³ × 8: the iterations set to 8 (converged first), then each
    correction toggled and back (:func:`toggles`), the medians to the first new picture
    and to the converged one; the iterations put back after."""
    rec.phase = "32³×8"
    iterations = app.state.settings.iterations
    rec.input()
    app.state.update(iterations=8)
    rec.converge()
    times = toggles(app, rec)
    rec.input()
    app.state.update(iterations=iterations)
    rec.converge()
    return {"iterations8_toggle_first_update_ms": statistics.median(
                t["first_update_ms"] for t in times.values()),
            "iterations8_toggle_converged_ms": statistics.median(
                t["converged_ms"] for t in times.values()),
            "iterations8_slowest_first_update_ms": max(
                t["first_update_ms"] for t in times.values())}


DRAG_FRAMES = 8
"""Frames of a slider drag or an object move (one new value each, as a mouse drag gives)."""
MOVED_OBJECT = "short block"
"""The Cornell box's object the object phase moves."""


def _flux_values(app) -> list:
    """The light's flux dragged up by 5 % a frame from the scene's own (then put back)."""
    flux = app.state.settings.light_flux
    base = flux or app.state.runtime.scene_facts.light_flux_default or 1.0
    return [float(base) * (1.0 + 0.05 * step) for step in range(1, DRAG_FRAMES + 1)] + [flux]


def _object_moves() -> list:
    """The moved object 2 cm further along x a frame (then put back)."""
    return [((MOVED_OBJECT, (0.02 * step, 0.0, 0.0)),) for step in range(1, DRAG_FRAMES + 1)
            ] + [()]


def _window_marks_setting_drags() -> bool:
    """Whether the window counts a held slider's changes as a move (a checkout that does:
    explorer/ui/frame_pacing.py ``note_setting_drag``)."""
    from explorer.ui import frame_pacing

    return hasattr(frame_pacing, "note_setting_drag")


def drag_phase(app, rec: Recorder, name: str, field: str, values: list,
               held: bool) -> dict:
    """A drag that sets ``field`` to each of ``values`` but the last in one frame each
    (input in every frame): the first changed picture after the first value, the
    converged picture after the last, the longest frame of the drag; then the last value
    (the field put back) and converged. ``held``: each change also counts as a move, as
    the window counts the gizmo's (and, where it does, a held slider's): the driver sets
    the view's interaction time as they do, since it changes the state directly."""
    rec.phase = name
    before = picture_serial(app)
    start = time.perf_counter()
    first = None
    longest = 0.0
    for value in values[:-1]:
        rec.input()
        app.state.update(**{field: value})
        if held:
            app.state.runtime.view.interaction.moved_at = time.monotonic()
        longest = max(longest, rec.frame())
        if first is None and picture_serial(app) != before:
            first = (time.perf_counter() - start) * 1e3
    released = time.perf_counter()
    while busy(app) and time.perf_counter() - released < SETTLE_LIMIT_S:
        rec.frame()
        if first is None and picture_serial(app) != before:
            first = (time.perf_counter() - start) * 1e3
    figures = {f"{name}_first_update_ms": first if first is not None else float("nan"),
               f"{name}_converged_ms": (time.perf_counter() - released) * 1e3,
               f"{name}_longest_frame_ms": longest}
    rec.input()
    app.state.update(**{field: values[-1]})
    rec.converge()
    return figures


def grid64_phase(app, rec: Recorder, correction: str) -> dict:
    """The grid at 64³, then ``correction`` toggled at that size: time to the first new
    picture and to the converged one, each."""
    figures = {}
    rec.phase = "grid 64"
    before = picture_serial(app)
    rec.input()                     # the click that makes the change
    app.state.update(grid_size=64)
    first, final = rec.until_new_picture(before)
    figures["grid64_first_update_ms"], figures["grid64_converged_ms"] = first, final
    before = picture_serial(app)
    corrections = app.state.settings.corrections
    rec.input()
    app.state.set_corrections(**{correction: not getattr(corrections, correction)})
    first, final = rec.until_new_picture(before)
    figures["grid64_toggle_first_update_ms"] = first
    figures["grid64_toggle_converged_ms"] = final
    return figures


def session_summary(app, rec: Recorder) -> dict:
    """The longest blocked frame and what ran in it, the frame count, the five slowest
    frames and the renderer."""
    figures = {}
    figures["longest_blocked_frame_ms"], figures["longest_blocked_frame_work"] = rec.longest
    (figures["longest_interacting_frame_ms"], figures["longest_interacting_frame_phase"],
     figures["longest_interacting_frame_detail"]) = rec.interacting
    figures["longest_panels_ms"], figures["longest_panels_what"] = rec.panels
    figures["longest_frame_cpu_ms"] = rec.cpu["any"]
    figures["longest_interacting_frame_cpu_ms"] = rec.cpu["interacting"]
    figures["frames"] = rec.frames
    figures["slowest_frames"] = [f"{ms:.0f} ms {what}" for ms, what in rec.slow]
    figures["renderer"] = app.state.runtime.services.gl_renderer
    return figures


def toggles(app, rec: Recorder) -> dict:
    from dataclasses import fields

    times = {}
    for entry in fields(app.state.settings.corrections):
        name = entry.name
        value = getattr(app.state.settings.corrections, name)
        before = picture_serial(app)
        rec.input()     # the click on the checkbox (a window that counts input sees it)
        app.state.set_corrections(**{name: not value})
        first, final = rec.until_new_picture(before)
        times[name] = {"first_update_ms": first, "converged_ms": final}
        rec.input()
        app.state.set_corrections(**{name: value})
        rec.converge()
    return times


# --- soak -------------------------------------------------------------------------------
def resident_mib() -> float:
    with open("/proc/self/status", encoding="ascii") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


class _MallInfo2(ctypes.Structure):
    """glibc's ``struct mallinfo2`` (malloc.h, glibc 2.33 on)."""
    _fields_ = [(name, ctypes.c_size_t) for name in (
        "arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks",
        "fordblks", "keepcost")]


def resident_parts() -> dict[str, float]:
    """Where resident memory is, in MiB: ``anonymous`` mappings (malloc's heaps and its
    mapped blocks, llvmpipe's textures and JIT code), ``files`` (libraries, fonts), from
    ``/proc/self/smaps``; of malloc's (glibc ``mallinfo2``, all threads' heaps):
    ``malloc_used`` allocated in the heaps, ``malloc_free`` free in them (resident or
    not), ``malloc_mapped`` blocks mapped on their own. Empty where neither is there."""
    parts: dict[str, float] = {}
    try:
        with open("/proc/self/smaps", encoding="ascii", errors="replace") as smaps:
            anonymous = files = 0
            named = False
            for line in smaps:
                head = line.split(maxsplit=1)[0]
                if not head.endswith(":"):          # a mapping's first line
                    fields = line.split()
                    named = len(fields) > 5 and fields[5].startswith("/")
                elif head == "Rss:":
                    kib = int(line.split()[1])
                    if named:
                        files += kib
                    else:
                        anonymous += kib
            parts.update(anonymous=anonymous / 1024.0, files=files / 1024.0)
    except OSError:
        pass
    libc = ctypes.CDLL(None)
    mallinfo2 = getattr(libc, "mallinfo2", None)
    if mallinfo2 is not None:
        mallinfo2.restype = _MallInfo2
        info = mallinfo2()
        parts.update(malloc_used=info.uordblks / 2**20, malloc_free=info.fordblks / 2**20,
                     malloc_mapped=info.hblkhd / 2**20)
    return {name: round(value, 1) for name, value in parts.items()}


GL_KINDS = ("Texture", "Buffer", "Framebuffer", "Renderbuffer", "Program", "VertexArray",
            "Query", "Sampler")


def gl_objects(limit: int = 8192) -> dict[str, int]:
    """How many names of each kind of GL object are alive in the current context (the
    ``glIs*`` test of every name below ``limit``: objects are named from 1 up), and the
    moderngl scopes made and not released (``Scope``: a scope holds no GL name, but one
    dropped unreleased keeps its native object and its framebuffers' for good)."""
    gl = ctypes.CDLL("libGL.so.1")
    counts = {}
    for kind in GL_KINDS:
        test = getattr(gl, f"glIs{kind}")
        test.restype, test.argtypes = ctypes.c_ubyte, [ctypes.c_uint]
        counts[kind] = sum(1 for name in range(1, limit) if test(name))
    counts["Scope"] = _SCOPES["made"] - _SCOPES["released"]
    return counts


_SCOPES = {"made": 0, "released": 0}


def count_scopes() -> None:
    """Count the moderngl scopes made and released from now on (:func:`gl_objects`)."""
    import moderngl

    make, release = moderngl.Context.scope, moderngl.Scope.release

    def counted_scope(self, *args, **kwargs):
        _SCOPES["made"] += 1
        return make(self, *args, **kwargs)

    def counted_release(self) -> None:
        if not isinstance(self.mglo, moderngl.InvalidObject):
            _SCOPES["released"] += 1
        release(self)

    moderngl.Context.scope, moderngl.Scope.release = counted_scope, counted_release


_GL_BYTES: dict[int, tuple[object, str]] = {}
"""id → (the object, its owner) of every texture, renderbuffer and buffer made since
:func:`count_gl_bytes` and not yet released (held: without ``gc_mode`` a dropped object's
GL storage stays alive, so it stays in the tally)."""
_MAKERS = ("texture", "texture3d", "texture_array", "texture_cube", "depth_texture",
           "renderbuffer", "depth_renderbuffer", "buffer")
_PROGRAMS: dict[int, tuple[object, str]] = {}
"""id → (the program, its owner) of every program made since :func:`count_gl_bytes` and
not yet released: which code's programs a count that grew holds."""


def _gl_object_bytes(obj) -> int:
    """What a texture, renderbuffer or buffer holds (llvmpipe keeps it in host memory):
    its texels times components times the size of its dtype (mip levels not counted)."""
    import moderngl

    if isinstance(obj, moderngl.Buffer):
        return int(obj.size)
    dtype = getattr(obj, "dtype", "f1") or "f1"
    item = int(dtype[1:]) if dtype[1:].isdigit() else 4
    texels = obj.width * obj.height * max(getattr(obj, "samples", 0) or 1, 1)
    if isinstance(obj, moderngl.Texture3D):
        texels *= obj.depth
    elif isinstance(obj, moderngl.TextureArray):
        texels *= obj.layers
    elif isinstance(obj, moderngl.TextureCube):
        texels *= 6
    return texels * obj.components * item


_NOT_OWNERS = ("explorer.gl.", "explorer.commands.", "explorer.lpv.passes.textures")


def _owner() -> str:
    """The module and function of the explorer code that made an object (the first frame
    outside explorer/gl, this module and the grid and texture classes that every pass's
    grids are made by: the pass that asked for them)."""
    here = inspect.currentframe()
    frame = here.f_back.f_back if here is not None and here.f_back is not None else None
    while frame is not None:
        name = frame.f_globals.get("__name__", "")
        if name.startswith("explorer.") and not name.startswith(_NOT_OWNERS):
            return f"{name.removeprefix('explorer.')}.{frame.f_code.co_name}"
        frame = frame.f_back
    return "other"


def count_gl_bytes() -> None:
    """Tally the bytes of every texture, renderbuffer and buffer made from now on by the
    code that made it (:func:`gl_bytes`)."""
    import moderngl

    def counted(make):
        def making(self, *args, **kwargs):
            obj = make(self, *args, **kwargs)
            _GL_BYTES[id(obj)] = (obj, _owner())
            return obj
        return making

    for name in _MAKERS:
        setattr(moderngl.Context, name, counted(getattr(moderngl.Context, name)))

    def counted_program(make):
        def making(self, *args, **kwargs):
            program = make(self, *args, **kwargs)
            _PROGRAMS[id(program)] = (program, _owner())
            return program
        return making

    for name in ("program", "compute_shader"):
        setattr(moderngl.Context, name, counted_program(getattr(moderngl.Context, name)))


def gl_programs() -> dict[str, int]:
    """How many programs made since :func:`count_gl_bytes` are alive, by their owner."""
    import moderngl

    owners: dict[str, int] = {}
    for key, (program, owner) in list(_PROGRAMS.items()):
        if isinstance(program.mglo, moderngl.InvalidObject):
            del _PROGRAMS[key]
            continue
        owners[owner] = owners.get(owner, 0) + 1
    return dict(sorted(owners.items()))


def gl_buffers() -> dict[str, int]:
    """How many buffers made since :func:`count_gl_bytes` are alive, by their owner."""
    import moderngl

    owners: dict[str, int] = {}
    for obj, owner in list(_GL_BYTES.values()):
        if isinstance(obj, moderngl.Buffer) and not isinstance(obj.mglo, moderngl.InvalidObject):
            owners[owner] = owners.get(owner, 0) + 1
    return dict(sorted(owners.items()))


def gl_bytes() -> dict[str, float]:
    """MiB of the textures, renderbuffers and buffers alive now by their owner (those
    released are dropped from the tally), largest first."""
    import moderngl

    owners: dict[str, int] = {}
    for key, (obj, owner) in list(_GL_BYTES.items()):
        if isinstance(obj.mglo, moderngl.InvalidObject):
            del _GL_BYTES[key]
            continue
        owners[owner] = owners.get(owner, 0) + _gl_object_bytes(obj)
    return {owner: round(size / 2**20, 1)
            for owner, size in sorted(owners.items(), key=lambda item: -item[1])}


GRID_CYCLE = (8, 16, 32, 48, 64)
SOAK_WINDOW = (960, 600)
SOAK_RENDER = (320, 200)
"""The soak's window and render sizes: small, so that the 2-core machine turns many
rounds a minute; memory that grows per round shows sooner."""


def _lesson_steps() -> list[tuple[str, int]]:
    from explorer.lessons import load_all

    lessons, _ = load_all()
    return [(lesson.id, step.number) for lesson in lessons for step in lesson.steps]


def _click_view(app, rec: Recorder, fraction: float) -> None:
    """A click (press and release, no drag) at ``fraction`` across the view: a pick."""
    from imgui_bundle import imgui

    rect = app.state.runtime.view.view_rect
    if rect is None:
        return
    x0, y0, x1, y1 = rect
    scale = imgui.get_io().display_framebuffer_scale.x or 1.0
    io = imgui.get_io()
    io.add_mouse_pos_event((x0 + (x1 - x0) * fraction) / scale, (y0 + y1) / 2 / scale)
    poke(app)
    rec.frame()
    io.add_mouse_button_event(0, True)
    poke(app)
    rec.frame()
    io.add_mouse_button_event(0, False)
    poke(app)
    rec.frame()


def release_unshown_sides(app, rec: Recorder) -> None:
    """Give back now what the sides the view does not show made and the Error panel's
    idle measuring pipeline (their idle release, without its wait), in one frame: after a
    step, which are still alive would otherwise depend on how long the step took on this
    machine, and so would the GL counts compared after it (resident memory is read
    before, as the user has it)."""
    controller = getattr(app, "controller", None)
    if controller is None or not hasattr(controller, "idle_release_s"):
        return                           # an older window: no idle release
    # the Error panel's measuring pipeline too (explorer/ui/panels/error.py): released
    # 20 s after its last measurement, alive or not after a step by the machine's speed
    idle = [controller] + [task for task in app.state.runtime.services.tasks
                           if hasattr(task, "idle_release_s")]
    waits = [holder.idle_release_s for holder in idle]
    for holder in idle:
        holder.idle_release_s = 0.0
    try:
        poke(app)
        rec.frame()
    finally:
        for holder, wait in zip(idle, waits, strict=True):
            holder.idle_release_s = wait


SOAK_RSS_SLACK = 0.10
"""How far resident memory may rise above its bound (:func:`growth`: the warm-up's end at
a pass's end, the second pass's peak from the third pass on): malloc's arenas and
llvmpipe's JIT move it by tens of MiB from step to step."""
SOAK_RSS_BUDGET_MIB = 1.2 * 1024
"""Resident memory the window stays under all the way through the course (issue #31:
the warm-up included); a step above it fails the soak as growth does."""


def _kept_try_mib(session) -> float | None:
    """MiB of arrays the try-this prompts' kept frames hold (``TryFrames.sizes``; shared
    in part with the frames on screen), None for a window without them."""
    sizes = getattr(getattr(session, "try_frames", None), "sizes", None)
    return None if sizes is None else round(sum(sizes.values()) / 2**20, 1)


def selected_steps(wanted: str | None) -> list[tuple[str, int]]:
    """The course's steps in order, or those of ``wanted`` (``LESSON:STEP,...``, e.g.
    ``overview:2,errata:1``: a lesson id and a step number); ValueError naming an item
    that is not a step of the course."""
    steps = _lesson_steps()
    if not wanted:
        return steps
    chosen = []
    for item in wanted.split(","):
        lesson, _, number = item.strip().partition(":")
        step = (lesson, int(number)) if number.isdigit() else None
        if step not in steps:
            raise ValueError(f"--soak-steps: {item.strip()!r} is not LESSON:STEP of the "
                             f"course (e.g. {steps[0][0]}:{steps[0][1]})")
        chosen.append(step)
    return chosen


def growth(warm: list[dict], later: list[dict]) -> list[str]:
    """What grew after the warm-up (the soak's rule, module docstring): at the end of a
    later pass a GL object count above the warm-up pass's end (the same step after the
    same course), or resident memory above it by more than :data:`SOAK_RSS_SLACK`; after
    a step of the third pass on a count above the highest of its kind after any step of
    the second pass (which starts with what the course fills its caches with), or
    resident memory above the second pass's peak by more than the slack. ``warm``: one
    record per step of the warm-up pass; ``later``: the records after it. A program count
    that grew names the code whose programs grew (records with ``programs``)."""
    problems = []
    last = len(warm) - 1
    warm_end = warm[last]
    second = [record for record in later if record["pass"] == 2]
    # per kind: the second pass's record with the highest count of it
    highest = {kind: max(second, key=lambda record, kind=kind: record["gl"][kind])
               for kind in (second[0]["gl"] if second else {})}
    second_peak = max((record["rss_mib"] for record in second), default=float("inf"))
    over = 1.0 + SOAK_RSS_SLACK
    for record in later:
        where = f"pass {record['pass']} step {record['step']}"
        at_end = record["position"] == last
        for kind, count in record["gl"].items():
            if at_end and count > warm_end["gl"][kind]:
                problems.append(f"{where} (the pass's end): {kind} {count}, "
                                f"{warm_end['gl'][kind]} at the warm-up's end"
                                + _grown_programs(kind, record, warm_end))
            elif record["pass"] > 2 and count > highest[kind]["gl"][kind]:
                problems.append(f"{where}: {kind} {count}, at most "
                                f"{highest[kind]['gl'][kind]} in pass 2"
                                + _grown_programs(kind, record, highest[kind]))
        rss = record["rss_mib"]
        if at_end and rss > warm_end["rss_mib"] * over:
            problems.append(f"{where} (the pass's end): resident memory {rss:.0f} MiB, "
                            f"over the warm-up's end {warm_end['rss_mib']:.0f} MiB by more "
                            f"than {SOAK_RSS_SLACK:.0%}")
        elif record["pass"] > 2 and rss > second_peak * over:
            problems.append(f"{where}: resident memory {rss:.0f} MiB, over pass 2's peak "
                            f"{second_peak:.0f} MiB by more than {SOAK_RSS_SLACK:.0%}")
    return problems


def resident_by_pass(records: list[dict]) -> list[dict]:
    """Each pass's resident memory after its steps: the peak, the median and the end (MiB),
    and the step of its peak."""
    passes = []
    for number in sorted({record["pass"] for record in records}):
        ones = [record for record in records if record["pass"] == number]
        peak = max(ones, key=lambda record: record["rss_mib"])
        passes.append({"pass": number, "steps": len(ones),
                       "peak_mib": round(peak["rss_mib"], 1), "peak_step": peak["step"],
                       "median_mib": round(statistics.median(
                           record["rss_mib"] for record in ones), 1),
                       "end_mib": round(ones[-1]["rss_mib"], 1)})
    return passes


_COUNTED_BY_OWNER = {"Program": "programs", "Buffer": "buffers"}
"""The GL kinds whose counts the soak's records also hold by owner, and under which key."""


def _grown_programs(kind: str, record: dict, before: dict) -> str:
    """`` (owner +n, ...)``: whose programs (or buffers) ``record`` holds more of than
    ``before``."""
    key = _COUNTED_BY_OWNER.get(kind)
    if key is None or key not in record or key not in before:
        return ""
    grown = [f"{owner} +{count - before[key].get(owner, 0)}"
             for owner, count in record[key].items()
             if count > before[key].get(owner, 0)]
    return f" ({', '.join(grown)})" if grown else ""


def over_budget(records: list[dict]) -> list[str]:
    """The steps (the warm-up's too) after which resident memory was above
    :data:`SOAK_RSS_BUDGET_MIB`."""
    return [f"pass {record['pass']} step {record['step']}: resident memory "
            f"{record['rss_mib']:.0f} MiB, over the budget of {SOAK_RSS_BUDGET_MIB:.0f} MiB"
            for record in records if record["rss_mib"] > SOAK_RSS_BUDGET_MIB]


def soak(minutes: float, grid: int, wanted: str | None = None) -> dict:
    """The soak (module docstring): one round per lesson step, each round also changing
    the grid, cascades, view, buffer and one correction by the step's place in the
    course (so every pass repeats the first), picking a pixel and (every fifth step)
    measuring the error. The first pass is the warm-up; passes follow until ``minutes``
    have gone by after it, at least one whole pass."""
    from dataclasses import fields

    from explorer.ui import camera
    from explorer.ui.lesson_panel import current_screen, session_of, show_screen
    from explorer.ui.panels.error import error_service

    count_scopes()
    count_gl_bytes()
    app = open_app(grid, window=SOAK_WINDOW, render=SOAK_RENDER)
    try:
        rec = Recorder(app)
        rec.converge()
        modes = ("single", "split", "difference")
        buffers = ("final", "direct", "indirect", "albedo")
        names = [entry.name for entry in fields(app.state.settings.corrections)]
        steps = selected_steps(wanted)
        session = session_of(app.state)

        def cycle(step: int) -> None:
            lesson_id, number = steps[step]
            session.open(lesson_id)
            session.go(number)
            show_screen(app.state, session.apply(current_screen(app.state)))
            rec.converge()
            if session.step is not None and session.step.try_this:
                show_screen(app.state, session.apply_try(1, current_screen(app.state)))
                rec.converge()
                show_screen(app.state, session.apply(current_screen(app.state)))
            app.state.update(grid_size=GRID_CYCLE[step % len(GRID_CYCLE)],
                             cascades=1 + step % 2, width=SOAK_RENDER[0],
                             height=SOAK_RENDER[1])
            app.state.view_mode = modes[step % len(modes)]
            app.state.view_buffer = buffers[step % len(buffers)]
            corrections = app.state.settings.corrections
            name = names[step % len(names)]
            app.state.set_corrections(**{name: not getattr(corrections, name)})
            eye, target = (app.state.settings.camera
                           or app.state.runtime.scene_facts.camera_default)
            app.state.update(camera=camera.orbit(eye, target, 7.0, 0.0))
            rec.converge()
            _click_view(app, rec, 0.3 + 0.1 * (step % 5))
            if step % 5 == 0:
                service = error_service(app.state)
                service.lesson_wants = True
                for _ in range(400):
                    rec.frame()
                    if service.result_for() is not None or service.problem is not None:
                        break
                service.lesson_wants = False

        began = time.monotonic()
        samples: list[dict] = []
        records: list[dict] = []

        def sample(phase: str) -> None:
            entry = {"minute": round((time.monotonic() - began) / 60.0, 2), "phase": phase,
                     "rss_mib": resident_mib(), "gl": gl_objects()}
            samples.append(entry)
            print(f"soak {entry['minute']:5.1f} min {phase:<8} {entry['rss_mib']:6.0f} MiB  "
                  + "  ".join(f"{kind} {count}" for kind, count in entry["gl"].items()),
                  file=sys.stderr, flush=True)

        # the course's last step first, so that the warm-up pass starts where every later
        # pass starts (what a step holds on screen depends on the step before it)
        cycle(len(steps) - 1)
        sample("start")
        passes, warm_end = 0, None
        while passes < 2 or time.monotonic() - warm_end < minutes * 60.0:
            passes += 1
            for position in range(len(steps)):
                cycle(position)
                lesson_id, number = steps[position]
                rec.until_idle()            # the step as a reader has it on screen
                rss = resident_mib()
                release_unshown_sides(app, rec)
                record = {"pass": passes, "position": position,
                          "step": f"{lesson_id}:{number}", "rss_mib": rss,
                          "resident": resident_parts(),
                          "kept_try_mib": _kept_try_mib(session),
                          "gl": gl_objects(), "gl_mib": gl_bytes(),
                          "programs": gl_programs(), "buffers": gl_buffers()}
                records.append(record)
                print(f"  pass {passes} step {position + 1}/{len(steps)} {record['step']:<26}"
                      f" {record['rss_mib']:6.0f} MiB  " + "  ".join(
                          f"{kind} {count}" for kind, count in record["gl"].items())
                      + f"  GL {sum(record['gl_mib'].values()):.0f} MiB (" + ", ".join(
                          f"{owner} {mib:.0f}" for owner, mib in
                          list(record["gl_mib"].items())[:4]) + ")",
                      file=sys.stderr, flush=True)
                phase = "warm-up" if passes == 1 else "soak"
                if time.monotonic() - began >= 60.0 * len(samples):
                    sample(phase)
                if passes > 2 and time.monotonic() - warm_end >= minutes * 60.0:
                    break
            if passes == 1:
                warm_end = time.monotonic()
                sample("warmed")
        sample("end")
        warm = [r for r in records if r["pass"] == 1]
        later = [r for r in records if r["pass"] > 1]
        start = next(s for s in samples if s["phase"] == "warmed")
        return {"renderer": app.state.runtime.services.gl_renderer,
                "minutes": minutes, "cycles": len(records), "passes": passes,
                "steps": len(steps), "frames": rec.frames,
                "warm_up_minutes": round((warm_end - began) / 60.0, 2),
                "start": {"rss_mib": start["rss_mib"], "gl": start["gl"]},
                "end": {"rss_mib": samples[-1]["rss_mib"], "gl": samples[-1]["gl"]},
                "warm_up_peak_rss_mib": max(r["rss_mib"] for r in warm),
                "peak_rss_mib": max(r["rss_mib"] for r in records),
                "growth": growth(warm, later), "over_budget": over_budget(records),
                "resident_by_pass": resident_by_pass(records),
                "rss_budget_mib": SOAK_RSS_BUDGET_MIB, "samples": samples,
                "records": records}
    finally:
        app.close()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--spawned", type=float, default=time.time(),
                        help="time.time() when the parent started this process")
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--grid", type=int, default=32)
    parser.add_argument("--soak", type=float, default=None, metavar="MINUTES")
    parser.add_argument("--soak-steps", default=None, metavar="LESSON:STEP,...")
    parser.add_argument("--finish-phases", action="store_true")
    parser.add_argument("--json", required=True)
    args = parser.parse_args(argv)
    figures = soak(args.soak, args.grid, args.soak_steps) if args.soak else session(
        args.spawned, args.frames, args.grid, args.finish_phases)
    figures["root"] = os.path.dirname(os.path.dirname(sys.modules["explorer"].__file__))
    with open(args.json, "w", encoding="utf-8") as out:
        json.dump(figures, out, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
