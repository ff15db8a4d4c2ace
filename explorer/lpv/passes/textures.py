"""GPU storage of the light grid: three RGBA 3D textures of SH intensity (docs/MODEL.md).

Numpy layout everywhere is ``(channel, x, y, z, coefficient)``; a 3D texture stores texel
``(x, y, z)`` with x running fastest, so uploads transpose to ``(z, y, x, coefficient)``.
L1 (``sh_order`` 1): 4 coefficients, one ``nx×ny×nz`` texture per channel. L2
(``sh_order`` 2): 9 coefficients in 3 groups of 4 (the last holds coefficient 8 and three
zeros), stacked along z in one ``nx×ny×3nz`` texture per channel: group k of cell
(x, y, z) is texel (x, y, z + k·nz) (``shaders/sh_grid.glsl``; docs/MODEL.md "L2 option").
Also the lazily created default context and program cache of the numpy-facing API.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import moderngl
import numpy as np

from explorer.gl.gpu_sync import DeferredRead, issue_together
from explorer.gl.image_copy import can_copy_volume, copy_volume_texels
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.lpv.grid import cube_edge, grid_cells
from explorer.lpv.settings import GRID_FORMATS

_TEXTURE_DTYPES = {"rgba32f": "f4", "rgba16f": "f2"}
SH_ORDERS = (1, 2)
SH_COEFFICIENTS = {1: 4, 2: 9}
"""Coefficients per colour channel of each SH order."""
SH_GROUPS = {1: 1, 2: 3}
"""RGBA texel groups per cell (stacked along z) of each SH order."""


def check_sh_order(sh_order: int) -> int:
    """``sh_order`` if it is 1 (L1, 4 coefficients) or 2 (L2, 9); a ValueError otherwise."""
    if isinstance(sh_order, bool) or sh_order not in SH_ORDERS:
        raise ValueError(f"sh_order must be 1 (L1, 4 coefficients) or 2 (L2, 9 "
                         f"coefficients), got {sh_order!r}")
    return int(sh_order)


def sh_order_of(coefficients: int) -> int:
    """The SH order of a grid whose last axis holds ``coefficients`` (4 -> 1, 9 -> 2)."""
    for order, count in SH_COEFFICIENTS.items():
        if count == coefficients:
            return order
    raise ValueError(f"a grid needs 4 (L1) or 9 (L2) SH coefficients per cell, got "
                     f"{coefficients}")
_NUMPY_DTYPES = {"rgba32f": np.float32, "rgba16f": np.float16}


def check_format(fmt: str) -> str:
    if fmt not in GRID_FORMATS:
        raise ValueError(f"grid format must be one of {GRID_FORMATS}, got {fmt!r}")
    return fmt


def check_volume_array(array: np.ndarray, cells: int | Sequence[int], name: str,
                       channels: int | None = None, coefficients: int = 4) -> np.ndarray:
    """``array`` as float32 if it is shaped ``(channels, nx, ny, nz, coefficients)`` (or
    ``(nx, ny, nz, coefficients)`` when ``channels`` is None) with ``(nx, ny, nz) == cells``
    (one number: a cube); a ValueError stating the expected shape otherwise."""
    array = np.asarray(array)
    expected = grid_cells(cells) + (coefficients,)
    if channels is not None:
        expected = (channels,) + expected
    if array.shape != expected:
        raise ValueError(f"{name} must have shape {expected}, got {array.shape}")
    return array.astype(np.float32, copy=False)


class VolumeTexture:
    """One RGBA float 3D texture of ``sx × sy × depth`` texels (``size``: one number, a
    cube, or ``(sx, sy, sz)``; ``depth`` replaces ``sz``) with numpy ``(x, y, z, 4)``
    access."""

    def __init__(self, ctx: moderngl.Context, size: int | Sequence[int], fmt: str = "rgba32f",
                 depth: int | None = None) -> None:
        self.ctx = ctx
        sx, sy, sz = grid_cells(size)
        self.cells = (sx, sy, sz)
        self.depth = sz if depth is None else int(depth)
        self.format = check_format(fmt)
        self.texture = ctx.texture3d((sx, sy, self.depth), 4, dtype=_TEXTURE_DTYPES[fmt])
        # Linear filtering for the final gather's trilinear lookups (where the texture
        # unit's weights are exact, see sh_grid.glsl); clamp to the edge so the border
        # cells do not blend with the opposite side.
        self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.texture.repeat_x = self.texture.repeat_y = self.texture.repeat_z = False

    @property
    def shape(self) -> tuple[int, int, int]:
        """Texels along x, y, z."""
        return self.cells[0], self.cells[1], self.depth

    def read(self) -> np.ndarray:
        return self.texels(np.frombuffer(self.texture.read(), dtype=_NUMPY_DTYPES[self.format]))

    def read_later(self, read: DeferredRead) -> None:
        """Copy the texels into ``read`` without waiting (explorer/gl/gpu_sync.py);
        :meth:`texels` of its array gives what :meth:`read` does."""
        read.issue(self.texture, self.texels_shape, _NUMPY_DTYPES[self.format])

    @property
    def texels_shape(self) -> tuple[int, int, int, int]:
        """The shape of the texels' bytes as GL lays them out (z, y, x, 4)."""
        return self.shape[::-1] + (4,)

    def texels(self, data: np.ndarray) -> np.ndarray:
        """float32 ``(x, y, z, 4)`` from the texture's bytes as GL lays them out."""
        return np.asarray(data).reshape(self.texels_shape).transpose(
            2, 1, 0, 3).astype(np.float32)

    def write(self, volume: np.ndarray) -> None:
        volume = np.asarray(volume)
        if self.depth == self.cells[2]:
            volume = check_volume_array(volume, self.cells, "volume")
        elif volume.shape != self.shape + (4,):
            raise ValueError(f"volume must have shape {self.shape + (4,)}, got {volume.shape}")
        texels = np.ascontiguousarray(volume.transpose(2, 1, 0, 3), _NUMPY_DTYPES[self.format])
        self.texture.write(texels.tobytes())

    def clear(self) -> None:
        self.texture.write(bytes(self.texture.width * self.texture.height * self.texture.depth
                                 * 4 * np.dtype(_NUMPY_DTYPES[self.format]).itemsize))

    def bind_image(self, unit: int, read: bool = True, write: bool = True) -> None:
        self.texture.bind_to_image(unit, read=read, write=write)

    def release(self) -> None:
        self.texture.release()


class LpvGrid:
    """Three 3D textures (r, g, b channel) of SH radiant intensity [W/sr] (docs/MODEL.md
    "Notation and storage"): L1 (``sh_order`` 1), each texel = 4 coefficients; L2
    (``sh_order`` 2), 9 coefficients per cell in 3 texel groups stacked along z (module
    docstring). ``cells``: ``(nx, ny, nz)``, or one number for a cube."""

    def __init__(self, ctx: moderngl.Context, cells: int | Sequence[int], fmt: str = "rgba32f",
                 sh_order: int = 1) -> None:
        self.ctx = ctx
        self.cells = grid_cells(cells)
        self.format = check_format(fmt)
        self.sh_order = check_sh_order(sh_order)
        self.coefficients = SH_COEFFICIENTS[self.sh_order]
        self.groups = SH_GROUPS[self.sh_order]
        self.volumes = tuple(VolumeTexture(ctx, self.cells, fmt,
                                           depth=self.groups * self.cells[2])
                             for _ in range(3))
        self.textures: tuple[moderngl.Texture3D, moderngl.Texture3D, moderngl.Texture3D] = (
            tuple(volume.texture for volume in self.volumes))

    @property
    def nbytes(self) -> int:
        """The bytes its three textures hold."""
        texel_bytes = np.dtype(_NUMPY_DTYPES[self.format]).itemsize
        return sum(int(np.prod(volume.texels_shape)) * texel_bytes for volume in self.volumes)

    @property
    def resolution(self) -> int:
        """Cells per axis of the light grid when it is a cube (:func:`cube_edge`)."""
        return cube_edge(self.cells)

    def clear(self) -> None:
        for volume in self.volumes:
            volume.clear()

    def read(self) -> np.ndarray:
        """float32 ``(3, nx, ny, nz, C)`` = (channel, x, y, z, coefficient), C = 4 (L1) or 9."""
        out = np.empty((3,) + self.cells + (self.coefficients,), np.float32)
        for channel, volume in enumerate(self.volumes):
            self._coefficients_into(out[channel], volume.texture.read())
        return out

    def read_channel(self, channel: int) -> np.ndarray:
        """float32 ``(nx, ny, nz, C)``: colour channel ``channel`` (0 r, 1 g, 2 b)."""
        out = np.empty(self.cells + (self.coefficients,), np.float32)
        self._coefficients_into(out, self.volumes[channel].texture.read())
        return out

    def read_later(self, reads: Sequence[DeferredRead]) -> None:
        """Copy each colour channel into its deferred read without waiting; :meth:`taken`
        of the same reads gives what :meth:`read` does."""
        volumes = self.volumes
        issue_together(reads[:len(volumes)], [volume.texture for volume in volumes],
                       [volume.texels_shape for volume in volumes],
                       _NUMPY_DTYPES[self.format])

    def taken(self, reads: Sequence[DeferredRead]) -> np.ndarray:
        """The ``(3, N, N, N, C)`` array of :meth:`read_later`'s copies (waiting only for
        those not done yet)."""
        out = np.empty((3,) + self.cells + (self.coefficients,), np.float32)
        for channel, read in enumerate(reads[:len(self.volumes)]):
            self._coefficients_into(out[channel], read.wait())
        return out

    def _coefficients_into(self, out: np.ndarray, data) -> None:
        """Fill ``out`` ``(nx, ny, nz, C)`` from one channel's texture bytes (as GL lays
        them out: z over the coefficient groups, then y, x, 4), each group's texels
        copied once straight into their place (a 64³ L2 grid's read took 99 ms on
        llvmpipe with the transposed, concatenated and sliced copies between)."""
        dtype = _NUMPY_DTYPES[self.format]
        raw = np.frombuffer(data, dtype) if isinstance(data, bytes) else np.asarray(data)
        raw = raw.reshape(self.volumes[0].texels_shape)
        n = self.cells[2]
        for k in range(self.groups):
            width = min(4, self.coefficients - 4 * k)
            out[..., 4 * k:4 * k + width] = \
                raw[k * n:(k + 1) * n].transpose(2, 1, 0, 3)[..., :width]

    def write(self, grid: np.ndarray) -> None:
        grid = check_volume_array(grid, self.cells, "grid", channels=3,
                                  coefficients=self.coefficients)
        padding = 4 * self.groups - self.coefficients
        for volume, channel in zip(self.volumes, grid):
            if padding:
                channel = np.concatenate(
                    [channel, np.zeros(channel.shape[:3] + (padding,), np.float32)], -1)
            volume.write(np.concatenate(np.split(channel, self.groups, axis=-1), axis=2))

    def use_as_textures(self, first_location: int) -> None:
        """Bind r, g, b as sampler3D units ``first_location`` .. ``first_location + 2``
        (linear filtering, clamped to the edge)."""
        for offset, texture in enumerate(self.textures):
            texture.use(first_location + offset)

    def bind_images(self, first_unit: int, read: bool = True, write: bool = True) -> None:
        """Bind r, g, b as image3D units ``first_unit`` .. ``first_unit + 2`` (straight on
        the textures; a propagation binds them once a unit: passes/propagate.py)."""
        for offset, texture in enumerate(self.textures):
            texture.bind_to_image(first_unit + offset, read=read, write=write)

    def release(self) -> None:
        for volume in self.volumes:
            volume.release()


def image_format_defines(fmt: str) -> dict[str, str]:
    """The ``IMAGE_FORMAT`` define matching a grid format, for the compute shaders."""
    return {"IMAGE_FORMAT": check_format(fmt)}


def dispatch_size(resolution: int | tuple[int, int, int], local_size: int = 4
                  ) -> tuple[int, int, int]:
    """Workgroups covering ``resolution``³ (or ``(x, y, z)``) invocations with cubic groups
    of ``local_size``."""
    shape = resolution if type(resolution) is tuple else \
        (resolution,) * 3 if np.ndim(resolution) == 0 else resolution
    if len(shape) == 3:             # the common case, without a generator (a frame's copies)
        x, y, z = shape
        return (-(-int(x) // local_size), -(-int(y) // local_size), -(-int(z) // local_size))
    return tuple(-(-int(extent) // local_size) for extent in shape)


def sh_defines(sh_order: int) -> dict[str, int]:
    """The ``SH_ORDER`` define of the shaders that store light vectors."""
    return {"SH_ORDER": check_sh_order(sh_order)}


class LayeredTarget:
    """``count`` layered 2D-array render targets of ``sx × sy × sz`` texels (``size``: one
    number, a cube, or three): points drawn with ``gl_Layer = z`` land in texel
    ``(x, y, z)``. moderngl refuses a 3D texture as a framebuffer attachment, so the point
    passes render here and :func:`copy_volume` moves each layer stack into its 3D texture.
    ``depth`` layers replace ``sz``."""

    def __init__(self, ctx: moderngl.Context, size: int | Sequence[int], count: int, fmt: str,
                 depth: int | None = None) -> None:
        sx, sy, sz = grid_cells(size)
        self.shape = (sx, sy, sz if depth is None else int(depth))
        self.depth = self.shape[2]
        self.format = check_format(fmt)
        self.layers = [ctx.texture_array(self.shape, 4,
                                         dtype=_TEXTURE_DTYPES[fmt])
                       for _ in range(count)]
        for layers in self.layers:
            layers.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self.framebuffer = ctx.framebuffer(color_attachments=self.layers)

    @property
    def nbytes(self) -> int:
        """The bytes its texture arrays hold."""
        texel_bytes = 4 * np.dtype(_NUMPY_DTYPES[self.format]).itemsize
        return int(np.prod(self.shape)) * texel_bytes * len(self.layers)

    def release(self) -> None:
        self.framebuffer.release()
        for layers in self.layers:
            layers.release()


def draw_points_additively(ctx: moderngl.Context, program: moderngl.Program,
                           target: LayeredTarget, count: int, clear: bool = True,
                           first: int = 0) -> None:
    """Clear ``target`` (unless ``clear`` is False: add to what it holds) and draw ``count``
    attribute-less points into it with ONE,ONE float blending (sums, negative values
    kept), their ``gl_VertexID`` from ``first`` on (a batch of a larger draw: GL blends in
    the order of the points, across draws too, so batches in a row give the same sums).
    The previous framebuffer and enable flags come back afterwards; the blend function is
    left at moderngl's default."""
    vertex_array = ctx.vertex_array(program, [])
    scope = ctx.scope(target.framebuffer, enable_only=moderngl.BLEND)
    try:
        with scope:
            if clear:
                target.framebuffer.clear(0.0, 0.0, 0.0, 0.0)
            ctx.blend_equation = moderngl.FUNC_ADD
            ctx.blend_func = moderngl.ONE, moderngl.ONE
            vertex_array.render(mode=moderngl.POINTS, vertices=count, first=first)
            ctx.blend_func = moderngl.DEFAULT_BLENDING
    finally:
        scope.release()
        vertex_array.release()


def copy_volume(programs: ProgramCache, source: moderngl.Texture3D | moderngl.TextureArray,
                target: VolumeTexture) -> None:
    """Copy a 3D texture or a layered 2D array (layer = z) into ``target``, texel for texel:
    an image copy (``glCopyImageSubData``, explorer/gl/image_copy.py) where both hold the
    same format, else with a compute shader (unit 0 holds the source while it runs). On
    llvmpipe a 64³ rgba32f channel's image copy takes about 0.1 ms, the compute shader's
    6–8 ms; the same bits (``texelFetch`` and ``imageStore`` of one format change none)."""
    if can_copy_volume(source, target.texture):
        copy_volume_texels(source, target.texture)
        return
    program = _copy_program(programs, isinstance(source, moderngl.TextureArray),
                            target.format)
    source.use(0)
    target.bind_image(0, read=False, write=True)
    set_uniforms(program, _COPY_UNIFORMS)    # one dict: the copies in a row set it once
    program.run(*dispatch_size(target.shape))
    programs.ctx.memory_barrier()


def copy_volumes(programs: ProgramCache, sources: Sequence, targets: Sequence[VolumeTexture]
                 ) -> None:
    """:func:`copy_volume` of each source into its target, in order: image copies where
    each pair holds one format (a grid's three channels), else the compute program got
    and its uniform set once for the sources of the first such pair's kind and targets of
    its format (any other pair is copied by :func:`copy_volume`): the same GL calls, less
    Python."""
    program = None          # got at the first pair the compute shader copies
    barrier = programs.ctx.memory_barrier
    uniforms_set, size, groups = False, None, (0, 0, 0)
    for source, target in zip(sources, targets, strict=True):
        if can_copy_volume(source, target.texture):
            copy_volume_texels(source, target.texture)     # an image copy: no program
            continue
        if program is None:
            layered, fmt = isinstance(source, moderngl.TextureArray), target.format
            program = _copy_program(programs, layered, fmt)
            run = program.run
        if isinstance(source, moderngl.TextureArray) is not layered or target.format != fmt:
            copy_volume(programs, source, target)
            uniforms_set = False        # that copy's program may be this one
            continue
        source.use(0)
        target.texture.bind_to_image(0, read=False, write=True)
        if not uniforms_set:
            set_uniforms(program, _COPY_UNIFORMS)
            uniforms_set = True
        if (target.cells, target.depth) != size:
            size = (target.cells, target.depth)
            groups = dispatch_size(target.shape)
        run(*groups)
        barrier()


APART_TEXELS = 40 ** 3
"""A volume of more texels than this is copied (and its draws and merges done) in a unit of
its own in a time-sliced frame: a 64³ volume's copy by the compute shader takes 8 ms on
llvmpipe, a 32³ one's 1 ms (those stay in one unit with the work around them: fewer
units, less per-unit Python); an image copy (:func:`copy_volume`, one format) takes
about 0.1 ms at 64³, but keeps the units as they are."""


def copied_apart(shape: Sequence[int]) -> bool:
    """Whether a volume of ``shape`` texels is copied in a unit of its own
    (:data:`APART_TEXELS`)."""
    return math.prod(map(int, shape)) > APART_TEXELS


POINT_BATCH = 1 << 15
"""Points a unit of a point pass draws at most; a larger set's draw is several units,
:func:`point_batches`. A 256² RSM's VPLs in two draws of half as many: on llvmpipe, run unit
by unit right after a change to 64³ (``bench --units``), the injection's longest unit went
20 → 7 ms and its stage 21 → 14 ms, the 32³ one's longest 10.6 → 7 ms with the same total;
a whole frame's injection (``bench``) takes the same time either way (BENCHMARKS.md,
issue #32 item 3)."""


def point_batches(count: int) -> list[tuple[int, int]]:
    """``(first, count)`` of the batches ``count`` points are drawn in (at least one)."""
    size = POINT_BATCH
    return [(first, min(size, count - first)) for first in range(0, count, size)] or [(0, 0)]


def _copy_program(programs: ProgramCache, layered: bool, fmt: str):
    """The volume copy's compute program for a layered or 3D source and a target of
    ``fmt`` (its defines and cache key made once a kind, :data:`_COPY_PROGRAMS`)."""
    made = _COPY_PROGRAMS.get((layered, fmt))
    if made is None:
        defines = {"SOURCE_LAYERED": int(layered), **image_format_defines(fmt)}
        made = _COPY_PROGRAMS[(layered, fmt)] = (
            defines, programs.key("volume_copy.glsl", defines))
    return programs.get("volume_copy.glsl", *made)


_COPY_PROGRAMS: dict[tuple[bool, str], tuple[dict, tuple]] = {}
_COPY_UNIFORMS: dict[str, object] = {"u_source": 0}
""":func:`copy_volume`'s program defines and keys by (layered source, format)."""

_PER_CONTEXT: dict[tuple[int, str], tuple[moderngl.Context, object]] = {}
_DEFAULT_CONTEXT: list[moderngl.Context] = []


def default_context() -> moderngl.Context:
    """One headless context, created on first use and reused by the numpy-facing API."""
    if not _DEFAULT_CONTEXT:
        from explorer.gl.context import create_headless_context

        _DEFAULT_CONTEXT.append(create_headless_context())
    return _DEFAULT_CONTEXT[0]


def per_context(ctx: moderngl.Context, key: str, factory):
    """An object made by ``factory()`` once per context and key (program caches and pass
    objects of the numpy-facing API)."""
    entry = _PER_CONTEXT.get((id(ctx), key))
    if entry is None or entry[0] is not ctx:
        entry = (ctx, factory())
        _PER_CONTEXT[(id(ctx), key)] = entry
    return entry[1]


def programs_for(ctx: moderngl.Context) -> ProgramCache:
    """The program cache the numpy-facing API uses with ``ctx``."""
    return per_context(ctx, "programs", lambda: ProgramCache(ctx))
