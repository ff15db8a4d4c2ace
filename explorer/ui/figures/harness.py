"""One figure alone in a glfw window: for looking at it, for tests and for screenshots.

The window is made like the app's (:class:`explorer.gl.window.Window`, imgui with implot
and implot3d, the app's style and font) and shows a single full-window imgui pane with the
figure at the given width::

    with FigureWindow(900, 700, visible=False) as win:
        spec = make_figure("clamped-cosine", normal_deg=45)
        pixels = win.render(spec, frames=3)      # (H, W, 3) of the figure's rectangle
        win.screenshot("cosine.png")             # the whole window

With ``cached`` the figure goes through the window's figure cache
(explorer/ui/figure_cache.py), as a lesson page's figures do: :attr:`cache` counts its
live drawings and the frames shown from its picture.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from explorer.gl.window import Window
from explorer.ui.figures.host import FigureContext
from explorer.ui.figures.registry import FigureSpec, draw_figure

_PADDING = 16.0


class FigureWindow:
    def __init__(self, width: int = 900, height: int = 700, visible: bool = True,
                 context: FigureContext | None = None, scale: float = 1.0,
                 headless: bool = False, cached: bool = False) -> None:
        """``scale``: draw the figure's sizes and fonts this many times larger (2 for the
        web site's 2× images); ``headless``: no display (glfw's null platform, EGL);
        ``cached``: draw through a :class:`~explorer.ui.figure_cache.FigureCache`."""
        from imgui_bundle import imgui

        from explorer.ui import fonts, theme
        from explorer.ui.imgui_host import ImguiHost

        self.window = Window(width, height, title="lpv-explorer figure", visible=visible,
                             vsync=False, headless=headless)
        self.ctx = self.window.ctx
        self.context = context or FigureContext()
        self.scale = float(scale)
        self._imgui = ImguiHost(self.window)
        imgui.get_io().set_ini_filename("")
        theme.apply_style(self.window.content_scale * scale)
        fonts.load(imgui.get_io(), 15.0)
        self._imgui.start_backends()
        self.rect: tuple[tuple[float, float], tuple[float, float]] | None = None
        """Screen rectangle (pixels) of the figure drawn last."""
        self.drawn_right: float | None = None
        """Right edge (screen pixels) of everything the figure drawn last submitted: past
        ``rect``'s left edge + the width asked for, the figure overflows its column."""
        self.last_pixels: np.ndarray | None = None
        self.cache = None
        """The figure cache (``cached``), else None."""
        if cached:
            from explorer.ui.figure_cache import FigureCache

            self.cache = FigureCache(self.ctx)
        self.page: object = self
        """What the cache takes as the page shown (another object releases its pictures)."""

    def __enter__(self) -> FigureWindow:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def frame(self, spec: FigureSpec, figure_width: float | None = None,
              capture: bool = False) -> bool:
        """Draw one frame with ``spec``; False once the window should close."""
        from imgui_bundle import imgui

        from explorer.ui.theme import CLEAR_COLOUR

        self.window.poll_events()
        if self.window.should_close():
            return False
        self._imgui.new_frame()
        viewport = imgui.get_main_viewport()
        imgui.set_next_window_pos(viewport.pos)
        imgui.set_next_window_size(viewport.size)
        flags = (imgui.WindowFlags_.no_decoration | imgui.WindowFlags_.no_move
                 | imgui.WindowFlags_.no_saved_settings
                 | imgui.WindowFlags_.no_bring_to_front_on_focus)
        pad = _PADDING * self.scale
        imgui.push_style_var(imgui.StyleVar_.window_padding, (pad, pad))
        imgui.begin("figure", None, flags)
        imgui.pop_style_var()
        width = figure_width or imgui.get_content_region_avail().x
        if self.cache is None:
            self.rect = draw_figure(spec, width, self.context)
        else:
            self.rect = self.cache.draw(spec, width, self.context, self.page)
        self.drawn_right = imgui.get_item_rect_max().x     # the figure's group, unpadded
        imgui.end()
        self._imgui.render(self.ctx, CLEAR_COLOUR)
        if self.cache is not None:
            self.cache.capture(self.window.framebuffer_size)
        if capture:
            self.last_pixels = self.window.read_pixels()
        self.window.swap_buffers()
        return True

    def render(self, spec: FigureSpec, frames: int = 3,
               figure_width: float | None = None) -> np.ndarray:
        """Draw ``frames`` frames (imgui lays out over the first ones) and return the
        pixels of the figure's rectangle, (h, w, 3) uint8."""
        for index in range(max(int(frames), 1)):
            self.frame(spec, figure_width, capture=index == frames - 1)
        return self.figure_pixels()

    def figure_pixels(self) -> np.ndarray:
        if self.last_pixels is None or self.rect is None:
            raise RuntimeError("no frame captured yet")
        from imgui_bundle import imgui

        scale = imgui.get_io().display_framebuffer_scale
        (x0, y0), (x1, y1) = self.rect
        h, w = self.last_pixels.shape[:2]
        cols = slice(max(int(x0 * scale.x), 0), min(int(np.ceil(x1 * scale.x)), w))
        rows = slice(max(int(y0 * scale.y), 0), min(int(np.ceil(y1 * scale.y)), h))
        return self.last_pixels[rows, cols]

    def screenshot(self, path: str | Path) -> Path:
        """Write the last captured frame (the whole window) as a PNG."""
        from explorer.ui.images import write_png

        if self.last_pixels is None:
            raise RuntimeError("no frame captured yet")
        write_png(self.last_pixels, path)
        return Path(path)

    def close(self) -> None:
        if self.window.handle is None:
            return
        if self.cache is not None:
            self.cache.release()
        self._imgui.shutdown()
        self.window.close()


def pipeline_results(ctx, settings: list) -> tuple:
    """FrameResults of the LPV pipeline for each Settings, run on the window's context
    (what the audit figures plot, when no app supplies them)."""
    from explorer.lpv.pipeline import Pipeline

    results = []
    for one in settings:
        pipeline = Pipeline(one, ctx=ctx)
        try:
            results.append(pipeline.run(one))
        finally:
            pipeline.release()
            ctx.screen.use()
    return tuple(results)
