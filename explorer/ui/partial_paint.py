"""imgui's draw lists painted only where they changed.

A software renderer fills about half a million pixels a millisecond on two cores: imgui's
lists over a 1600×960 window cost it 8–9 ms a frame (BENCHMARKS.md, issue #32 item 3),
while a display-only change alters only the view's rectangle. :class:`PartialPainter`
compares the frame's draw lists with the last painted ones (:mod:`explorer.ui.drawn_lists`)
and, for each changed rectangle, clears it and renders every list clipped to it: the
pixels there come out as a whole repaint would make them, and those outside keep theirs.

That needs a surface that still holds the last frame. The window's back buffer does when
its swap copies it to the window: Mesa's software rasteriser on X11 swaps by copying its
back buffer into the window (XPutImage), though GLX reports the swap method as undefined,
so on a software renderer :func:`back_buffer_kept` probes it once, drawing three frames in
shades of the clear colour nobody can tell apart. A GPU driver may flip buffers, and may
start to flip later (a window going full screen, a compositor), so there the lists are
always painted into a framebuffer of the painter's own (the *canvas*), which is copied to
the back buffer every frame: one copy of the window, which a GPU makes in microseconds
(a 1600×960 copy costs llvmpipe 3.3 ms, which is why it keeps the back buffer instead).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from explorer.lpv.timing import is_software_renderer
from explorer.ui import drawn_lists
from explorer.ui.drawn_lists import DrawnFrame, Rect
from explorer.ui.texture_versions import versions_for

if TYPE_CHECKING:
    import moderngl

    from explorer.gl.window import Window


class PartialPainter:
    """Paints a window's imgui frames where they changed (module docstring).

    ``enabled`` False: every frame is painted whole, straight into the back buffer (as
    before this painter existed: a diagnosis, ``--repaint-all``)."""

    def __init__(self, window: Window, enabled: bool = True) -> None:
        self.window = window
        self.enabled = enabled
        self.kept: bool | None = None
        """The back buffer holds the last frame after a swap (on a software renderer,
        probed at the first paint; elsewhere False: the canvas)."""
        self.painted: list[Rect] = []
        """The rectangles the last paint repainted."""
        self.painted_share = 1.0
        """Their share of the window's pixels."""
        self.whole_because: str | None = "not painted yet"
        """Why the last paint painted the whole window (None: it painted a part)."""
        self._last: DrawnFrame | None = None
        self._canvas: moderngl.Framebuffer | None = None

    def paint(self, ctx: moderngl.Context, draw_data, clear_colour: tuple[float, ...],
              whole: bool = False) -> None:
        """Paint ``draw_data`` (imgui's, after ``imgui.render()``) over the clear colour;
        the back buffer holds the whole frame afterwards. ``whole``: every pixel, into the
        same surface (what a partial paint is checked against)."""
        from imgui_bundle import imgui

        size = drawn_lists.framebuffer_size(draw_data)
        if not self.enabled or size[0] <= 0 or size[1] <= 0:
            self._paint_whole(ctx, ctx.screen, draw_data, clear_colour, size)
            self.whole_because = "partial painting is off"
            return
        if self.kept is None:
            self.kept = is_software_renderer(ctx) and back_buffer_kept(self.window, ctx,
                                                                       clear_colour)
        frame = drawn_lists.drawn_frame(draw_data, versions_for(ctx),
                                        int(imgui.ImTextureStatus.ok), self._last)
        target = ctx.screen if self.kept else self._canvas_of(ctx, size)
        rects = "asked for" if whole else drawn_lists.merged(
            drawn_lists.damage(self._last, frame), size)
        if isinstance(rects, str):
            self._paint_whole(ctx, target, draw_data, clear_colour, size)
            self.whole_because = rects
        else:
            self.whole_because = None
            for rect in rects:
                _paint_within(target, draw_data, clear_colour, rect, size)
            self.painted = rects
            self.painted_share = (sum(drawn_lists.area(rect) for rect in rects)
                                  / (size[0] * size[1]))
        if target is not ctx.screen:
            ctx.copy_framebuffer(ctx.screen, target)
        ctx.screen.use()
        ctx.viewport = (0, 0, size[0], size[1])
        self._last = frame

    def release(self) -> None:
        if self._canvas is not None:
            for attachment in self._canvas.color_attachments:
                attachment.release()
            self._canvas.release()
            self._canvas = None
        self._last = None

    def _paint_whole(self, ctx: moderngl.Context, target, draw_data,
                     clear_colour: tuple[float, ...], size: tuple[int, int]) -> None:
        from imgui_bundle import imgui

        target.use()
        ctx.viewport = (0, 0, size[0], size[1])
        target.clear(*clear_colour)
        imgui.backends.opengl3_render_draw_data(draw_data)
        self.painted = [(0, 0, size[0], size[1])]
        self.painted_share = 1.0

    def _canvas_of(self, ctx: moderngl.Context, size: tuple[int, int]):
        """The painter's own framebuffer at the window's size (made anew on a resize,
        when :func:`drawn_lists.damage` repaints everything anyway)."""
        if self._canvas is None or self._canvas.size != size:
            self.release()
            self._canvas = ctx.framebuffer(color_attachments=[ctx.renderbuffer(size, 4)])
        return self._canvas


def _paint_within(target, draw_data, clear_colour: tuple[float, ...], rect: Rect,
                  size: tuple[int, int]) -> None:
    """Clear ``rect`` and render every command clipped to it: each command's clip
    rectangle is replaced, for this render, by one whose scissor is its own scissor within
    ``rect`` (:func:`drawn_lists.clip_for`), then put back."""
    from imgui_bundle import imgui

    origin = drawn_lists.origin_of(draw_data)
    target.use()
    target.clear(*clear_colour, viewport=(rect[0], rect[1], rect[2] - rect[0],
                                          rect[3] - rect[1]))
    saved = []
    for draw_list in draw_data.cmd_lists:
        for index in range(draw_list.cmd_buffer.size()):
            command = draw_list.cmd_buffer[index]
            clip = command.clip_rect
            clip = (clip.x, clip.y, clip.z, clip.w)
            saved.append((command, clip))
            within = drawn_lists.intersect(drawn_lists.scissor(clip, origin, size), rect)
            command.clip_rect = imgui.ImVec4(*drawn_lists.clip_for(within, origin, size))
    try:
        imgui.backends.opengl3_render_draw_data(draw_data)
    finally:
        for command, clip in saved:
            command.clip_rect = imgui.ImVec4(*clip)


PROBE_SHADES = (1, 2, 3)
"""The probe's frames: the clear colour's blue raised by this many 1/255 steps."""


def back_buffer_kept(window: Window, ctx: moderngl.Context,
                     clear_colour: tuple[float, ...]) -> bool:
    """Whether a swap leaves the back buffer holding the frame it showed (a copy, not an
    exchange): three frames, the first cleared whole to one shade, the next two each a
    corner in another; after them the back buffer holds all three shades only if every
    swap kept it. Read once, at the window's first paint (not inside a frame after it)."""
    width, height = window.framebuffer_size
    if width < 4 or height < 4:
        return False
    # whole steps of 1/255, so that no shade's conversion to 8 bits falls on a tie
    red, green, blue = (round(channel * 255.0) for channel in clear_colour[:3])
    blue = min(blue, 255 - max(PROBE_SHADES))
    shades = [(red / 255.0, green / 255.0, (blue + step) / 255.0, 1.0) for step in PROBE_SHADES]
    corners = [None, (0, 0, 1, 1), (width - 1, height - 1, 1, 1)]
    ctx.screen.use()
    for shade, corner in zip(shades, corners):
        ctx.screen.clear(*shade, viewport=corner)
        window.swap_buffers()
    pixels = window.read_pixels()              # (H, W, 3), top row first
    seen = [pixels[height // 2, width // 2], pixels[height - 1, 0], pixels[0, width - 1]]
    expected = [[red, green, blue + step] for step in PROBE_SHADES]
    return all(list(map(int, got)) == want for got, want in zip(seen, expected))
