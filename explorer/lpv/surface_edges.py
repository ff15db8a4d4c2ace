"""The geometry's edges in the camera's image, drawn over the albedo view.

A flat albedo hides the shapes that shading shows: the Cornell box's white blocks stand on
a white floor before a white wall, so an unlit albedo image shows no block at all and
reads as another camera's picture. The albedo view therefore darkens the pixels where the
G-buffer's surface ends, folds or jumps in depth, the same pixels in the window
(shaders/view_snapshot.glsl) and in ``render --view albedo`` (:func:`outlined_albedo`);
the float data of the view (``render --out x.exr``) stays the plain albedo.
"""

from __future__ import annotations

import numpy as np

EDGE_COSINE = 0.95
"""Neighbouring pixels whose normals' cosine is below this lie on two faces (a fold)."""
EDGE_JUMP = 4.0
"""Neighbouring pixels farther apart than this many pixel footprints (the square root of
the larger of their world areas, the G-buffer normal's w) lie on two surfaces."""
EDGE_SHADE = 0.3
"""The albedo view multiplies an edge pixel's albedo by this."""
EDGE_FLAG = 0.75
"""The albedo copy's w on an edge pixel (1 on other surface pixels, 0 off the surfaces:
the window's surface test, w > 0.5, holds for both)."""


def surface_edges(position: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """(H, W) bool: the surface pixels of a G-buffer (``position`` w = 1 on a surface,
    ``normal`` w = the pixel's world area) with a 4-neighbour off the surfaces, on
    another face (:data:`EDGE_COSINE`) or at a depth jump (:data:`EDGE_JUMP`). The image's
    own border is no edge."""
    surface = np.asarray(position[..., 3]) > 0.5
    xyz = np.asarray(position[..., :3], np.float64)
    n = np.asarray(normal[..., :3], np.float64)
    area = np.asarray(normal[..., 3], np.float64)
    edges = np.zeros(surface.shape, bool)
    height, width = surface.shape
    for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0)):
        here = (slice(max(0, -dy), height - max(0, dy)), slice(max(0, -dx), width - max(0, dx)))
        there = (slice(max(0, dy), height - max(0, -dy)), slice(max(0, dx), width - max(0, -dx)))
        apart = np.linalg.norm(xyz[here] - xyz[there], axis=-1)
        footprint = np.sqrt(np.maximum(area[here], area[there]))
        differs = (~surface[there] | (np.sum(n[here] * n[there], axis=-1) < EDGE_COSINE)
                   | (apart > EDGE_JUMP * footprint))
        edges[here] |= surface[here] & differs
    return edges


def outlined_albedo(albedo: np.ndarray, position: np.ndarray, normal: np.ndarray
                    ) -> np.ndarray:
    """``albedo`` (H, W, 3) with its :func:`surface_edges` darkened by :data:`EDGE_SHADE`:
    the albedo view's linear colour."""
    edges = surface_edges(position, normal)
    return np.where(edges[..., None], EDGE_SHADE * albedo, albedo).astype(np.float32)


def edge_uniforms() -> dict[str, float]:
    """The uniforms of shaders/view_snapshot.glsl's edge test and view.glsl's shading."""
    return {"u_edge_cosine": EDGE_COSINE, "u_edge_jump": EDGE_JUMP,
            "u_edge_flag": EDGE_FLAG}
