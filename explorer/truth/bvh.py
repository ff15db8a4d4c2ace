"""A small bounding-volume hierarchy for the reference renderer's shadow rays.

The built-in scenes have tens to a few thousand triangles; a median-split BVH built in
numpy once per scene keeps every shadow ray at O(log T) box tests on the GPU
(``shaders/reference_gather.glsl`` walks it with a fixed-size stack).
"""

from __future__ import annotations

import time
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
    builder = BvhBuilder(triangles, leaf_size)
    while not builder.done:
        builder.step(len(builder.triangles) + 1)
    return builder.result()


class BvhBuilder:
    """:func:`build_bvh` a few nodes at a time, so that a window builds a large scene's BVH
    between its frames: the atrium's 186 000 triangles make 131 071 nodes, seconds of work
    in all, of which the largest single node (the root: a sort of every centroid) takes
    milliseconds. :meth:`step` builds a given number of nodes, :meth:`advance` builds nodes
    for a time budget; the finished :meth:`result` is the same BVH whatever the steps.

    The recursion of a median split is kept on an explicit stack: a node's left subtree
    is built first, then its right child's index (the next free node) is linked into it,
    then its right subtree, which is the depth-first order the shader walks."""

    def __init__(self, triangles: np.ndarray, leaf_size: int = 4) -> None:
        if leaf_size < 1:
            raise ValueError(f"leaf_size must be at least 1, got {leaf_size}")
        tris = as_triangles(triangles)
        self.triangles = tris
        self.leaf_size = int(leaf_size)
        count = tris.shape[0]
        self._centroids = tris.mean(axis=1)
        self._lows, self._highs = tris.min(axis=1), tris.max(axis=1)   # per triangle
        # Pad the boxes so flat boxes (a wall is one) survive float rounding in the slab
        # test.
        extent = (self._highs.max(axis=0) - self._lows.min(axis=0)).max() if count else 0.0
        self._pad = 1e-5 * max(float(extent), 1e-12)
        self._order = np.arange(count)
        capacity = max(2 * count - 1, 0)        # a binary tree with at most `count` leaves
        self._lo = np.zeros((capacity, 3))
        self._hi = np.zeros((capacity, 3))
        self._link = np.zeros(capacity, np.int64)   # left_or_first
        self._size = np.zeros(capacity, np.int64)   # count (0: an inner node)
        self.nodes_built = 0
        self.placed = 0
        """Triangles in finished leaves (the fraction done)."""
        self.depth = 0
        self._stack: list[tuple] = [("node", 0, count, 0)] if count else []

    @property
    def done(self) -> bool:
        return not self._stack

    @property
    def fraction(self) -> float:
        count = len(self.triangles)
        return self.placed / count if count else 1.0

    def step(self, nodes: int = 1) -> int:
        """Build up to ``nodes`` more nodes; returns how many were built (0 once done)."""
        built = 0
        while self._stack and built < nodes:
            entry = self._stack.pop()
            if entry[0] == "link":              # the left subtree is done: its sibling
                self._link[entry[1]] = self.nodes_built      # starts at the next node
                continue
            self._build(*entry[1:])
            built += 1
        return built

    def advance(self, budget_s: float) -> int:
        """Build nodes for about ``budget_s`` seconds (at least one while any is left);
        returns how many were built."""
        start = time.perf_counter()
        built = self.step(1)
        while not self.done and time.perf_counter() - start < budget_s:
            built += self.step(1)            # the clock costs far less than a node
        return built

    def _build(self, first: int, end: int, depth: int) -> None:
        self.depth = max(self.depth, depth)
        index = self.nodes_built
        self.nodes_built += 1
        members = self._order[first:end]
        self._lo[index] = self._lows[members].min(axis=0) - self._pad
        self._hi[index] = self._highs[members].max(axis=0) + self._pad
        size = end - first
        if size <= self.leaf_size or depth >= MAX_DEPTH:
            self._link[index], self._size[index] = first, size
            self.placed += size
            return
        span = self._centroids[members]
        axis = int(np.argmax(span.max(axis=0) - span.min(axis=0)))
        self._order[first:end] = members[np.argsort(span[:, axis], kind="stable")]
        middle = first + size // 2
        # popped in reverse: the left subtree, then the link, then the right subtree
        self._stack += [("node", middle, end, depth + 1), ("link", index),
                        ("node", first, middle, depth + 1)]

    def result(self) -> Bvh:
        """The finished BVH (raises while nodes are left to build)."""
        if not self.done:
            raise RuntimeError(f"the BVH is not finished: {self.nodes_built} nodes built, "
                               f"{self.fraction:.0%} of the triangles placed")
        count = self.nodes_built
        packed = np.zeros(count, NODE_DTYPE)
        packed["lo"], packed["hi"] = self._lo[:count], self._hi[:count]
        packed["left_or_first"], packed["count"] = self._link[:count], self._size[:count]
        return Bvh(self.triangles[self._order].astype(np.float32), packed, self.depth)
