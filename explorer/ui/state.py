"""The one app-state object every panel reads and writes.

Panels are functions ``gui_<panel>(state: AppState)``. They change :class:`AppState`
(mostly by replacing the immutable :class:`~explorer.lpv.settings.Settings`) and post
requests; the app loop turns those into pipeline runs, screenshots and file loads. What
the pipeline produced comes back in :attr:`AppState.runtime` (results, texture ids), which
is never persisted.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

from explorer.lpv.settings import MAX_CASCADES, MAX_GRID_SIZE, MAX_ITERATIONS, PRESETS, Settings
from explorer.overlay_params import (  # noqa: F401 - the overlays' names, re-exported
    COLOUR_MAPS,
    GLYPH_CELLS,
    GLYPH_SIZINGS,
    PICK_KINDS,
    SLICE_AXES,
    SLICE_QUANTITIES,
    OverlayState,
)
from explorer.schema import setting, validate

if TYPE_CHECKING:
    import numpy as np

    from explorer.lpv.corrections import Corrections
    from explorer.lpv.frame import FrameResult
    from explorer.scene import Scene
    from explorer.ui.animation import Animation
    from explorer.ui.fonts import Fonts
    from explorer.ui.formulas import FormulaCache
    from explorer.ui.picture import Picture, SideDisplay
    from explorer.ui.textures import UiTextures

VIEW_MODES = ("single", "split", "difference", "side-by-side")
"""single: configuration A; split: A left | B right with a draggable divider;
difference: false-colour |A − B| with a scale bar; side-by-side: the whole A beside the
whole B."""
COMPARE_MODES = VIEW_MODES[1:] + ("small-multiples",)
"""The views that show A against other configurations; small multiples (a lesson
try-this's several values, ``AppState.compare_variants``) put A, B and each further
variant in a grid."""

VIEW_BUFFERS = ("final", "direct", "indirect", "albedo")
"""What the 3D view shows (the first names of settings.VIEWS): the final image, or one
linear buffer of the picture, as the display shows it (``shaders/view.glsl`` BUFFER_*)."""

INSPECT_SOURCES = (
    "rsm-position", "rsm-normal", "rsm-flux",   # RSM buffers
    "grid-slice",                               # accumulated grid acc_N, one z slice
    "propagation",                              # grid_t at a chosen iteration t
    "geometry-volume",                          # occlusion grid, one z slice
    "vpls",                                     # the injected VPLs as 3D points
    "cascade-weights",                          # which cascade the gather reads per pixel
)
GRID_COMPONENTS = ("intensity", "sh0", "sh1", "sh2", "sh3")
"""What a grid slice shows: the intensity evaluated in a chosen direction (rgb), or one SH
coefficient (rgb of that coefficient, signed)."""


MIN_WINDOW_SIZE = 150
"""Smallest window edge in pixels (the menu bar and a panel still fit)."""
MAX_WINDOW_SIZE = 8192
"""Largest window edge in pixels: X11 refuses windows past 32767 (Xlib aborts the
process), and no screen is wider than this; the window's framebuffer must also fit a
texture (GL_MAX_TEXTURE_SIZE is at least 8192 on a GL 4.3 driver)."""


@dataclass
class InspectState:
    """What the Inspect panel shows; persisted, so every field is declared and checked
    by the settings schema (explorer/schema.py) when the file is read back."""

    source: str = setting("rsm-flux", kind="choice", choices=INSPECT_SOURCES,
                          doc="The buffer the Inspect panel shows.")
    slice_z: int = setting(-1, kind="int", low=-1, high=MAX_GRID_SIZE,
                           doc="z slice of the grid views; -1 = the middle slice.")
    component: str = setting("intensity", kind="choice", choices=GRID_COMPONENTS,
                             doc="What a grid slice shows.")
    direction_azimuth: float = setting(0.0, kind="float", low=-180.0, high=180.0, unit="°",
                                       doc="Direction the intensity is evaluated in.")
    direction_elevation: float = setting(90.0, kind="float", low=-90.0, high=90.0, unit="°",
                                         doc="Direction the intensity is evaluated in.")
    iteration: int = setting(0, kind="int", low=0, high=MAX_ITERATIONS << (MAX_CASCADES - 1),
                             doc='The step t of grid_t the "propagation" source shows (the '
                                 'finest cascade runs up to 2^(cascades-1)·iterations steps '
                                 'with "same-distance").')
    playing: bool = setting(False, kind="bool", doc="Step through the iterations.")
    play_rate: float = setting(4.0, kind="float", low=0.0, low_open=True, high=1000.0,
                               doc="Iterations per second while playing.")
    signed_scale: float = setting(0.0, kind="float", low=0.0, high=1e12,
                                  doc="Top of the signed scale; 0 = automatic.")
    glyphs: bool = setting(False, kind="bool", doc="Draw SH glyphs over grid slices.")
    cascade: int = setting(0, kind="int", low=0, high=MAX_CASCADES - 1,
                           doc="The cascade grid-slice and geometry-volume show.")

    def __post_init__(self) -> None:
        validate(self)


@dataclass
class Message:
    text: str
    level: str = "info"               # "info" | "warning" | "error"
    created: float = field(default_factory=time.monotonic)


@dataclass
class Interaction:
    """The camera's mouse and keyboard moves (explorer/ui/camera_controls.py) and the
    object gizmo's drags (explorer/ui/gizmo.py): the view renders at a reduced size while
    they last."""

    held: bool = False
    """A drag that moves the camera or an object is in progress (the button is down)."""
    moved_at: float = -1e9
    """time.monotonic() of the last camera move by the mouse, wheel or keys, or object
    move by the gizmo."""

    def active(self, now: float, settle_s: float) -> bool:
        """Whether the camera is being moved: held, or moved less than ``settle_s`` ago
        (wheel steps and fly keys come as single events)."""
        return self.held or now - self.moved_at < settle_s


@dataclass(slots=True)
class ShownFrame:
    """The frame being shown: each side's last result and picture, how the view shows
    them, the jobs' progress and the frame loop's own times (the controller publishes
    them each frame)."""

    result: FrameResult | None = None           # configuration A's last finished frame
    compare_result: FrameResult | None = None   # B's (compare views)
    pictures: dict[str, Picture] = field(default_factory=dict)
    """Side -> its last picture (a finished frame or a progressive preview), which the
    view shows (explorer/ui/picture.py)."""
    displays: dict[str, SideDisplay] = field(default_factory=dict)
    """Side -> how the view shows it (exposure, display scale, tone curve)."""
    progress: dict[str, str] = field(default_factory=dict)
    """Side -> its job's progress ("propagating 5/8"); empty when the picture is final."""
    frame_view: Callable[..., np.ndarray] | None = None
    """``Pipeline.view`` of configuration A's pipeline (a view the FrameResult alone
    cannot make, e.g. cascade-weights, which needs the G-buffer); None before a run."""
    pipeline_error: str | None = None
    side_exposures: tuple[float, float] = (1.0, 1.0)  # A, B when exposed separately
    exposure_seen: list = field(default_factory=lambda: [None, None])
    """Per side, the (result, indirect only) its exposure was last measured on."""
    frame_ms: float = 0.0
    pipeline_ms: float = 0.0          # time of the last finished frame's job, all frames
    frame_index: int = 0                  # frames drawn (an idle window draws none)


@dataclass(slots=True)
class SceneFacts:
    """What the scene itself says, before the Settings' overrides (loaded once per
    scene by the controller): the defaults the camera and light controls start from."""

    scene: tuple[str, Scene] | None = None
    """(scene name, the scene as loaded, before the Settings' overrides): its lights,
    objects and paths (the Lights & objects panel)."""
    camera_default: tuple | None = None   # the scene's (eye, target) once known
    light_default: tuple | None = None    # the scene's (position, target) once known
    light_flux_default: float | None = None
    light_cone_default: tuple | None = None   # the scene spot's (inner, outer) cone, degrees
    light_is_spot: bool = True                # False for a directional light (no cone)
    scene_bounds: tuple | None = None


@dataclass(slots=True)
class ViewInput:
    """The 3D view's input: where it is on screen and what the mouse does over it."""

    view_size: tuple[int, int] = (0, 0)   # pixels the 3D view panel offers
    view_rect: tuple | None = None        # (x0, y0, x1, y1) framebuffer pixels of the image
    split_dragging: bool = False          # the split view's divider is held
    view_press: tuple | None = None       # where the left button went down on the view
    pointer_moved: bool = False           # the mouse has moved over the view (hover reads)
    hover: object | None = None
    """explorer.ui.overlays.in_view.Hover under the mouse in the view, or None."""
    interaction: Interaction = field(default_factory=Interaction)
    play_clock: float = 0.0               # fractional iterations while playing


@dataclass(slots=True)
class Services:
    """What the window's parts draw and compute with: GL helpers, caches, fonts, the
    file dialog, background tasks, and what the GL context could not do."""

    composer: object | None = None
    """explorer.ui.view_composer.ViewComposer: draws the view's images (view.glsl)."""
    compositor: object | None = None
    """explorer.ui.overlays.compositor.Compositor: the View panel's in-scene overlays
    (named, not imported: it reads this module's OverlayState)."""
    textures: UiTextures | None = None          # UI-owned textures (uploads)
    formulas: FormulaCache | None = None
    fonts: Fonts | None = None          # prose styles
    markdown_ready: bool = False      # imgui_bundle.rich_md can render (lesson text)
    gl_renderer: str = ""                 # GL_RENDERER of the window's context
    gl_problem: str | None = None
    shader_errors: dict[str, str] = field(default_factory=dict)
    file_dialog: object | None = None     # a pending portable_file_dialogs.open_file
    file_dialog_available: bool | None = None
    inspect_cache: tuple | None = None     # (version, texture id, scale top, caption)
    vpl_cache: tuple | None = None        # (result id, point groups) for the VPL plot
    tasks: list[BackgroundTask] = field(default_factory=list)
    """Background work the controller advances within the frame budget with its GL
    context (objects with ``advance(ctx, budget_s)``, ``release()`` and ``running``),
    e.g. the Error panel's reference render."""
    figure_cache: object | None = None
    """explorer.ui.figure_cache.FigureCache: the lesson figures' pictures, made by the
    window (named, not imported: the figures' context reads this module)."""
    animation: Animation | None = None
    """The paths and fly-through that play, the object the gizmo moves (made on first use
    by explorer.ui.animation.animation_of)."""


RUNTIME_PARTS = {"frame": ShownFrame, "scene_facts": SceneFacts, "view": ViewInput,
                 "services": Services}
"""Runtime's parts by attribute name."""


@dataclass(slots=True)
class Runtime:
    """What the app loop hands to the panels each frame, in four parts: the
    frame being shown (:class:`ShownFrame`), the scene's facts (:class:`SceneFacts`), the
    view's input (:class:`ViewInput`) and the services (:class:`Services`); besides them
    only what the panels drawn this frame ask of the next (the audit, a redraw). Not
    persisted.

    A panel reads the part it needs by name (``runtime.frame.result``,
    ``runtime.services.textures``); no field of a part is reachable from the runtime
    itself, so what a panel depends on shows in its code. The runtime and its parts have
    slots: setting a name they do not declare raises."""

    frame: ShownFrame = field(default_factory=ShownFrame)
    scene_facts: SceneFacts = field(default_factory=SceneFacts)
    view: ViewInput = field(default_factory=ViewInput)
    services: Services = field(default_factory=Services)
    audit_wanted: str = "off"
    """The most a panel drawn this frame needs of the energy audit (a plot, a lesson
    figure or a live number; explorer.lpv.audit.AUDIT_MODES): the pipelines measure that
    much (``need_audit``) while this is so."""
    audit_wanted_on: dict[str, str] = field(default_factory=dict)
    """What a panel drawn this frame needs of one side's audit only (side name -> mode):
    the picked cell's records are read on the picked side, and at 64³ with two cascades
    a side's per-cell records are 84 MiB (issue #31)."""
    redraw: bool = False
    """Something drawn this frame moves by itself (playback, fly keys held): draw the
    next frame too, even with no input."""

    def want_audit(self, mode: str = "full", side: str | None = None) -> None:
        """Called by what shows the energy audit while it is drawn, with the audit mode
        it needs (``flux``: only the flux per step; ``full``: every term), of every side
        or of ``side`` only."""
        from explorer.lpv.audit import strongest_audit

        if side is None:
            self.audit_wanted = strongest_audit(self.audit_wanted, mode)
        else:
            self.audit_wanted_on[side] = strongest_audit(
                self.audit_wanted_on.get(side, "off"), mode)

    def audit_of_sides(self, sides: Iterable[str]) -> dict[str, str]:
        """Per side: the audit mode what is drawn this frame needs of it."""
        from explorer.lpv.audit import strongest_audit

        return {side: strongest_audit(self.audit_wanted, self.audit_wanted_on.get(side, "off"))
                for side in sides}

    def ask_again(self) -> None:
        """At a frame's start: what is drawn now asks for the audit and the redraw again."""
        self.redraw, self.audit_wanted = False, "off"
        self.audit_wanted_on.clear()

    def request_redraw(self) -> None:
        """Called by what animates, every frame it animates."""
        self.redraw = True


class BackgroundTask(Protocol):
    """Work a panel hands to the frame loop (``runtime.services.tasks``)."""

    running: bool

    def advance(self, ctx, budget_s: float) -> None: ...
    def release(self) -> None: ...


@dataclass
class Requests:
    """Things a panel asks of the app loop, handled after the panels ran."""

    screenshot: Path | None = None
    open_scene: str | None = None
    reset_layout: bool = False
    open_file_dialog: bool = False
    save_scene_dialog: bool = False           # File → Save scene as… (explorer/ui/scene_save.py)
    scene_overrides: dict | None = None       # Settings changes applied once open_scene opened
    focus_panel: str | tuple | None = None   # bring this panel's (these panels') tab forward
    quit: bool = False


def fit_window_size(size: tuple[int, int]) -> tuple[int, int]:
    """A window size within [MIN_WINDOW_SIZE, MAX_WINDOW_SIZE] per edge: what the
    settings file may hold (a window dragged smaller is saved at the smallest size)."""
    width, height = (min(max(int(edge), MIN_WINDOW_SIZE), MAX_WINDOW_SIZE) for edge in size[:2])
    return width, height


WINDOW_FRAME_PX = (16, 48)
"""What a window manager adds around a window's content (borders, the title bar), at
most, per axis: the content size that fits a work area is this much smaller."""


def fit_work_area(size: tuple[int, int], area: tuple[int, int, int, int] | None
                  ) -> tuple[tuple[int, int], tuple[int, int] | None]:
    """(size, top-left position) of a window of ``size`` opened on a monitor whose work
    area is ``area`` (x, y, width, height): shrunk to fit it, frame included (never
    below :data:`MIN_WINDOW_SIZE`), and centred in it; ``size`` as it is and no position
    without a work area."""
    if area is None:
        return (size[0], size[1]), None
    x, y, width, height = area
    frame_w, frame_h = WINDOW_FRAME_PX
    w, h = (max(min(int(edge), room - frame), MIN_WINDOW_SIZE)
            for edge, room, frame in zip(size, (width, height), WINDOW_FRAME_PX))
    border = frame_w // 2                       # each side; the title bar is the rest
    left = x + max((width - w - frame_w) // 2, 0) + border
    top = y + max((height - h - frame_h) // 2, 0) + frame_h - border
    return (w, h), (left, top)


_SCREENSHOTS_NAMED: set[Path] = set()
"""The screenshot paths this process has handed out (a second press within the same
second is given the next free name, even before the first is written)."""


def default_screenshot_path(folder: Path | None = None) -> Path:
    """Where F12 and the View panel's button write: a time-stamped PNG in ``folder`` (the
    folder the explorer was started from), ``-2``, ``-3``, ... added when that name is
    taken, on disk, by an earlier press or by another window: every screenshot gets a file
    of its own."""
    folder = Path.cwd() if folder is None else Path(folder)
    stem = f"lpv-explorer-{datetime.now():%Y%m%d-%H%M%S}"
    number = 1
    while True:
        path = folder / (f"{stem}.png" if number == 1 else f"{stem}-{number}.png")
        if path not in _SCREENSHOTS_NAMED and not os.path.lexists(path):
            try:
                # reserved on disk too (an empty file, replaced whole by the PNG): two
                # windows started from one folder never pick the same name
                os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            except FileExistsError:
                number += 1
                continue
            except OSError:
                pass                    # a folder it cannot write: the write says so
            _SCREENSHOTS_NAMED.add(path)
            return path
        number += 1


def release_screenshot_path(path: Path) -> None:
    """Remove the empty file :func:`default_screenshot_path` reserved as ``path`` when the
    screenshot could not be written (never a file it did not reserve)."""
    path = Path(path)
    if path in _SCREENSHOTS_NAMED:
        with contextlib.suppress(OSError):
            if path.stat().st_size == 0:
                path.unlink()


@dataclass
class AppState:
    """The window's state. The fields declared with :func:`setting` are what the settings
    file holds (explorer/ui/persist.py): the schema checks them when the file is read
    back, and the Scene panel draws those that declare a widget."""

    settings: Settings = setting(kind="nested", nested=Settings, default_factory=Settings,
                                 doc="Configuration A: what the view shows.")
    compare_settings: Settings = setting(  # configuration B: only its corrections are used
        kind="nested", nested=Settings,
        default_factory=lambda: Settings(corrections=PRESETS["original"]),
        doc="Configuration B of the compare views (only its corrections are used).")
    view_mode: str = setting("single", kind="choice", choices=("single", *COMPARE_MODES),
                             doc="One configuration, split A|B, their difference, both "
                                 "side by side, or small multiples.")
    view_buffer: str = setting("final", kind="choice", choices=VIEW_BUFFERS,
                               doc="What the 3D view shows.")
    split_position: float = setting(0.5, kind="float", low=0.02, high=0.98,
                                    doc="The split view's divider, a fraction of its width.")
    expose_sides_separately: bool = setting(
        False, kind="bool", doc="Expose each side of a comparison on its own (with the "
                                "display's auto exposure: B keeps its own display scale "
                                "instead of A's).")
    difference_scale: float = setting(0.0, kind="float", low=0.0, high=1e12,
                                      doc="Watts per pixel at the top of the difference "
                                          "scale; 0 = automatic.")
    difference_colour_map: str = setting("heat", kind="choice", choices=("heat", "diverging"),
                                         doc="The difference view: |A − B| on the heat map, "
                                             "or the signed A − B on the diverging map.")
    frame_budget_ms: float = setting(30.0, kind="float", low=2.0, high=1000.0,
                                     widget="slider", label="Frame budget", unit="ms",
                                     group="Output",
                                     doc="Pipeline work per drawn frame: a change renders "
                                         "over several frames and the window keeps "
                                         "responding (45 ms, or this if more, while no "
                                         "input comes; input brings it back at once).")
    progressive: bool = setting(True, kind="bool", widget="checkbox",
                                label="Show the light converging", group="Output",
                                doc="Show the picture at half resolution after every "
                                    "few propagation steps while it converges (one "
                                    "for a short propagation), instead of only the "
                                    "converged one.")
    follow_view_size: bool = setting(True, kind="bool", widget="checkbox",
                                     label="Render at view size", group="Output",
                                     doc="Render at the View panel's size (times the render "
                                         "scale) instead of a fixed resolution.")
    render_scale: float = setting(1.0, kind="float", low=0.25, high=2.0, widget="slider",
                                  label="Render scale", group="Output",
                                  doc="Render resolution per View panel pixel.")
    mesh_path: str = setting("", kind="text", doc="The path typed in the Scene panel.")
    window_size: tuple[int, int] = setting(
        (1600, 960), kind="size", low=MIN_WINDOW_SIZE, high=MAX_WINDOW_SIZE,
        doc="The window's size in pixels when it was closed (it opens at this size, "
            "shrunk to fit the monitor's work area).")
    inspect: InspectState = setting(kind="nested", nested=InspectState,
                                    default_factory=InspectState,
                                    doc="What the Inspect panel shows.")
    overlays: OverlayState = setting(kind="nested", nested=OverlayState,
                                     default_factory=OverlayState,
                                     doc="What the main view draws in the scene, and the "
                                         "picked point.")
    open_panels: dict[str, bool] = setting(kind="switches", default_factory=dict,
                                           doc="Panel title -> shown.")
    reader_mode: bool = setting(True, kind="bool",
                                doc="Reader's mode: while a lesson step is on screen, only "
                                    "the panels the step uses are shown (the others come "
                                    "back in the explorer mode).")
    compare_overrides: tuple = ()
    """(field, value) pairs in which B also differs from A (a lesson's before | after
    view of a try-this); not persisted."""
    compare_variants: tuple = ()
    """Small multiples' further views after B: per view, the (field, value) pairs in
    which it differs from A (corrections included); not persisted."""
    lesson_id: str | None = None
    lesson_step: int | None = None     # the step `run --lesson ID --step K` opens
    lesson_folder: str | None = None
    """The reader's own lesson folder (``run --lessons DIR``), listed beside the shipped
    course; not persisted."""
    lesson_folder_alone: bool = False
    """List the folder's lessons alone (``run --lessons DIR --no-shipped``)."""
    lesson_session: object | None = None
    """explorer.ui.lesson_panel.LessonSession (named, not imported: it reads this module):
    the course being read, the lesson open, its step, the reader's own screen to come back
    to; made and loaded on first use by ``lesson_panel.session_of``; not persisted."""
    lesson_figures: object | None = None
    """explorer.ui.figures.FigureContext: the lesson figures' shared interactive state
    (``article_numbers.figure_context``); not persisted."""
    layout_panels: list[str] = setting(
        kind="names", default_factory=list,
        doc="Panel titles the saved dock layout was built for; a new panel rebuilds it.")
    plot_tab: str | None = None       # a name in settings.PLOTS: bring that plot's tab forward
    plot_scale: str = setting("auto", kind="choice", choices=("auto", "linear", "log"),
                              doc="Value axis of the flux and audit plots: log when the "
                                  "values span over two decades (auto), or as chosen.")
    plot_relative: bool = setting(False, kind="bool",
                                  doc="Plot flux as shares of the injected flux.")
    messages: list[Message] = field(default_factory=list)
    requests: Requests = field(default_factory=Requests)
    runtime: Runtime = field(default_factory=Runtime)

    def __post_init__(self) -> None:
        validate(self)

    # -- helpers panels use --------------------------------------------------------------
    def notify(self, text: str, level: str = "info") -> None:
        """Show a message in the window (the status line and the Messages panel)."""
        self.messages.append(Message(text, level))
        del self.messages[:-50]

    def set_corrections(self, **switches: bool) -> bool:
        """Switch corrections of A; a combination Settings refuses (in-place propagation
        with 26 neighbours, say) is not applied, as in :meth:`update`."""
        return self.update(corrections=switches)

    def apply_preset(self, name: str, compare: bool = False) -> bool:
        """A correction preset for A, or for B (``compare``); refused as in :meth:`update`
        when A's other settings cannot run with it."""
        return self.set_compare_corrections(name) if compare else \
            self.update(corrections=name)

    def set_compare_corrections(self, corrections: str | Corrections) -> bool:
        """B's corrections (a preset name or a Corrections); refused, with a message, when
        A's other settings cannot run with them (B runs on A's rest)."""
        try:
            self.settings.with_changes(corrections=corrections)
            self.compare_settings = self.compare_settings.with_changes(corrections=corrections)
        except ValueError as exc:
            self.notify(f"not applied to B: {exc}", "error")
            return False
        return True

    def update(self, **changes) -> bool:
        """Change configuration A. B is built from A each frame (see
        ``App.settings_for``), so scene, camera, light and sizes are always shared.

        A combination Settings refuses (e.g. a second bounce without a geometry volume)
        is not applied: the window says why and keeps the settings it had."""
        try:
            self.settings = self.settings.with_changes(**changes)
        except ValueError as exc:
            self.notify(f"not applied: {exc}", "error")
            return False
        return True

    @property
    def comparing(self) -> bool:
        return self.view_mode in COMPARE_MODES

