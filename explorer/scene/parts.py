"""The named surfaces of a scene, one name per triangle: what ``lpv-explorer compare
--region-mask NAME`` selects.

A built-in scene names its surfaces as it builds them (:attr:`Scene.parts`: the Cornell
box's ``floor`` and ``tall block``, the atrium's ``north curtains``); a triangle in no
part takes the name of the movable object holding it (:attr:`Scene.objects`: a loaded
mesh's scene-graph nodes), and one in neither is ``other``. Every triangle thus has
exactly one name, so the masks of all names partition the pixels that see a surface.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

OTHER = "other"
"""The name of the triangles in no part and no object."""


@dataclass(frozen=True)
class SurfaceNames:
    names: tuple[str, ...]
    """Every name a triangle of the scene has, in the order the scene built them."""
    triangle_names: np.ndarray
    """(T,) index into :attr:`names` of each triangle."""


def surface_names(scene) -> SurfaceNames:
    """The name of every triangle of ``scene`` (an ``explorer.scene.Scene``): its part, else
    its object, else :data:`OTHER` (module docstring); names no triangle has are left
    out."""
    triangles = scene.triangle_count
    names: list[str] = []
    index = np.full(triangles, -1, np.int64)

    def label(name: str) -> int:
        if name not in names:
            names.append(name)
        return names.index(name)

    if scene.triangle_parts is not None:
        for part, name in enumerate(scene.parts):
            chosen = scene.triangle_parts == part
            if np.any(chosen):
                index[chosen] = label(name)
    for obj in scene.objects:
        span = np.zeros(triangles, bool)
        span[obj.first // 3:obj.stop // 3] = True
        chosen = span & (index < 0)
        if np.any(chosen):
            index[chosen] = label(obj.name)
    if np.any(index < 0):
        index[index < 0] = label(OTHER)
    return SurfaceNames(tuple(names), index)
