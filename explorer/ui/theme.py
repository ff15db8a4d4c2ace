"""The window's look, shared by the explorer and the one-figure window: colours and the
markdown context (fonts: explorer/ui/fonts.py)."""

from __future__ import annotations

import sys
from pathlib import Path

WINDOW_BG = (0.11, 0.115, 0.13, 1.0)
"""A panel's background."""
CLEAR_COLOUR = WINDOW_BG
"""What each frame is cleared to: the docked panels' background (they draw none of their
own, explorer/ui/window_panels.py ``WindowPanels.draw``)."""
DOCKED_WINDOW_BG = WINDOW_BG[:3] + (0.0,)
"""A docked panel's background colour: transparent, which imgui does not draw."""


def apply_style(scale: float) -> None:
    from imgui_bundle import imgui

    imgui.style_colors_dark()
    style = imgui.get_style()
    style.window_rounding = 4.0
    style.frame_rounding = 3.0
    style.grab_rounding = 3.0
    style.tab_rounding = 3.0
    style.window_border_size = 1.0
    style.frame_padding = (6.0, 4.0)
    style.item_spacing = (8.0, 6.0)
    style.scrollbar_size = 12.0
    colours = {
        imgui.Col_.window_bg: WINDOW_BG,
        imgui.Col_.title_bg: (0.09, 0.095, 0.11, 1.0),
        imgui.Col_.title_bg_active: (0.13, 0.20, 0.32, 1.0),
        imgui.Col_.frame_bg: (0.17, 0.18, 0.21, 1.0),
        imgui.Col_.header: (0.20, 0.32, 0.50, 0.6),
        imgui.Col_.check_mark: (0.45, 0.72, 1.0, 1.0),
        imgui.Col_.slider_grab: (0.40, 0.62, 0.95, 1.0),
        imgui.Col_.tab_selected: (0.20, 0.36, 0.58, 1.0),
        imgui.Col_.docking_empty_bg: (0.07, 0.075, 0.085, 1.0),
    }
    for index, rgba in colours.items():
        style.set_color_(index, imgui.ImVec4(*rgba))
    if scale != 1.0:
        style.scale_all_sizes(scale)
        style.font_scale_dpi = scale


def markdown_context():
    """A rich_md (imgui_md) context reading its fonts from imgui_bundle's assets, or None
    when markdown cannot be rendered here (panels then fall back to wrapped text)."""
    try:
        import imgui_bundle
        from imgui_bundle import rich_md

        rich_md.set_assets_folder(str(Path(imgui_bundle.__file__).parent / "assets"))
        return rich_md.create_context()
    except Exception as exc:  # noqa: BLE001 - markdown is optional
        print(f"lpv-explorer: markdown unavailable: {exc}", file=sys.stderr)
        return None
