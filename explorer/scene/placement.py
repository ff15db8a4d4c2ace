"""Where to put a light in a mesh that comes without one: inside it when it is closed.

A point is *inside a room* when every ray from it meets a triangle and the first triangle
each ray meets shows it its front (the side the triangle's normal points to): the walls
face the point. A point outside a closed mesh, or inside a solid block (whose faces point
away from it), fails. Candidates are the points of a regular lattice in the mesh's box;
of those inside a room the one farthest from its nearest wall is chosen (the light then
sits as far as it can from every surface, so no wall is lit at a grazing hot spot).

The rays are cast in numpy (Möller–Trumbore), in chunks of triangles, so that a mesh of
tens of thousands of triangles is tested in about a second.
"""

from __future__ import annotations

import math

import numpy as np

from explorer.scene.model import Scene

RAY_DIRECTIONS = 26
"""Rays per candidate: a Fibonacci sphere (even coverage, no axis-aligned gaps)."""
MAX_WORK = 2.0e7
"""Largest (rays × triangles) pairs tested: fewer candidates for larger meshes."""
LATTICE_STEPS = (5, 3, 1)
"""Candidates per axis tried in order, the first whose work fits ``MAX_WORK``."""
CHUNK_PAIRS = 2_000_000


def fibonacci_directions(count: int) -> np.ndarray:
    """(count, 3) unit vectors spread evenly over the sphere."""
    k = np.arange(count, dtype=np.float64) + 0.5
    z = 1.0 - 2.0 * k / count
    radius = np.sqrt(1.0 - z * z)
    angle = k * math.pi * (3.0 - math.sqrt(5.0))
    return np.stack([radius * np.cos(angle), z, radius * np.sin(angle)], axis=1)


def first_hits(origins: np.ndarray, directions: np.ndarray, corners: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """For R rays (``origins``, ``directions`` (R, 3)) and T triangles ``corners``
    (T, 3, 3): the distance to the nearest triangle each ray meets (inf: none) and that
    triangle's index (−1: none)."""
    a = corners[:, 0]
    edge1, edge2 = corners[:, 1] - a, corners[:, 2] - a
    best = np.full(len(origins), np.inf)
    which = np.full(len(origins), -1)
    step = max(1, CHUNK_PAIRS // max(len(origins), 1))
    for start in range(0, len(corners), step):
        e1, e2, a0 = edge1[start:start + step], edge2[start:start + step], a[start:start + step]
        p = np.cross(directions[:, None, :], e2[None])                   # (R, t, 3)
        det = np.einsum("rtj,tj->rt", p, e1)
        usable = np.abs(det) > 1e-12
        inverse = np.where(usable, 1.0 / np.where(usable, det, 1.0), 0.0)
        s = origins[:, None, :] - a0[None]
        u = np.einsum("rtj,rtj->rt", s, p) * inverse
        q = np.cross(s, e1[None])
        v = np.einsum("rj,rtj->rt", directions, q) * inverse
        t = np.einsum("rtj,tj->rt", q, e2) * inverse
        hit = usable & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
        t = np.where(hit, t, np.inf)
        nearest = np.argmin(t, axis=1)
        distance = t[np.arange(len(origins)), nearest]
        closer = distance < best
        best[closer] = distance[closer]
        which[closer] = start + nearest[closer]
    return best, which


def light_inside(scene: Scene) -> tuple[np.ndarray, float] | None:
    """``(position, mean distance to the walls)`` of the point inside the closed mesh
    farthest from its nearest wall, or None when no candidate is inside a room (the mesh
    is open, or its rooms are thinner than the lattice)."""
    corners = np.asarray(scene.positions, np.float64).reshape(-1, 3, 3)
    lo, hi = np.asarray(scene.bounds_min, np.float64), np.asarray(scene.bounds_max, np.float64)
    directions = fibonacci_directions(RAY_DIRECTIONS)
    steps = next((n for n in LATTICE_STEPS
                  if n ** 3 * RAY_DIRECTIONS * len(corners) <= MAX_WORK), 1)
    fractions = (np.arange(steps) + 0.5) / steps
    grid = np.stack(np.meshgrid(fractions, fractions, fractions, indexing="ij"), -1)
    candidates = lo + grid.reshape(-1, 3) * (hi - lo)
    origins = np.repeat(candidates, len(directions), axis=0)
    rays = np.tile(directions, (len(candidates), 1))
    distance, triangle = first_hits(origins, rays, corners)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    facing = np.einsum("rj,rj->r", normals[np.maximum(triangle, 0)], rays) < 0.0
    inside = (np.isfinite(distance) & facing).reshape(len(candidates), -1).all(axis=1)
    if not inside.any():
        return None
    per_candidate = distance.reshape(len(candidates), -1)
    clearance = np.where(inside, per_candidate.min(axis=1), -np.inf)
    # the clearest candidate; of equally clear ones, the highest (lights hang from above)
    best = max(range(len(candidates)),
               key=lambda k: (round(float(clearance[k]), 9), candidates[k][1]))
    return candidates[best], float(per_candidate[best].mean())
