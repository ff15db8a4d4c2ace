"""The one place where world coordinates and grid cells are related (docs/MODEL.md)."""

from __future__ import annotations

import numbers
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np


def grid_cells(cells: int | Sequence[int]) -> tuple[int, int, int]:
    """``(nx, ny, nz)`` from one whole number (a cube) or three; a ValueError otherwise."""
    if type(cells) is tuple and len(cells) == 3 and type(cells[0]) is int and \
            type(cells[1]) is int and type(cells[2]) is int and min(cells) >= 1:
        return cells        # already one (the common case: no abstract-class checks)
    if isinstance(cells, numbers.Integral) and not isinstance(cells, bool):
        shape = (int(cells),) * 3
    else:
        shape = tuple(cells)
        if len(shape) != 3 or any(isinstance(n, bool) or not isinstance(n, numbers.Integral)
                                  for n in shape):
            raise ValueError(f"grid cells must be one whole number or three [nx, ny, nz], "
                             f"got {cells!r}")
        shape = tuple(int(n) for n in shape)
    if min(shape) < 1:
        raise ValueError(f"a grid needs at least 1 cell along each axis, got {shape}")
    return shape


def cube_edge(cells: Sequence[int]) -> int:
    """Cells per axis of a cubic grid; a ValueError naming the shape for another (what
    needs a cube says so through this)."""
    if len({int(n) for n in cells}) != 1:
        raise ValueError(f"this needs a cubic grid (N x N x N cells), the grid has "
                         f"{shape_text(cells)}")
    return int(cells[0])


def shape_text(cells: Sequence[int]) -> str:
    """How messages name a grid's cells: ``"8^3"`` for a cube, ``"7x12x5"`` otherwise."""
    shape = [int(n) for n in cells]
    if len(set(shape)) == 1:
        return f"{shape[0]}^3"
    return "x".join(str(n) for n in shape)


@dataclass(frozen=True, init=False)
class GridSpec:
    """An axis-aligned grid of ``nx × ny × nz`` cubic cells of edge ``cell_size``.

    ``origin`` is the world position of the grid's minimum corner. ``GridSpec(origin, h, n)``
    (or ``resolution=n``) is the cube of ``n`` cells per axis.
    """

    origin: tuple[float, float, float]
    cell_size: float
    cells: tuple[int, int, int] = field()

    def __init__(self, origin: Sequence[float], cell_size: float,
                 cells: int | Sequence[int] | None = None, *,
                 resolution: int | None = None) -> None:
        if (cells is None) == (resolution is None):
            raise ValueError("a GridSpec needs its cells (nx, ny, nz) or a cube's resolution")
        shape = grid_cells(cells if cells is not None else resolution)
        if not float(cell_size) > 0:
            raise ValueError(f"cell_size must be positive, got {cell_size}")
        corner = tuple(float(v) for v in origin)
        if len(corner) != 3:
            raise ValueError(f"origin must be three numbers (x, y, z), got {origin!r}")
        object.__setattr__(self, "origin", corner)
        object.__setattr__(self, "cell_size", float(cell_size))
        object.__setattr__(self, "cells", shape)

    @classmethod
    def enclosing(cls, bounds_min, bounds_max, resolution: int, margin_cells: float = 1.0
                  ) -> GridSpec:
        """The smallest cubic grid holding the box with ``margin_cells`` of room on each
        side, centred on the box."""
        lo = np.asarray(bounds_min, dtype=np.float64)
        hi = np.asarray(bounds_max, dtype=np.float64)
        extent = float(np.max(hi - lo))
        cell = extent / max(resolution - 2.0 * margin_cells, 1.0)
        centre = 0.5 * (lo + hi)
        origin = centre - 0.5 * cell * resolution
        return cls(tuple(float(v) for v in origin), cell, int(resolution))

    @property
    def is_cube(self) -> bool:
        return self.cells[0] == self.cells[1] == self.cells[2]

    @property
    def resolution(self) -> int:
        """Cells per axis of a cubic grid (:func:`cube_edge`)."""
        return cube_edge(self.cells)

    @property
    def cell_count(self) -> int:
        return self.cells[0] * self.cells[1] * self.cells[2]

    @property
    def extents(self) -> np.ndarray:
        """World size of the grid along x, y, z."""
        return self.cell_size * np.asarray(self.cells, np.float64)

    @property
    def extent(self) -> float:
        """Edge of a cubic grid (see :attr:`extents` for any shape)."""
        return self.cell_size * self.resolution

    def grid_coords(self, world: np.ndarray) -> np.ndarray:
        """Continuous grid coordinates ``(p - origin) / cell_size`` (cell i spans [i, i+1))."""
        return (np.asarray(world, dtype=np.float64) - np.asarray(self.origin)) / self.cell_size

    def cell_index(self, world: np.ndarray) -> np.ndarray:
        """Integer cell index of each world point (may lie outside the grid)."""
        return np.floor(self.grid_coords(world)).astype(np.int64)

    def cell_centre(self, index: np.ndarray) -> np.ndarray:
        """World position of the centre of cell ``index``."""
        index = np.asarray(index, dtype=np.float64)
        return np.asarray(self.origin) + (index + 0.5) * self.cell_size

    def inside(self, index: np.ndarray) -> np.ndarray:
        """Whether each integer cell index lies in the grid."""
        index = np.asarray(index)
        return np.all((index >= 0) & (index < np.asarray(self.cells)), axis=-1)

    def uniforms(self) -> dict[str, object]:
        """Uniform values for shaders that include ``grid.glsl``."""
        return {
            "u_grid_origin": tuple(float(v) for v in self.origin),
            "u_grid_cell_size": float(self.cell_size),
            "u_grid_cells": tuple(int(n) for n in self.cells),
        }
