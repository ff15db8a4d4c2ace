"""Which textures imgui shows hold the content they held last frame.

The window repaints only where its draw lists changed (:mod:`explorer.ui.partial_paint`),
but a draw list that samples a texture stays the same when only the texture's content
changes. A texture whose every write goes through one owner (:class:`UiTextures
<explorer.ui.textures.UiTextures>`, the figure cache) is *tracked* here: the owner calls
:meth:`TextureVersions.written` after each write and :meth:`TextureVersions.forget` when it
releases the texture. A texture nobody tracks (the view's pictures, written by the
composer every frame they change) has no version, and the part of the window that shows it
is repainted every frame.
"""

from __future__ import annotations

import itertools
import weakref
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import moderngl


class TextureVersions:
    """GL texture name -> the version of its content (a number never given twice)."""

    def __init__(self) -> None:
        self._versions: dict[int, int] = {}
        self._next = itertools.count(1)

    def written(self, glo: int) -> None:
        """The texture ``glo`` got new content (or is new: a name GL hands out again
        after a release gets a version it never had)."""
        self._versions[int(glo)] = next(self._next)

    def forget(self, glo: int) -> None:
        """The texture ``glo`` is released: its name may come back as a texture nobody
        tracks."""
        self._versions.pop(int(glo), None)

    def version(self, glo: int) -> int | None:
        """The content's version, or None for a texture nobody tracks."""
        return self._versions.get(int(glo))


_BY_CONTEXT: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def versions_for(ctx: moderngl.Context) -> TextureVersions:
    """The versions of ``ctx``'s textures (GL names are per context)."""
    versions = _BY_CONTEXT.get(ctx)
    if versions is None:
        versions = _BY_CONTEXT[ctx] = TextureVersions()
    return versions
