"""The one app-state object every panel reads and writes.

Panels are functions ``gui_<panel>(state: AppState)``. They change :class:`AppState`
(mostly by replacing the immutable :class:`~explorer.lpv.settings.Settings`) and post
requests; the app loop turns those into pipeline runs, screenshots and file loads. What
the pipeline produced comes back in :attr:`AppState.runtime` (results, texture ids), which
is never persisted.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from explorer.lpv.settings import PRESETS, Settings

VIEW_MODES = ("single", "split", "difference")
"""single: configuration A; split: A left | B right with a draggable divider;
difference: false-colour |A − B| with a scale bar."""

VIEW_BUFFERS = ("final", "direct", "indirect", "albedo")
"""What the 3D view shows (the first names of settings.VIEWS): the pipeline's final image,
or one FrameResult buffer tonemapped at the current exposure."""

INSPECT_SOURCES = (
    "rsm-position", "rsm-normal", "rsm-flux",   # RSM buffers
    "grid-slice",                               # accumulated grid acc_N, one z slice
    "propagation",                              # grid_t at a chosen iteration t
    "geometry-volume",                          # occlusion grid, one z slice
    "vpls",                                     # the injected VPLs as 3D points
)
GRID_COMPONENTS = ("intensity", "sh0", "sh1", "sh2", "sh3")
"""What a grid slice shows: the intensity evaluated in a chosen direction (rgb), or one SH
coefficient (rgb of that coefficient, signed)."""


@dataclass
class InspectState:
    source: str = "rsm-flux"
    slice_z: int = -1                 # -1 = the middle slice
    component: str = "intensity"
    direction_azimuth: float = 0.0    # degrees; direction of evaluation for "intensity"
    direction_elevation: float = 90.0
    iteration: int = 0                # for "propagation"
    playing: bool = False
    play_rate: float = 4.0            # iterations per second while playing
    signed_scale: float = 0.0         # 0 = automatic scaling of signed data
    glyphs: bool = False              # draw SH glyphs over grid slices
    cascade: int = 0                  # which cascade grid-slice / geometry-volume show


@dataclass
class Message:
    text: str
    level: str = "info"               # "info" | "warning" | "error"
    created: float = field(default_factory=time.monotonic)


@dataclass
class Runtime:
    """What the app loop hands to the panels each frame. Not persisted."""

    result: Any = None                # FrameResult of configuration A
    compare_result: Any = None        # FrameResult of configuration B (compare views)
    final_texture_id: int = 0         # GL name of Pipeline.final_texture (A)
    compare_texture_id: int = 0       # GL name of the second pipeline's final texture (B)
    textures: Any = None              # explorer.ui.textures.UiTextures (UI-owned textures)
    formulas: Any = None              # explorer.ui.formulas.FormulaCache
    markdown_ready: bool = False      # imgui_bundle.rich_md can render (lesson text)
    pipeline_error: str | None = None
    gl_problem: str | None = None
    shader_errors: dict[str, str] = field(default_factory=dict)
    camera_default: tuple | None = None   # the scene's (eye, target) once known
    light_default: tuple | None = None    # the scene's (position, target) once known
    light_flux_default: float | None = None
    light_cone_default: tuple | None = None   # the scene spot's (inner, outer) cone, degrees
    light_is_spot: bool = True                # False for a directional light (no cone)
    scene_bounds: tuple | None = None
    frame_ms: float = 0.0
    pipeline_ms: float = 0.0
    view_size: tuple[int, int] = (0, 0)   # pixels the 3D view panel offers
    view_rect: tuple | None = None        # (x0, y0, x1, y1) framebuffer pixels of the image
    frame_index: int = 0
    file_dialog: Any = None               # a pending portable_file_dialogs.open_file
    file_dialog_available: bool | None = None
    split_dragging: bool = False          # the split view's divider is held
    difference_cache: tuple | None = None  # (version, texture id, scale top)
    inspect_cache: tuple | None = None     # (version, texture id, scale top, caption)
    auto_exposure: tuple[float, float] = (1.0, 1.0)   # per side, from the last results
    play_clock: float = 0.0               # fractional iterations while playing
    vpl_cache: tuple | None = None        # (result id, point groups) for the VPL plot


@dataclass
class Requests:
    """Things a panel asks of the app loop, handled after the panels ran."""

    screenshot: Path | None = None
    open_scene: str | None = None
    reset_layout: bool = False
    open_file_dialog: bool = False
    focus_panel: str | None = None    # bring this panel's tab to the front
    quit: bool = False


@dataclass
class AppState:
    settings: Settings = field(default_factory=Settings)
    compare_settings: Settings = field(  # configuration B: only its corrections are used
        default_factory=lambda: Settings(corrections=PRESETS["original"]))
    view_mode: str = "single"
    view_buffer: str = "final"
    split_position: float = 0.5       # divider, fraction of the view width
    auto_exposure: bool = False       # expose each side of a comparison on its own
    difference_scale: float = 0.0     # watts per pixel at the top of the scale; 0 = auto
    render_scale: float = 1.0         # render resolution / view panel pixels
    follow_view_size: bool = True     # render at the view panel's size
    mesh_path: str = ""
    window_size: tuple[int, int] = (1600, 960)
    inspect: InspectState = field(default_factory=InspectState)
    open_panels: dict[str, bool] = field(default_factory=dict)
    lesson_id: str | None = None
    layout_panels: list[str] = field(default_factory=list)
    """Panel titles the saved dock layout was built for; a new panel rebuilds it."""
    plot_tab: str | None = None       # a name in settings.PLOTS: bring that plot's tab forward
    messages: list[Message] = field(default_factory=list)
    requests: Requests = field(default_factory=Requests)
    runtime: Runtime = field(default_factory=Runtime)

    # -- helpers panels use --------------------------------------------------------------
    def notify(self, text: str, level: str = "info") -> None:
        """Show a message in the window (the status line and the Messages panel)."""
        self.messages.append(Message(text, level))
        del self.messages[:-50]

    def set_corrections(self, **switches: bool) -> None:
        self.settings = self.settings.with_changes(corrections=switches)

    def apply_preset(self, name: str, compare: bool = False) -> None:
        if compare:
            self.compare_settings = self.compare_settings.with_changes(corrections=name)
        else:
            self.settings = self.settings.with_changes(corrections=name)

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
        return self.view_mode in ("split", "difference")

