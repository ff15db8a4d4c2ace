"""Bounds of every request that costs memory: checked before anything is allocated, each
failure one line naming the request, the bytes or the limit, and the allowed value.

Memory is counted for what a frame holds at once: on the GPU its textures (and on a
software renderer that is host memory too) and on the host the arrays the pipeline reads
back (each texture read is a bytes copy and a row-flipped array). Framebuffer sizes must
stay strictly below the driver's largest (``GL_MAX_TEXTURE_SIZE``,
``GL_MAX_RENDERBUFFER_SIZE``, ``GL_MAX_FRAMEBUFFER_WIDTH``/``HEIGHT``,
``GL_MAX_VIEWPORT_DIMS``): Mesa reports "framebuffer is not complete" at exactly the
maximum.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from explorer.lpv.cascades import AUDIT_RECORD_BYTES, texture_bytes
from explorer.lpv.grid import grid_cells, shape_text

DEFAULT_MEMORY_BUDGET = 4 << 30
"""Default limit of one pipeline's memory (GPU textures + host read-back), bytes."""
RSM_TEXTURES = 4
"""RSM targets: position, normal, flux, albedo (rgba32f) and a 4-byte depth buffer."""
RSM_READ_BACK = 3 + 4
"""RSM arrays read back (position, normal, flux) and the VPL arrays made from them
(position, normal, flux, albedo)."""
IMAGE_TEXTURES = (3, 3)
"""Per pixel: G-buffer and gather ``rgba32f`` targets (3 each), plus a 4-byte depth
buffer and the ``rgba8`` display texture."""
IMAGE_READ_BACK = 6
"""Image arrays read back: the G-buffer's three and the gather's three."""
FOG_TEXTURES = 2
"""With fog: the fog pass's two ``rgba32f`` targets, both read back too."""
TEXEL = 16
"""Bytes of one ``rgba32f`` texel."""


@dataclass(frozen=True)
class Request:
    """One allocation request: what asks (a Settings field and its value) and its bytes."""

    name: str
    what: str
    bytes: int


def memory_requests(settings, views: int = 1) -> list[Request]:
    """The memory a frame with ``settings`` holds, by request (module docstring), with
    ``views`` RSM views (several lights; a point light has six): each view's RSM textures
    and read-back, and with several views their atlas (explorer/lpv/passes/atlas.py)."""
    s = settings
    rsm_texels = s.rsm_size ** 2
    pixels = s.width * s.height
    # a read-back array is the bytes object plus the flipped float32 copy: twice its size
    rsm = views * rsm_texels * (RSM_TEXTURES * TEXEL + 4 + RSM_READ_BACK * TEXEL * 2)
    if views > 1:
        rsm += views * rsm_texels * RSM_TEXTURES * TEXEL
    fog = FOG_TEXTURES if s.fog else 0
    images = pixels * ((sum(IMAGE_TEXTURES) + fog) * TEXEL + 4 + 4
                       + (IMAGE_READ_BACK + fog) * TEXEL * 2)
    groups = 3 if s.sh_order == 2 else 1
    grids = texture_bytes(s.grid_shape, s.cascades, s.grid_format, s.geometry_volume != "off",
                          groups)
    # the accumulation of every cascade is read back too (float32, 4 or 9 coefficients)
    grids += s.cascades * 3 * _count(s.grid_shape) * 4 * (9 if s.sh_order == 2 else 4) * 2
    what = ("RSM textures and their read-back" if views == 1 else
            f"{views} RSM views of several lights: their textures, atlas and read-back")
    return [Request("rsm_size", f"rsm_size {s.rsm_size} ({what})", rsm),
            Request("width", f"{s.width}x{s.height} pixels (G-buffer, gather, fog and "
                             f"display targets and their read-back)", images),
            Request("grid_cells" if s.grid_cells is not None else "grid_size",
                    f"{s.cascades} cascade(s) of {shape_text(s.grid_shape)} cells in "
                                 f"{s.grid_format} (light grids, audit records, geometry "
                                 f"volume, read-back)", grids)]


def check_memory(settings, budget_bytes: int, views: int = 1) -> None:
    """A ValueError naming the largest request when the frame (with ``views`` RSM views)
    needs more than ``budget_bytes``."""
    if not budget_bytes:
        return
    requests = memory_requests(settings, views)
    total = sum(r.bytes for r in requests)
    if total <= budget_bytes:
        return
    largest = max(requests, key=lambda r: r.bytes)
    others = total - largest.bytes
    raise ValueError(f"{largest.what} needs {_mib(largest.bytes)}; with the rest of the frame "
                     f"({_mib(others)}) that is {_mib(total)}, more than the memory budget "
                     f"of {_mib(budget_bytes)} (Pipeline.memory_budget_bytes): lower "
                     f"{largest.name}")


@dataclass(frozen=True)
class DriverLimits:
    """The GL limits the requests are checked against (0 = unknown, not checked)."""

    max_texture_size: int = 0
    max_3d_texture_size: int = 0
    max_framebuffer_size: int = 0
    """The smallest of the texture, renderbuffer, framebuffer and viewport maxima."""
    max_texture_units: int = 0
    max_storage_block_bytes: int = 0

    @classmethod
    def of(cls, info: dict) -> DriverLimits:
        def value(name: str) -> int:
            raw = info.get(name, 0) or 0
            return int(min(raw)) if isinstance(raw, (tuple, list)) else int(raw)

        sizes = [value(name) for name in (
            "GL_MAX_TEXTURE_SIZE", "GL_MAX_RENDERBUFFER_SIZE", "GL_MAX_FRAMEBUFFER_WIDTH",
            "GL_MAX_FRAMEBUFFER_HEIGHT", "GL_MAX_VIEWPORT_DIMS")]
        known = [size for size in sizes if size > 0]
        return cls(max_texture_size=value("GL_MAX_TEXTURE_SIZE"),
                   max_3d_texture_size=value("GL_MAX_3D_TEXTURE_SIZE"),
                   max_framebuffer_size=min(known) if known else 0,
                   max_texture_units=value("GL_MAX_TEXTURE_IMAGE_UNITS"),
                   max_storage_block_bytes=value("GL_MAX_SHADER_STORAGE_BLOCK_SIZE"))


def check_framebuffers(settings, limits: DriverLimits) -> None:
    """A ValueError unless the RSM and the image stay strictly below the driver's largest
    framebuffer."""
    largest = limits.max_framebuffer_size
    if not largest:
        return
    for name in ("rsm_size", "width", "height"):
        value = int(getattr(settings, name))
        if value >= largest:
            raise ValueError(f"{name} {value} must be below this driver's largest framebuffer "
                             f"size {largest} (GL_MAX_TEXTURE_SIZE, GL_MAX_RENDERBUFFER_SIZE, "
                             f"GL_MAX_FRAMEBUFFER_*, GL_MAX_VIEWPORT_DIMS): use at most "
                             f"{largest - 1}")


def check_grid_textures(settings, limits: DriverLimits) -> None:
    """A ValueError when the light grid does not fit the driver's 3D textures."""
    s, largest = settings, limits.max_3d_texture_size
    name = "grid_cells" if s.grid_cells is not None else "grid_size"
    nx, ny, nz = s.grid_shape
    if largest and max(nx, ny, nz) > largest:
        shown = s.grid_size if s.grid_cells is None else shape_text(s.grid_cells)
        raise ValueError(f"{name} {shown} exceeds this driver's "
                         f"GL_MAX_3D_TEXTURE_SIZE {largest}")
    # L2 stacks its 3 texel groups along z (explorer/lpv/passes/textures.py)
    if s.sh_order == 2 and largest and 3 * nz > largest:
        what = "grid_size" if s.grid_cells is None else "nz"
        raise ValueError(f"sh_order 2 stores 3·{what} = {3 * nz} texels along z, "
                         f"more than this driver's GL_MAX_3D_TEXTURE_SIZE {largest}")


def audit_fits(cells: int | tuple[int, int, int], limits: DriverLimits) -> bool:
    """Whether the per-cell audit records of a grid of ``cells`` (one number: a cube) fit
    one shader storage block each (128 MiB on llvmpipe: up to 122³ cells)."""
    largest = limits.max_storage_block_bytes
    return not largest or AUDIT_RECORD_BYTES * _count(cells) <= largest


def _count(cells: int | tuple[int, int, int]) -> int:
    # exact Python integers, without numpy's reduction machinery (asked every frame)
    return math.prod(grid_cells(cells))


def audit_skipped_warning(cells: int | tuple[int, int, int], limits: DriverLimits) -> str:
    return (f"the per-step energy audit of a {shape_text(grid_cells(cells))} grid needs "
            f"storage blocks of {_mib(AUDIT_RECORD_BYTES * _count(cells))} for its per-cell "
            f"records, more than "
            f"this driver's GL_MAX_SHADER_STORAGE_BLOCK_SIZE "
            f"({_mib(limits.max_storage_block_bytes)}): only the injected and accumulated "
            f"flux and the flux per step were measured")


def _mib(size: int) -> str:
    return f"{size / 2**30:.2f} GiB" if size >= 2**30 else f"{size / 2**20:.1f} MiB"
