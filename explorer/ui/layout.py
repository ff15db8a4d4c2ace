"""The panel list and the default dock layout.

To add a panel, append ``Panel(title, gui_function, area)`` to :data:`PANELS` (or call
:func:`register`); ``area`` names where the default layout docks it: "article" (the
lesson column, which holds the Lesson panel alone), "left", "left-bottom", "right",
"right-bottom", "bottom" or "centre".

The default layout reads like an explorable article: the lesson column on the left, the
3D view beside it (the view answers every control in the text), the tool panels in a
column on the right ("left"/"left-bottom" panels at its top, "right" in the middle,
"right-bottom" at the bottom) and the messages under the view. Column widths follow the
window's width (:func:`column_widths`), from 1280×720 up.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from imgui_bundle import imgui
from imgui_bundle.imgui import internal

from explorer.ui.article import gui_article
from explorer.ui.panels.compare import gui_compare
from explorer.ui.panels.corrections import gui_corrections
from explorer.ui.panels.error import gui_error
from explorer.ui.panels.inspect import gui_inspect
from explorer.ui.panels.lights import gui_lights
from explorer.ui.panels.messages import gui_messages, gui_shaders
from explorer.ui.panels.picked import gui_picked
from explorer.ui.panels.plots import gui_plots
from explorer.ui.panels.scene import gui_scene
from explorer.ui.panels.show_in_scene import gui_show_in_scene
from explorer.ui.panels.view import gui_view
from explorer.ui.state import AppState

AREAS = ("centre", "article", "left", "left-bottom", "right", "right-bottom", "bottom")
ARTICLE_CLASS = 0x4C455353
"""imgui window class of the Lesson panel: windows of other classes cannot dock into its
node (no tabs), and it cannot be tabbed into theirs."""


@dataclass(frozen=True)
class Panel:
    title: str
    gui: Callable[[AppState], None]
    area: str = "right"
    padding: bool = True      # False: (almost) no margin around the content (the 3D view)
    window_class: int = 0     # nonzero: a dock of its own (see ARTICLE_CLASS)


PANELS: list[Panel] = [
    Panel("View", gui_view, "centre", padding=False),
    Panel("Lesson", gui_article, "article", window_class=ARTICLE_CLASS),
    Panel("Corrections", gui_corrections, "left"),
    Panel("Scene", gui_scene, "left-bottom"),
    Panel("Lights & objects", gui_lights, "left-bottom"),
    Panel("Show in scene", gui_show_in_scene, "right"),   # first: the tab shown at start
    Panel("Inspect", gui_inspect, "right"),
    Panel("Compare", gui_compare, "right"),   # not a fourth tab beside Corrections: cut
    Panel("Plots", gui_plots, "right-bottom"),
    Panel("Picked", gui_picked, "right-bottom"),
    Panel("Error", gui_error, "right-bottom"),
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


def column_widths(width: float) -> tuple[float, float]:
    """(article, tool column) widths in pixels for a window ``width`` wide: the article
    about a third, never narrower than a readable column nor wider than a long line; the
    rest goes to the 3D view. In a window narrower than 1280 px the two columns shrink
    together so that the view keeps :data:`VIEW_SHARE` of the width (a squeezed view
    answers no control visibly)."""
    article = min(max(0.36 * width, 400.0), 700.0)
    tools = min(max(0.24 * width, 290.0), 480.0)
    most = (1.0 - VIEW_SHARE) * width
    if article + tools > most:
        shrink = most / (article + tools)
        article, tools = article * shrink, tools * shrink
    return article, tools


VIEW_SHARE = 0.4
"""The smallest share of the window's width the default layout leaves to the 3D view."""

PLOT_ROW_MIN_PX = 300.0
"""The tool column's bottom row (plots, Picked, Error) needs about this much height for a
readable plot (its tab bar, axis choices and seven labelled bars) or the Error panel's
three images."""


def tool_rows(height: float) -> tuple[float, float]:
    """(top, bottom) heights in pixels of the tool column's first and last rows in a
    dockspace ``height`` tall; the middle row (Show in scene, Inspect) gets the rest.

    Tall windows split the column about 36/32/32. Short ones (720 px) keep the bottom row
    at :data:`PLOT_ROW_MIN_PX`, at most 45 % of the column, and give the top row (the
    corrections, which scroll) a little over half of what is left."""
    bottom = max(0.32 * height, min(PLOT_ROW_MIN_PX, 0.45 * height))
    top = min(0.36 * height, 0.53 * (height - bottom))
    return top, bottom


def window_class(panel: Panel):
    """The imgui window class a panel with ``window_class`` is begun with."""
    klass = imgui.WindowClass()
    klass.class_id = panel.window_class
    klass.docking_allow_unclassed = False
    return klass


def build_default_layout(dockspace_id: int, size) -> None:
    """Split the dockspace: the lesson column left, the view in the centre with the
    messages under it, the tool panels in three rows on the right."""
    internal.dock_builder_remove_node(dockspace_id)
    internal.dock_builder_add_node(dockspace_id, imgui.DockNodeFlags_.none
                                   | internal.DockNodeFlagsPrivate_.dock_space)
    internal.dock_builder_set_node_size(dockspace_id, size)
    article_px, tools_px = column_widths(float(size.x))
    article, rest = _split(dockspace_id, imgui.Dir.left, article_px / float(size.x))
    tools, centre = _split(rest, imgui.Dir.right, tools_px / max(float(size.x) - article_px,
                                                                 1.0))
    bottom, centre = _split(centre, imgui.Dir.down, 0.16)
    height = max(float(size.y), 1.0)
    top_px, bottom_px = tool_rows(height)
    tools_top, tools_rest = _split(tools, imgui.Dir.up, top_px / height)
    tools_bottom, tools_middle = _split(tools_rest, imgui.Dir.down,
                                        bottom_px / max(height - top_px, 1.0))
    nodes = {"centre": centre, "article": article, "left": tools_top,
             "left-bottom": tools_top, "right": tools_middle, "right-bottom": tools_bottom,
             "bottom": bottom}
    for panel in PANELS:
        internal.dock_builder_dock_window(panel.title, nodes[panel.area])
    node = internal.dock_builder_get_node(article)
    if node is not None:
        node.set_local_flags(node.local_flags | internal.DockNodeFlagsPrivate_.no_docking_over_me
                             | internal.DockNodeFlagsPrivate_.no_window_menu_button)
    # the tool column's tab bars keep the room of the window menu button for their titles
    # (three tabs fit whole at 1280 px); the Windows menu opens and closes panels
    for tool in (tools_top, tools_middle, tools_bottom):
        node = internal.dock_builder_get_node(tool)
        if node is not None:
            node.set_local_flags(node.local_flags
                                 | internal.DockNodeFlagsPrivate_.no_window_menu_button)
    internal.dock_builder_finish(dockspace_id)


def _split(node: int, direction, ratio: float) -> tuple[int, int]:
    """(new node on ``direction``'s side, the rest)."""
    result = internal.dock_builder_split_node(node, direction, ratio)
    return result.id_at_dir, result.id_at_opposite_dir
