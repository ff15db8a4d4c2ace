"""The panel list and the default dock layout.

To add a panel, append ``Panel(title, gui_function, area)`` to :data:`PANELS` (or call
:func:`register`); ``area`` names where the default layout docks it: "left", "left-bottom",
"right", "right-bottom", "bottom" or "centre".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from imgui_bundle import imgui
from imgui_bundle.imgui import internal

from explorer.ui.panels.compare import gui_compare
from explorer.ui.panels.corrections import gui_corrections
from explorer.ui.panels.inspect import gui_inspect
from explorer.ui.panels.messages import gui_messages, gui_shaders
from explorer.ui.panels.picked import gui_picked
from explorer.ui.panels.plots import gui_plots
from explorer.ui.panels.scene import gui_scene
from explorer.ui.panels.show_in_scene import gui_show_in_scene
from explorer.ui.panels.view import gui_view
from explorer.ui.lesson_panel import gui_lesson  # the lessons helper's panel
from explorer.ui.state import AppState

AREAS = ("centre", "left", "left-bottom", "right", "right-bottom", "bottom")


@dataclass(frozen=True)
class Panel:
    title: str
    gui: Callable[[AppState], None]
    area: str = "right"
    padding: bool = True      # False: (almost) no margin around the content (the 3D view)


PANELS: list[Panel] = [
    Panel("View", gui_view, "centre", padding=False),
    Panel("Lessons", gui_lesson, "left"),   # first in its dock: the tab shown at start
    Panel("Corrections", gui_corrections, "left"),
    Panel("Scene", gui_scene, "left-bottom"),
    Panel("Compare", gui_compare, "left-bottom"),
    Panel("Show in scene", gui_show_in_scene, "right"),   # first: the tab shown at start
    Panel("Inspect", gui_inspect, "right"),
    Panel("Plots", gui_plots, "right-bottom"),
    Panel("Picked", gui_picked, "right-bottom"),
    Panel("Shaders", gui_shaders, "bottom"),
    Panel("Messages", gui_messages, "bottom"),
]


def register(panel: Panel, before: str | None = None) -> None:
    """Add a panel (e.g. the lessons panel), optionally before the one titled ``before``."""
    if panel.area not in AREAS:
        raise ValueError(f"area must be one of {AREAS}, got {panel.area!r}")
    if any(p.title == panel.title for p in PANELS):
        raise ValueError(f"a panel titled {panel.title!r} exists already")
    titles = [p.title for p in PANELS]
    PANELS.insert(titles.index(before) if before in titles else len(PANELS), panel)


def build_default_layout(dockspace_id: int, size) -> None:
    """Split the dockspace: view in the centre, corrections and scene left, inspect and
    plots right, messages under the view."""
    internal.dock_builder_remove_node(dockspace_id)
    internal.dock_builder_add_node(dockspace_id, imgui.DockNodeFlags_.none
                                   | internal.DockNodeFlagsPrivate_.dock_space)
    internal.dock_builder_set_node_size(dockspace_id, size)
    left, rest = _split(dockspace_id, imgui.Dir.left, 0.27)
    right, centre = _split(rest, imgui.Dir.right, 0.33)
    bottom, centre = _split(centre, imgui.Dir.down, 0.18)
    left_bottom, left = _split(left, imgui.Dir.down, 0.42)
    right_bottom, right = _split(right, imgui.Dir.down, 0.55)
    nodes = {"centre": centre, "left": left, "left-bottom": left_bottom, "right": right,
             "right-bottom": right_bottom, "bottom": bottom}
    for panel in PANELS:
        internal.dock_builder_dock_window(panel.title, nodes[panel.area])
    internal.dock_builder_finish(dockspace_id)


def _split(node: int, direction, ratio: float) -> tuple[int, int]:
    """(new node on ``direction``'s side, the rest)."""
    result = internal.dock_builder_split_node(node, direction, ratio)
    return result.id_at_dir, result.id_at_opposite_dir
