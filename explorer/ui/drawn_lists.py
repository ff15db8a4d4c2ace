"""What imgui's draw lists changed since the last painted frame, in framebuffer pixels.

A frame's draw data is reduced to a :class:`DrawnFrame`: per draw list (one per imgui
window, in painting order) its vertex and index bytes, its commands, and the pixels its
commands may touch (their scissor rectangles, computed exactly as imgui's OpenGL 3 backend
computes them). :func:`damage` compares two frames: a pixel outside every rectangle it
returns is covered by the same primitives, in the same order, sampling the same texture
content, in both frames, so it keeps its colour (OpenGL's invariance rules make a
fragment's colour independent of the scissor: Appendix A of the GL 4.6 specification).
:func:`merged` turns those rectangles into the few the painter repaints
(:mod:`explorer.ui.partial_paint`).

Rectangles are ``(x0, y0, x1, y1)`` integer framebuffer pixels, y up from the bottom row
(OpenGL's window coordinates), x1 and y1 exclusive.
"""

from __future__ import annotations

import ctypes
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from explorer.ui.texture_versions import TextureVersions

Rect = tuple[int, int, int, int]

VERTEX_BYTES = 20
"""sizeof(ImDrawVert): position and uv as two float pairs, a packed RGBA colour."""
INDEX_BYTES = 4
"""sizeof(ImDrawIdx) in imgui_bundle's build (32-bit indices;
tests/ui/test_partial_paint.py reads a real frame's buffers to hold both sizes)."""

MAX_RECTS = 4
"""Repainted rectangles at most: the lists are rendered once per rectangle."""
FULL_SHARE = 0.7
"""Past this share of the window repainted in rectangles, the whole window is painted."""


@dataclass(frozen=True)
class DrawnList:
    """One draw list as painted."""

    name: str
    content: bytes
    """Its vertex bytes, then its index bytes."""
    commands: tuple
    """Per command: clip rectangle, texture, the texture's version, offsets, count."""
    footprint: Rect | None
    """The bounding box of its commands' scissors (None: it paints nothing)."""
    live: tuple[Rect, ...]
    """Scissors of its commands that sample a texture nobody tracks (repainted always)."""


@dataclass(frozen=True)
class DrawnFrame:
    """A frame's draw data as :func:`damage` compares it."""

    size: tuple[int, int]
    """The framebuffer's width and height."""
    origin: tuple[float, float, float, float]
    """imgui's display position and framebuffer scale (x, y, sx, sy)."""
    lists: tuple[DrawnList, ...]
    settled: bool
    """imgui's own textures (the font atlas) need no upload or update this frame."""


def origin_of(draw_data) -> tuple[float, float, float, float]:
    """imgui's display position and framebuffer scale as (x, y, sx, sy)."""
    scale, pos = draw_data.framebuffer_scale, draw_data.display_pos
    return (float(pos.x), float(pos.y), float(scale.x), float(scale.y))


def vertex_box(vertex_bytes: bytes, origin: tuple[float, float, float, float],
               size: tuple[int, int]) -> Rect | None:
    """The pixels whose centres the triangles of these ImDrawVerts can cover (a pixel is
    drawn when its centre is inside a triangle, so within the vertices' box), a pixel
    wider on each side."""
    if not vertex_bytes:
        return None
    rows = np.frombuffer(vertex_bytes, np.float32).reshape(-1, VERTEX_BYTES // 4)
    ox, oy, sx, sy = origin
    low, high = rows[:, :2].min(axis=0), rows[:, :2].max(axis=0)
    x0, x1 = (float(low[0]) - ox) * sx, (float(high[0]) - ox) * sx
    y0, y1 = size[1] - (float(high[1]) - oy) * sy, size[1] - (float(low[1]) - oy) * sy
    return intersect((math.floor(x0) - 1, math.floor(y0) - 1, math.ceil(x1) + 1,
                      math.ceil(y1) + 1), (0, 0, size[0], size[1]))


def framebuffer_size(draw_data) -> tuple[int, int]:
    """The backend's ``(int)(DisplaySize * FramebufferScale)``, in single precision."""
    size, scale = draw_data.display_size, draw_data.framebuffer_scale
    return (int(np.float32(size.x) * np.float32(scale.x)),
            int(np.float32(size.y) * np.float32(scale.y)))


def scissor(clip: tuple[float, float, float, float], origin: tuple[float, float, float, float],
            size: tuple[int, int]) -> Rect | None:
    """The pixels a command with clip rectangle ``clip`` (imgui's coordinates) may touch:
    the backend's ``glScissor`` arguments (imgui_impl_opengl3.cpp, RenderDrawData:
    ``clip_min = (ClipRect.xy - DisplayPos) * FramebufferScale``, y flipped by the
    framebuffer height, truncated to int) in single precision as the backend computes
    them, clamped to the framebuffer. None: the backend skips the command."""
    f = np.float32
    ox, oy, sx, sy = (f(v) for v in origin)
    x0, y0 = (f(clip[0]) - ox) * sx, (f(clip[1]) - oy) * sy
    x1, y1 = (f(clip[2]) - ox) * sx, (f(clip[3]) - oy) * sy
    if x1 <= x0 or y1 <= y0:
        return None
    left, bottom = int(x0), int(f(size[1]) - y1)
    right, top = left + int(x1 - x0), bottom + int(y1 - y0)
    rect = (max(left, 0), max(bottom, 0), min(right, size[0]), min(top, size[1]))
    return rect if rect[0] < rect[2] and rect[1] < rect[3] else None


def clip_for(rect: Rect | None, origin: tuple[float, float, float, float],
             size: tuple[int, int]) -> tuple[float, float, float, float]:
    """A clip rectangle (imgui's coordinates) for which the backend's scissor is exactly
    ``rect``: each edge a quarter pixel inside its pixel, each extent half a pixel over, so
    that the backend's truncations land on ``rect`` (the inverse of :func:`scissor`).
    None: an empty rectangle, which the backend skips."""
    ox, oy, sx, sy = origin
    if rect is None:
        return (ox, oy, ox, oy)
    x0, y0, x1, y1 = rect
    top = size[1] - y0 - 0.25           # framebuffer height minus the scissor's y
    return (ox + (x0 + 0.25) / sx, oy + (top - (y1 - y0) - 0.5) / sy,
            ox + (x0 + 0.25 + (x1 - x0) + 0.5) / sx, oy + top / sy)


def intersect(a: Rect | None, b: Rect | None) -> Rect | None:
    if a is None or b is None:
        return None
    rect = (max(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), min(a[3], b[3]))
    return rect if rect[0] < rect[2] and rect[1] < rect[3] else None


def bounding(a: Rect | None, b: Rect | None) -> Rect | None:
    if a is None or b is None:
        return a if b is None else b
    return _box(a, b)


def _box(a: Rect, b: Rect) -> Rect:
    return (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]))


def area(rect: Rect) -> int:
    return (rect[2] - rect[0]) * (rect[3] - rect[1])


def drawn_frame(draw_data, versions: TextureVersions, settled_state: int = 0,
                before: DrawnFrame | None = None) -> DrawnFrame | None:
    """``draw_data`` (imgui's, after ``imgui.render()``) as :func:`damage` compares it;
    None when it holds a command the comparison cannot follow (a user callback: a command
    that draws no elements). ``settled_state``: ``ImTextureStatus.ok``. ``before``: the
    last frame, whose lists that did not change are taken as they are (their vertices'
    box, most of this function's time, is not measured again)."""
    origin = origin_of(draw_data)
    size = framebuffer_size(draw_data)
    olds = {} if before is None or (before.size, before.origin) != (size, origin) else {
        drawn.name: drawn for drawn in before.lists}
    own = {}
    for texture in draw_data.textures:
        own[int(texture.get_tex_id())] = int(texture.status)
    settled = all(status == settled_state for status in own.values())
    if not settled:         # a texture imgui's lists use may not have its GL name yet
        return DrawnFrame(size, origin, (), False)
    lists = []
    for draw_list in draw_data.cmd_lists:
        commands, live, footprint = [], [], None
        for index in range(draw_list.cmd_buffer.size()):
            command = draw_list.cmd_buffer[index]
            if command.elem_count == 0:
                return None
            clip = command.clip_rect
            clip = (clip.x, clip.y, clip.z, clip.w)
            texture = int(command.get_tex_id())
            version = 0 if texture in own else versions.version(texture)
            rect = scissor(clip, origin, size)
            if version is None and rect is not None:
                live.append(rect)
            footprint = bounding(footprint, rect)
            commands.append((clip, texture, version, command.vtx_offset, command.idx_offset,
                             command.elem_count))
        vertices, indices = draw_list.vtx_buffer, draw_list.idx_buffer
        vertex_bytes = ctypes.string_at(vertices.data_address(), vertices.size() * VERTEX_BYTES)
        content = vertex_bytes + ctypes.string_at(indices.data_address(),
                                                  indices.size() * INDEX_BYTES)
        name, commands_made = draw_list._owner_name, tuple(commands)
        old = olds.get(name)
        if old is not None and old.content == content and old.commands == commands_made:
            lists.append(old)            # the same list: the same pixels, the same box
            continue
        # a tooltip's or the menu bar's commands clip to the whole window: what they can
        # touch is also within their vertices' box
        footprint = intersect(footprint, vertex_box(vertex_bytes, origin, size))
        lists.append(DrawnList(name, content, commands_made, footprint, tuple(live)))
    return DrawnFrame(size, origin, tuple(lists), settled)


def damage(before: DrawnFrame | None, after: DrawnFrame | None) -> list[Rect] | str:
    """The rectangles whose pixels may differ between a window painted with ``before`` and
    one painted with ``after``; or why any pixel may (no frame before, another size or
    scale, imgui's textures updated, lists added, removed or reordered)."""
    if before is None or after is None:
        return "no frame to compare" if after is not None else "a user callback"
    if not after.settled:
        return "imgui's textures updated"
    if before.size != after.size or before.origin != after.origin:
        return "the window's size or scale changed"
    old_names = [drawn.name for drawn in before.lists]
    new_names = [drawn.name for drawn in after.lists]
    if len(set(old_names)) < len(old_names) or len(set(new_names)) < len(new_names):
        return "two draw lists of one name"
    # a list opened or closed (a tooltip, a popup) damages its own footprint; the lists
    # in both frames must paint in the same order, or a pixel under two of them may change
    kept = set(old_names) & set(new_names)
    if [name for name in old_names if name in kept] != [name for name in new_names
                                                         if name in kept]:
        return "windows reordered"
    olds = {drawn.name: drawn for drawn in before.lists}
    rects: list[Rect] = []
    for new in after.lists:
        old = olds.get(new.name)
        if old is None or old.content != new.content or old.commands != new.commands:
            rects.extend(rect for rect in (old and old.footprint, new.footprint)
                         if rect is not None)
        rects.extend(new.live)
    rects.extend(old.footprint for old in before.lists
                 if old.name not in kept and old.footprint is not None)
    return rects


def merged(rects: list[Rect] | str, size: tuple[int, int]) -> list[Rect] | str:
    """``rects`` as at most :data:`MAX_RECTS` rectangles within the framebuffer
    (overlapping ones joined into their bounding box, then the pair whose box adds the
    least area while too many); or why the whole window is painted (``rects`` a reason
    already, or they cover over :data:`FULL_SHARE` of the window)."""
    if isinstance(rects, str):
        return rects
    window = (0, 0, size[0], size[1])
    pending = [rect for rect in (intersect(rect, window) for rect in rects) if rect]
    joined: list[Rect] = []
    while pending:
        rect = pending.pop()
        for other in joined:
            if intersect(rect, other) is not None:
                joined.remove(other)
                pending.append(_box(rect, other))     # may now meet another
                break
        else:
            joined.append(rect)
    while len(joined) > MAX_RECTS:     # join the pair whose box adds the least area
        _, i, j = min((area(_box(a, b)) - area(a) - area(b), i, j)
                      for i, a in enumerate(joined) for j, b in enumerate(joined) if i < j)
        box = _box(joined[i], joined[j])
        rest = [rect for k, rect in enumerate(joined) if k not in (i, j)]
        again = merged(rest + [box], size)           # the box may meet another
        joined = [window] if isinstance(again, str) else again
    if sum(area(rect) for rect in joined) > FULL_SHARE * size[0] * size[1]:
        return "most of the window changed"
    return joined
