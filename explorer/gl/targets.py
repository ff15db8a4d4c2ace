"""Render targets of the full-screen and raster passes (RSM, G-buffer, downsample, gather,
display): colour textures of one size, an optional depth buffer, their framebuffer and
the scope that binds it, made together and released together.

The scope is made once per allocation and reused for every draw: a moderngl ``Scope``
that is dropped without ``release()`` leaks its native object (the context's default
``gc_mode`` frees nothing), so a ``with ctx.scope(...)`` per draw leaked one per frame.
A draw into a framebuffer that has no :class:`RenderTargets` (an overlay's target) goes
through :func:`scoped`, which releases its scope when the draw ends.

A change of size keeps the targets of the size left (up to :data:`KEPT_SIZES` of them):
the window alternates between a drag's reduced size, its previews' and the full one, and
making and zero-filling full-size float targets anew cost a software renderer tens of
milliseconds each time (a third of the frame after a drag).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import moderngl

KEPT_SIZES = 2
"""Sets of targets at other sizes a :class:`RenderTargets` keeps for a change back."""


@contextmanager
def scoped(ctx: moderngl.Context, framebuffer: moderngl.Framebuffer,
           enable_only: int = moderngl.NOTHING) -> Iterator[moderngl.Framebuffer]:
    """Draw into ``framebuffer`` with only ``enable_only`` enabled; the previous
    framebuffer and flags come back afterwards and the scope is released then."""
    scope = ctx.scope(framebuffer, enable_only=enable_only)
    try:
        with scope:
            yield framebuffer
    finally:
        scope.release()


class RenderTargets:
    """RGBA textures of ``dtypes`` (``"f4"`` float, ``"f1"`` 8-bit) at one size, drawn to
    through one framebuffer with ``enable`` flags (e.g. ``moderngl.DEPTH_TEST``) and, with
    ``depth``, a depth renderbuffer. Textures are clamped to the edge; ``linear`` names the
    indices sampled with linear filtering (the others are nearest)."""

    def __init__(self, ctx: moderngl.Context, dtypes: tuple[str, ...], depth: bool = False,
                 enable: int = moderngl.NOTHING, linear: tuple[int, ...] = ()) -> None:
        self.ctx = ctx
        self.dtypes = tuple(dtypes)
        self.depth = depth
        self.enable = enable
        self.linear = tuple(linear)
        self.size: tuple[int, int] = (0, 0)
        self.textures: list[moderngl.Texture] = []
        self._depth: moderngl.Renderbuffer | None = None
        self.framebuffer: moderngl.Framebuffer | None = None
        self._scope: moderngl.Scope | None = None
        self.keep_sizes = KEPT_SIZES
        """How many sets at other sizes are kept (0: a change of size releases the old)."""
        self._kept: dict[tuple[int, int], tuple] = {}
        """Size -> (textures, depth, framebuffer, scope) kept, the oldest first."""

    def allocate(self, size: tuple[int, int]) -> None:
        """Make the targets ``size`` (width, height) big; nothing happens at the same size.
        The set of the size left is kept (module docstring), and one kept at ``size`` is
        taken back as it was left (its texels are not cleared)."""
        size = (int(size[0]), int(size[1]))
        if size == self.size:
            return
        if self._scope is not None:
            self._kept[self.size] = (self.textures, self._depth, self.framebuffer,
                                     self._scope)
        kept = self._kept.pop(size, None)
        if kept is not None:
            self.textures, self._depth, self.framebuffer, self._scope = kept
        else:
            self.textures, self._depth, self.framebuffer, self._scope = self._make(size)
        self.size = size
        while len(self._kept) > self.keep_sizes:
            self._release_set(self._kept.pop(next(iter(self._kept))))

    def _make(self, size: tuple[int, int]) -> tuple:
        textures = []
        for index, dtype in enumerate(self.dtypes):
            texture = self.ctx.texture(size, 4, dtype=dtype)
            smooth = moderngl.LINEAR if index in self.linear else moderngl.NEAREST
            texture.filter = (smooth, smooth)
            texture.repeat_x = texture.repeat_y = False
            textures.append(texture)
        depth = self.ctx.depth_renderbuffer(size) if self.depth else None
        framebuffer = self.ctx.framebuffer(textures, depth)
        return textures, depth, framebuffer, self.ctx.scope(framebuffer,
                                                            enable_only=self.enable)

    @contextmanager
    def drawing(self, clear: bool = False, rows: tuple[int, int] | None = None
                ) -> Iterator[moderngl.Framebuffer]:
        """Bind the framebuffer over its whole size (cleared to zero, depth to 1, when
        ``clear``); ``rows`` = (first, end): draw only those rows (GL order, row 0 at the
        bottom), the others keep their texels. The previous framebuffer and enable flags
        come back afterwards."""
        if self._scope is None:
            raise RuntimeError("render targets used before allocate()")
        with self._scope:
            self.framebuffer.viewport = (0, 0, *self.size)
            if rows is not None:
                first, end = rows
                self.framebuffer.scissor = (0, first, self.size[0], end - first)
            try:
                if clear:
                    self.framebuffer.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
                yield self.framebuffer
            finally:
                self.framebuffer.scissor = None

    @staticmethod
    def _release_set(kept: tuple) -> None:
        textures, depth, framebuffer, scope = kept
        for resource in (scope, framebuffer, depth, *textures):
            if resource is not None:
                resource.release()

    def release(self) -> None:
        """Release the targets and every set kept at another size."""
        self._release_set((self.textures, self._depth, self.framebuffer, self._scope))
        for kept in self._kept.values():
            self._release_set(kept)
        self._kept.clear()
        self._scope = self.framebuffer = self._depth = None
        self.textures, self.size = [], (0, 0)
