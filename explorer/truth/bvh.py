"""A small bounding-volume hierarchy for the reference renderer's shadow rays.

The built-in scenes have tens to a few thousand triangles; a median-split BVH built in
numpy once per scene keeps every shadow ray at O(log T) box tests on the GPU
(``shaders/reference_gather.glsl`` walks it with a fixed-size stack).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Matches ``struct Node`` in reference_gather.glsl under std430: a vec3 followed by an int
# packs into 16 bytes, so one node is 32 bytes.
NODE_DTYPE = np.dtype([("lo", "<f4", (3,)), ("left_or_first", "<i4"),
                       ("hi", "<f4", (3,)), ("count", "<i4")])
# The shader's traversal stack holds at most depth + 1 entries (each pop pushes two).
MAX_DEPTH = 60


@dataclass(frozen=True)
class Bvh:
    """``triangles`` (T, 3, 3) in leaf order; ``nodes`` in depth-first order, the left
    child of an inner node right after it, the right child at ``left_or_first``."""

    triangles: np.ndarray
    nodes: np.ndarray
    depth: int

    @property
    def triangle_count(self) -> int:
        return int(self.triangles.shape[0])


def as_triangles(triangles: np.ndarray) -> np.ndarray:
    """Validate a triangle soup and return it as float64 (T, 3, 3)."""
    array = np.asarray(triangles, dtype=np.float64)
    if array.ndim != 3 or array.shape[1:] != (3, 3):
        raise ValueError(f"triangles must have shape (T, 3, 3), got {array.shape}")
    if not np.all(np.isfinite(array)):
        raise ValueError("triangles contain NaN or infinite coordinates")
    return array


def build_bvh(triangles: np.ndarray, leaf_size: int = 4) -> Bvh:
    """Median split on the longest axis of the centroid bounds, down to ``leaf_size``."""
    if leaf_size < 1:
        raise ValueError(f"leaf_size must be at least 1, got {leaf_size}")
    tris = as_triangles(triangles)
    count = tris.shape[0]
    if count == 0:
        return Bvh(np.zeros((0, 3, 3), np.float32), np.zeros(0, NODE_DTYPE), 0)
    # Pad the boxes so flat boxes (a wall is one) survive float rounding in the slab test.
    pad = 1e-5 * max(float(np.ptp(tris.reshape(-1, 3), axis=0).max()), 1e-12)
    centroids = tris.mean(axis=1)
    order = np.arange(count)
    nodes: list[tuple] = []
    deepest = 0

    def build(first: int, end: int, depth: int) -> None:
        nonlocal deepest
        deepest = max(deepest, depth)
        index = len(nodes)
        corners = tris[order[first:end]].reshape(-1, 3)
        lo, hi = corners.min(axis=0) - pad, corners.max(axis=0) + pad
        size = end - first
        if size <= leaf_size or depth >= MAX_DEPTH:
            nodes.append((lo, first, hi, size))
            return
        nodes.append(None)  # filled once the right child's index is known
        span = centroids[order[first:end]]
        axis = int(np.argmax(span.max(axis=0) - span.min(axis=0)))
        order[first:end] = order[first:end][np.argsort(span[:, axis], kind="stable")]
        middle = first + size // 2
        build(first, middle, depth + 1)
        right = len(nodes)
        build(middle, end, depth + 1)
        nodes[index] = (lo, right, hi, 0)

    build(0, count, 0)
    packed = np.zeros(len(nodes), NODE_DTYPE)
    for i, (lo, left_or_first, hi, size) in enumerate(nodes):
        packed[i] = (lo, left_or_first, hi, size)
    return Bvh(tris[order].astype(np.float32), packed, deepest)
