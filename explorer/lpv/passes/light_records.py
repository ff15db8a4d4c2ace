"""The light records every full-screen or point pass that lights or shadows with the RSM
views reads (``shaders/light_records.glsl``: the gather's direct light, the fog's direct
in-scattering, the camera occluders' "does a light view hold this surface?" test;
docs/MODEL.md "Several lights"): one record per RSM view, in a storage buffer at binding
:data:`LIGHT_BINDING`, its shadow map a tile of the RSM atlas (``explorer/lpv/passes/atlas.py``).
"""

from __future__ import annotations

import operator
from collections.abc import Sequence
from dataclasses import dataclass

import moderngl
import numpy as np

from explorer.lpv.passes.rsm import LightView
from explorer.lpv.vpl import VplTextures
from explorer.scene.transforms import gl_matrix

LIGHT_BINDING = 5
"""Storage-buffer binding of the light records (``LightRecords`` in light_records.glsl)."""
LIGHT_KINDS = {"spot": 0.0, "directional": 1.0, "point": 2.0}
LIGHT_RECORD = np.dtype([("view", "<f4", 16), ("projection", "<f4", 16),
                         ("position_kind", "<f4", 4), ("axis_power", "<f4", 4),
                         ("colour_texel", "<f4", 4), ("cone", "<f4", 4),
                         ("tile", "<i4", 4)])
"""One ``LightRecord`` of light_records.glsl in std430 layout (208 bytes; matrices
column-major)."""


def light_records(views: Sequence[LightView],
                  tiles: Sequence[tuple[int, int]] | None = None) -> np.ndarray:
    """The light records: one per RSM view, its shadow map at ``tiles[k]`` (lower-left
    texel in the shadow atlas; None: every view at (0, 0), i.e. one view)."""
    views = list(views)
    if tiles is None:
        tiles = [(0, 0)] * len(views)
    if len(tiles) != len(views):
        raise ValueError(f"{len(views)} light views need as many shadow tiles, got "
                         f"{len(tiles)}")
    records = np.zeros(len(views), LIGHT_RECORD)
    for record, view, tile in zip(records, views, tiles):
        power = view.irradiance if view.orthographic else view.intensity
        record["view"] = gl_matrix(view.view)
        record["projection"] = gl_matrix(view.projection)
        record["position_kind"] = (*map(float, view.position), LIGHT_KINDS[view.kind])
        record["axis_power"] = (*map(float, view.direction), float(power))
        record["colour_texel"] = (*map(float, view.colour), view.texel_world_size)
        record["cone"] = (float(view.spot_cone), *view.cone_cosines, 0.0)
        record["tile"] = (*map(int, tile), view.size, view.size)
    return records


def view_list(lights: LightView | Sequence[LightView]) -> list[LightView]:
    """``lights`` as a list of views (one view alone is a list of one)."""
    return [lights] if isinstance(lights, LightView) else list(lights)


@dataclass(frozen=True)
class ShadowMaps:
    """The RSM views a pass lights and shadows with: their shadow maps as one set (one
    view's RSM, or the atlas of several: ``LightViews.shadow_maps``) and where each view's
    tile starts in it."""

    textures: VplTextures
    views: tuple[LightView, ...]
    """One view alone is made a tuple of one."""
    tiles: tuple[tuple[int, int], ...] | None = None
    """Lower-left texel of each view's tile in :attr:`textures`; None: one view at (0, 0)."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "views", tuple(view_list(self.views)))
        if self.tiles is not None:
            object.__setattr__(self, "tiles", tuple(tuple(t) for t in self.tiles))


class LightRecordBuffer:
    """The storage buffer of the light records, owned by one pass (grown when needed)."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self._buffer: moderngl.Buffer | None = None
        self._written: tuple[tuple[LightView, ...], tuple | None] | None = None
        """The views (the objects) and tiles the buffer holds the records of."""

    def bind(self, views: Sequence[LightView],
             tiles: Sequence[tuple[int, int]] | None = None) -> int:
        """Upload the records of ``views`` (shadow maps at ``tiles``, as
        :func:`light_records`), bind them to :data:`LIGHT_BINDING`, return their count
        (``u_light_count``). The same view objects (frozen; made when the RSM stage
        runs) at the same tiles are not written again: once per light change, not per
        frame."""
        views = tuple(views)
        tiles = None if tiles is None else tuple(map(tuple, tiles))
        written = self._written
        if written is None or written[1] != tiles or len(written[0]) != len(views) or \
                not all(map(operator.is_, written[0], views)):
            data = light_records(views, tiles).tobytes()
            if self._buffer is None or self._buffer.size < len(data):
                if self._buffer is not None:
                    self._buffer.release()
                self._buffer = self.ctx.buffer(reserve=max(len(data),
                                                           LIGHT_RECORD.itemsize))
            self._buffer.write(data)
            self._written = (views, tiles)
        self._buffer.bind_to_storage_buffer(LIGHT_BINDING)
        return len(views)

    def release(self) -> None:
        if self._buffer is not None:
            self._buffer.release()
            self._buffer = None
        self._written = None
