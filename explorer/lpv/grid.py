"""The one place where world coordinates and grid cells are related (docs/MODEL.md)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class GridSpec:
    """An axis-aligned cubic grid of ``resolution``³ cells of edge ``cell_size``.

    ``origin`` is the world position of the grid's minimum corner.
    """

    origin: tuple[float, float, float]
    cell_size: float
    resolution: int

    def __post_init__(self) -> None:
        if self.cell_size <= 0:
            raise ValueError(f"cell_size must be positive, got {self.cell_size}")
        if self.resolution < 1:
            raise ValueError(f"resolution must be at least 1, got {self.resolution}")

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
    def extent(self) -> float:
        return self.cell_size * self.resolution

    def grid_coords(self, world: np.ndarray) -> np.ndarray:
        """Continuous grid coordinates ``(p - origin) / cell_size`` (cell i spans [i, i+1))."""
        return (np.asarray(world, dtype=np.float64) - np.asarray(self.origin)) / self.cell_size

    def cell_index(self, world: np.ndarray) -> np.ndarray:
        """Integer cell index of each world point (may lie outside ``[0, N)``)."""
        return np.floor(self.grid_coords(world)).astype(np.int64)

    def cell_centre(self, index: np.ndarray) -> np.ndarray:
        """World position of the centre of cell ``index``."""
        index = np.asarray(index, dtype=np.float64)
        return np.asarray(self.origin) + (index + 0.5) * self.cell_size

    def inside(self, index: np.ndarray) -> np.ndarray:
        """Whether each integer cell index lies in the grid."""
        index = np.asarray(index)
        return np.all((index >= 0) & (index < self.resolution), axis=-1)

    def uniforms(self) -> dict[str, object]:
        """Uniform values for shaders that include ``grid.glsl``."""
        return {
            "u_grid_origin": tuple(float(v) for v in self.origin),
            "u_grid_cell_size": float(self.cell_size),
            "u_grid_resolution": int(self.resolution),
        }
