"""Where to put a light in a mesh that comes without one: inside its box, inside the
room when it is closed.

A point is *inside a room* when every ray from it meets a triangle and the first triangle
each ray meets shows it its front (the side the triangle's normal points to): the walls
face the point. A point inside a solid block (whose faces point away from it) sees backs
and fails; a point of an open room (an open-fronted box, a roofless courtyard) sees fronts
in most directions and nothing in the others, and holds the light when no closed room
exists. Candidates are the points of a regular lattice in the mesh's box; of the most
enclosed the one farthest from its nearest surface is chosen (the light then sits as far
as it can from every surface, so no wall is lit at a grazing hot spot).

The rays are cast in numpy (Möller–Trumbore, :func:`first_hits`), in chunks of triangles
(:data:`MAX_WORK` bounds the time).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from explorer.scene.model import Scene

RAY_DIRECTIONS = 96
"""Rays per candidate: a Fibonacci sphere (even coverage, no axis-aligned gaps)."""
MAX_WORK = 4.0e7
"""Largest (rays × triangles) pairs tested (one to two seconds on one core): fewer
candidates for larger meshes (125 up to 3 300 triangles, 27 up to 15 000, 8 up to
52 000, beyond that the box's centre alone)."""
LATTICE_STEPS = (5, 3, 2, 1)
"""Candidates per axis tried in order, the first whose work fits ``MAX_WORK``."""
CHUNK_PAIRS = 2_000_000
MIN_CLEARANCE = 0.02
"""Nearest surface at least this share of the box's diagonal away from the light."""
MIN_ENCLOSED = 0.5
"""Share of rays that must meet a surface's front for a point of an open mesh to hold
the light (an open-fronted box: about 5/6; a floor under a statue: about 1/2)."""


def fibonacci_directions(count: int) -> np.ndarray:
    """(count, 3) unit vectors spread evenly over the sphere."""
    k = np.arange(count, dtype=np.float64) + 0.5
    z = 1.0 - 2.0 * k / count
    radius = np.sqrt(1.0 - z * z)
    angle = k * math.pi * (3.0 - math.sqrt(5.0))
    return np.stack([radius * np.cos(angle), z, radius * np.sin(angle)], axis=1)


def first_hits(origin: np.ndarray, directions: np.ndarray, corners: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """For R rays from one ``origin`` along ``directions`` (R, 3) and T triangles
    ``corners`` (T, 3, 3): the distance to the nearest triangle each ray meets (inf: none)
    and that triangle's index (−1: none).

    Möller–Trumbore with the origin fixed: with ``s = o − a``, ``e1 = b − a``,
    ``e2 = c − a`` and ``n = e1 × e2``, a ray ``o + t·d`` meets the triangle at
    barycentrics ``u = d·(e2 × s)/det``, ``v = d·(s × e1)/det`` and distance
    ``t = e2·(s × e1)/det`` with ``det = −d·n``: three dot products per ray and triangle,
    i.e. three matrix products (rays × triangles) per chunk of triangles."""
    a = corners[:, 0]
    edge1, edge2 = corners[:, 1] - a, corners[:, 2] - a
    best = np.full(len(directions), np.inf)
    which = np.full(len(directions), -1)
    step = max(1, CHUNK_PAIRS // max(len(directions), 1))
    rows = np.arange(len(directions))
    for start in range(0, len(corners), step):
        e1, e2 = edge1[start:start + step], edge2[start:start + step]
        s = origin[None, :] - a[start:start + step]
        normal, across, q = np.cross(e1, e2), np.cross(e2, s), np.cross(s, e1)
        det = -(directions @ normal.T)                                   # (R, t)
        usable = np.abs(det) > 1e-12
        inverse = np.where(usable, 1.0 / np.where(usable, det, 1.0), 0.0)
        u = (directions @ across.T) * inverse
        v = (directions @ q.T) * inverse
        t = np.einsum("tj,tj->t", e2, q)[None, :] * inverse
        hit = usable & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
        t = np.where(hit, t, np.inf)
        nearest = np.argmin(t, axis=1)
        distance = t[rows, nearest]
        closer = distance < best
        best[closer] = distance[closer]
        which[closer] = start + nearest[closer]
    return best, which


@dataclass(frozen=True)
class Placement:
    """Where :func:`light_inside` puts a light."""

    position: np.ndarray
    distance: float
    """Mean distance to the surfaces the rays from there meet (for the light's flux)."""
    closed: bool
    """True: from every candidate that sees no back, every ray meets a surface's front
    (a closed room); False: the mesh is open somewhere (an open room, a courtyard)."""
    enclosed: float
    """The share of the rays that meet a front."""


def light_inside(scene: Scene) -> Placement | None:
    """The candidate inside the mesh's box that is most enclosed: inside a closed room
    if there is one (every ray meets a front), else where at least
    :data:`MIN_ENCLOSED` of the rays meet a front and none a back (an open room); among
    equally enclosed ones the farthest from its nearest surface, then the highest. None
    when no candidate qualifies (a solid object, a single sheet: the caller puts a spot
    light above the mesh instead)."""
    corners = np.asarray(scene.positions, np.float64).reshape(-1, 3, 3)
    lo, hi = np.asarray(scene.bounds_min, np.float64), np.asarray(scene.bounds_max, np.float64)
    directions = fibonacci_directions(RAY_DIRECTIONS)
    steps = next((n for n in LATTICE_STEPS
                  if n ** 3 * RAY_DIRECTIONS * len(corners) <= MAX_WORK), 1)
    fractions = (np.arange(steps) + 0.5) / steps
    grid = np.stack(np.meshgrid(fractions, fractions, fractions, indexing="ij"), -1)
    candidates = lo + grid.reshape(-1, 3) * (hi - lo)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    diagonal = float(np.linalg.norm(hi - lo))
    best_key, best, escapes = None, None, False
    for origin in candidates:
        distance, triangle = first_hits(origin, directions, corners)
        hit = np.isfinite(distance)
        facing = np.einsum("rj,rj->r", normals[np.maximum(triangle, 0)], directions) < 0.0
        if np.any(hit & ~facing):
            continue                    # a back seen: inside a solid, or behind a wall
        enclosed = float(hit.mean())
        escapes |= enclosed < 1.0
        if enclosed < MIN_ENCLOSED:
            continue
        clearance = float(distance[hit].min())
        if clearance < MIN_CLEARANCE * diagonal:
            continue                    # on a surface (a flat mesh's box is the mesh)
        key = (enclosed == 1.0, round(enclosed, 1), round(clearance, 9), float(origin[1]))
        if best_key is None or key > best_key:
            best_key = key
            best = Placement(origin, float(distance[hit].mean()), enclosed == 1.0, enclosed)
    if best is not None and escapes:
        # a point hemmed in by objects is not a closed room when rays from another
        # point that sees no back get out: the mesh is open
        best = Placement(best.position, best.distance, False, best.enclosed)
    return best
