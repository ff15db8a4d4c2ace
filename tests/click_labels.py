"""Which labelled items the window drew on screen in its last frames (a helper of the
click sessions, tests/click_app.py).

The test engine finds an item by its label only when it was drawn unclipped, and a
search that finds nothing costs it about six frames (it waits two, then pans the window
it was given and waits again); a session that scrolls an article page by page to its
Next button paid that on every page. :class:`DrawnLabels` wraps imgui's labelled
widgets (as tests/reader_walk.py does) and notes, per top-level window, the labels of
the items drawn visible and the frame: a search in a child window (the article, the
lesson list) asks the engine only on a page where the label was drawn
(:meth:`Clicks.find`), and asks it on every page again when that finds nothing, so a
widget this does not wrap is still found, only later."""

from __future__ import annotations

LABELLED = ("button", "small_button", "checkbox", "radio_button", "selectable",
            "slider_float", "slider_int", "input_float", "input_int", "input_text",
            "drag_float", "drag_int", "collapsing_header", "menu_item", "menu_item_simple",
            "begin_menu", "begin_tab_item", "tree_node", "combo", "begin_combo",
            "invisible_button", "image_button", "arrow_button")
"""imgui's calls whose first argument is the item's label (or string ID)."""


class DrawnLabels:
    """(top-level window name, label) -> the imgui frame it was last drawn visible in."""

    def __init__(self) -> None:
        self.drawn: dict[tuple[str, str], int] = {}

    def install(self) -> None:
        """Wrap the calls (for the rest of the process: a session is a child of its own)."""
        from imgui_bundle import imgui

        for name in LABELLED:
            if hasattr(imgui, name):
                self._wrap(imgui, name)

    def _wrap(self, imgui, name: str) -> None:
        original, drawn = getattr(imgui, name), self.drawn
        internal = imgui.internal

        def call(*args, **kwargs):
            result = original(*args, **kwargs)
            label = args[0] if args else kwargs.get("label", kwargs.get("str_id"))
            if isinstance(label, str) and imgui.is_item_visible():
                window = internal.get_current_window()
                root = window.root_window if window is not None else None
                if root is not None:
                    drawn[(root.name, label)] = imgui.get_frame_count()
            return result
        setattr(imgui, name, call)

    def seen(self, window: str, label: str) -> bool:
        """Whether ``label`` (as a test engine reference segment: "/" escaped) was drawn
        visible in the top-level window named ``window`` in this frame or the one before."""
        from imgui_bundle import imgui

        frame = self.drawn.get((window, label.replace("\\/", "/")))
        return frame is not None and frame >= imgui.get_frame_count() - 1
