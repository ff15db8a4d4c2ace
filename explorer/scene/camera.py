"""The viewer's camera: a perspective pinhole looking from ``eye`` at ``target``."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from explorer.scene.transforms import look_at, perspective


@dataclass(frozen=True)
class Camera:
    eye: tuple[float, float, float]
    target: tuple[float, float, float]
    fov_y_degrees: float = 45.0

    def view_matrix(self) -> np.ndarray:
        return look_at(self.eye, self.target)

    def projection_matrix(self, aspect: float, bounds_min, bounds_max) -> np.ndarray:
        """Perspective projection whose depth range holds the whole scene box."""
        near, far = depth_range(self.eye, bounds_min, bounds_max)
        return perspective(self.fov_y_degrees, aspect, near, far)


def depth_range(eye, bounds_min, bounds_max) -> tuple[float, float]:
    """A near/far pair that keeps every point of the box in front of the far plane and
    keeps near small enough for an eye inside the box."""
    lo, hi = np.asarray(bounds_min, np.float64), np.asarray(bounds_max, np.float64)
    eye = np.asarray(eye, np.float64)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    farthest = float(np.max(np.linalg.norm(corners - eye, axis=1)))
    diagonal = float(np.linalg.norm(hi - lo))
    far = 1.05 * farthest + 1e-3
    near = max(far * 1e-4, 0.005 * max(diagonal, 1e-6))
    return near, far
