"""A lesson step's inline figures drawn once: a figure whose inputs did not change is shown
as a picture of its last drawing instead of being drawn again (implot's lobes and meshes
cost a software renderer 5–35 ms a frame, for the same pixels).

A figure is drawn live while the mouse is over it (it answers hovering and dragging), while
it changes by itself (a playback advancing its state as it draws) and until its inputs
were the same two frames in a row (imgui lays a new figure out over a frame or two). The
part of such a settled drawing inside its window, under no popup or hovered item, is
copied from the back buffer into a texture after imgui's lists are rendered
(:meth:`FigureCache.capture`, ``glCopyTexSubImage2D``: queued, nothing read back), and
later frames with the same inputs show that texture over the figure's place. The inputs:
the figure's spec and width, its state's compared fields, the frame results it plots (by
identity), the framebuffer scale, and where it is on screen with its window's clip
rectangle (a page scrolled draws it live, then copies it again). Hovering a figure
forgets its picture (a 3-D view may be turned, which its state does not hold); a new
lesson step releases them all.
"""

from __future__ import annotations

import dataclasses
import math
from collections import Counter
from dataclasses import dataclass
from typing import TYPE_CHECKING

from explorer.ui.texture_versions import versions_for
from explorer.ui.weak_version import WeakVersion

if TYPE_CHECKING:
    import moderngl

    from explorer.ui.figures.host import FigureContext
    from explorer.ui.figures.registry import FigureSpec

GL_TEXTURE_2D = 0x0DE1
Rect = tuple[tuple[float, float], tuple[float, float]]


@dataclass
class _Picture:
    """One figure's texture, the inputs it was drawn with and where."""

    key: tuple
    texture: moderngl.Texture
    size: tuple[float, float]
    """Screen units (imgui's): the figure's rectangle, which the picture keeps free."""
    shown: Rect
    """Screen rectangle of the part copied (what was inside the window)."""
    results: WeakVersion | None = None
    """The frame results it plots, by weak reference: the key names them by identity, and
    a freed result (whose id a later one may take) matches nothing; holding them would
    keep a step's frame (hundreds of MiB at 64³) after the view moved on."""


class FigureCache:
    """The pictures of the figures on the lesson page (module docstring), owned by the
    window (``runtime.services.figure_cache``). ``enabled`` False draws every figure every
    frame (the click tests' engine finds a figure's widgets only when they are drawn)."""

    def __init__(self, ctx: moderngl.Context, enabled: bool = True) -> None:
        self.ctx = ctx
        self._versions = versions_for(ctx)      # every copy and release is told there
        self.enabled = enabled
        self.pictures: dict[str, _Picture] = {}
        self.draws: Counter = Counter()
        """Instance id -> times the figure was drawn live (tests count them)."""
        self.shown: Counter = Counter()
        """Instance id -> times its picture was shown instead."""
        self._last_keys: dict[str, tuple] = {}
        """Instance id -> the inputs it was drawn live with last frame."""
        self._pending: list[tuple[str, tuple, Rect, Rect, WeakVersion]] = []
        """Figures to copy after this frame's rendering: (id, inputs, the figure's screen
        rectangle, the part of it to copy, the results it plotted)."""
        self._page: object = None

    # ------------------------------------------------------------------ drawing
    def draw(self, spec: FigureSpec, width: float, context: FigureContext,
             page: object) -> Rect:
        """Draw ``spec`` at the cursor (:func:`explorer.ui.figures.draw_figure`), or show
        its picture when its inputs are those it was copied with; ``page``: the lesson
        step shown (another object, a reloaded step too, releases every picture). Returns
        the figure's rectangle."""
        from imgui_bundle import imgui

        from explorer.ui.figures import draw_figure

        if page is not self._page:
            self.release()
            self._page = page
        name = spec.instance_id
        start = imgui.get_cursor_screen_pos()
        key = self._key(spec, width, context, (start.x, start.y))
        picture = self.pictures.get(name)
        if picture is not None:
            if _mouse_in(((start.x, start.y), (start.x + picture.size[0],
                                                start.y + picture.size[1]))):
                self._forget(name)           # hovered: live (a 3-D view may turn)
            elif picture.key == key and (picture.results is None
                                         or picture.results.matches(context.results)):
                return self._show(spec, picture, (start.x, start.y))
            else:
                self._forget(name)
        rect = draw_figure(spec, width, context)
        self.draws[name] += 1
        after = self._key(spec, width, context, (start.x, start.y))
        settled = after == key and self._last_keys.get(name) == key
        self._last_keys[name] = after
        visible = _copyable_part(rect) if self.enabled and settled else None
        if visible is not None:
            self._pending.append((name, key, rect, visible,
                                  WeakVersion(tuple(context.results), ())))
        return rect

    def _show(self, spec: FigureSpec, picture: _Picture, at: tuple[float, float]) -> Rect:
        from imgui_bundle import imgui

        imgui.push_id(f"figure:{spec.instance_id}")
        imgui.begin_group()
        low, high = picture.shown
        imgui.get_window_draw_list().add_image(imgui.ImTextureRef(picture.texture.glo), low,
                                               high, (0.0, 1.0), (1.0, 0.0))
        imgui.dummy(picture.size)            # the figure's place, as drawn
        imgui.end_group()
        imgui.pop_id()
        self.shown[spec.instance_id] += 1
        return at, (at[0] + picture.size[0], at[1] + picture.size[1])

    def _key(self, spec: FigureSpec, width: float, context: FigureContext,
             at: tuple[float, float]) -> tuple:
        from imgui_bundle import imgui

        from explorer.ui.figures.registry import FIGURES, USES_RESULTS

        state = context.state_for(spec.instance_id, spec.kind, spec.params,
                                  FIGURES[spec.kind].make_state)
        compared = tuple(getattr(state, field.name) for field in dataclasses.fields(state)
                         if field.compare)
        results = tuple(map(id, context.results)) if spec.kind in USES_RESULTS else ()
        scale = imgui.get_io().display_framebuffer_scale
        draw_list = imgui.get_window_draw_list()
        low, high = draw_list.get_clip_rect_min(), draw_list.get_clip_rect_max()
        return (spec, round(float(width), 2), compared, results, scale.x, scale.y, at,
                (low.x, low.y, high.x, high.y))

    # ------------------------------------------------------------------ copying
    def capture(self, framebuffer_size: tuple[int, int]) -> int:
        """Copy the figures this frame settled from the back buffer (after imgui's lists
        were rendered, before the swap); returns how many were copied."""
        from imgui_bundle import imgui

        from explorer.gl import gpu_sync

        pending, self._pending = self._pending, []
        if not pending:
            return 0
        scale = imgui.get_io().display_framebuffer_scale
        fb_width, fb_height = framebuffer_size
        self.ctx.screen.use()
        copied = 0
        for name, key, ((x0, y0), (x1, y1)), ((v0, w0), (v1, w1)), results in pending:
            left, top = math.ceil(v0 * scale.x), math.ceil(w0 * scale.y)
            right = min(math.floor(v1 * scale.x), fb_width)
            bottom = min(math.floor(w1 * scale.y), fb_height)
            width, height = right - left, bottom - top
            if left < 0 or top < 0 or width <= 0 or height <= 0:
                continue
            texture = self.ctx.texture((width, height), 4, dtype="f1")
            texture.filter = (_nearest(), _nearest())
            texture.use(0)
            gpu_sync.gl().copy_tex_sub_image_2d(GL_TEXTURE_2D, 0, 0, 0, left,
                                                fb_height - bottom, width, height)
            self._forget(name)
            self._versions.written(texture.glo)
            shown = ((left / scale.x, top / scale.y), (right / scale.x, bottom / scale.y))
            self.pictures[name] = _Picture(key, texture, (x1 - x0, y1 - y0), shown, results)
            copied += 1
        return copied

    def _forget(self, name: str) -> None:
        picture = self.pictures.pop(name, None)
        if picture is not None:
            self._versions.forget(picture.texture.glo)
            picture.texture.release()

    def release(self) -> None:
        """Release every picture (a new step, the window closing)."""
        for name in list(self.pictures):
            self._forget(name)
        self._last_keys.clear()
        self._pending.clear()


def _mouse_in(rect: Rect) -> bool:
    from imgui_bundle import imgui

    mouse = imgui.get_mouse_pos()
    (x0, y0), (x1, y1) = rect
    return x0 <= mouse.x <= x1 and y0 <= mouse.y <= y1


def _copyable_part(rect: Rect) -> Rect | None:
    """The part of the figure's rectangle inside its window's clip rectangle, when it may be
    copied: not hovered, and nothing could be drawn over it this frame (a popup, a hovered
    or active item's tooltip); None otherwise or when nothing of it is visible."""
    from imgui_bundle import imgui

    (x0, y0), (x1, y1) = rect
    draw_list = imgui.get_window_draw_list()
    low, high = draw_list.get_clip_rect_min(), draw_list.get_clip_rect_max()
    part = ((max(x0, low.x), max(y0, low.y)), (min(x1, high.x), min(y1, high.y)))
    if part[1][0] - part[0][0] < 1.0 or part[1][1] - part[0][1] < 1.0:
        return None
    if (_mouse_in(rect) or imgui.is_any_item_hovered() or imgui.is_any_item_active()
            or imgui.is_popup_open("", imgui.PopupFlags_.any_popup_id)):
        return None
    return part


def _nearest() -> int:
    import moderngl

    return moderngl.NEAREST
