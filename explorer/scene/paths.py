"""Animation paths: closed keyframe loops interpolated by a Catmull-Rom spline.

A scene may carry a path for its primary light (keys ``(position, target)``, 6 numbers),
one per object (keys of an :class:`~explorer.scene.objects.ObjectTransform`, 9 numbers)
and one for its camera (the atrium's fly-through, keys ``(eye, target)``). A path is a
closed loop of ``K`` keys taking ``period`` seconds; :meth:`KeyframePath.at` gives the
values at any time ``t`` (wrapping). Nothing here knows what the numbers mean: the
callers (:func:`explorer.scene.animation.pose_changes`) turn them into Settings fields.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def catmull_rom(points: np.ndarray, t: float | np.ndarray) -> np.ndarray:
    """The closed uniform Catmull-Rom spline through ``points`` (K, D) at ``t`` in [0, 1)
    (one K-th per segment): it passes through every point and its velocity is continuous
    (C¹), so a camera or an object on it never jerks."""
    points = np.asarray(points, np.float64)
    count = len(points)
    s = np.asarray(t, np.float64) % 1.0 * count
    index = np.floor(s).astype(int)
    f = (s - index)[..., None]
    p0, p1, p2, p3 = (points[(index + k) % count] for k in (-1, 0, 1, 2))
    return 0.5 * (2 * p1 + (p2 - p0) * f + (2 * p0 - 5 * p1 + 4 * p2 - p3) * f * f
                  + (3 * p1 - p0 - 3 * p2 + p3) * f * f * f)


@dataclass(frozen=True)
class KeyframePath:
    """A closed loop through ``keys`` (K rows of D numbers, K >= 2) lasting ``period``
    seconds."""

    keys: tuple[tuple[float, ...], ...]
    period: float

    def __post_init__(self) -> None:
        keys = np.asarray(self.keys, np.float64)
        if keys.ndim != 2 or len(keys) < 2 or not np.all(np.isfinite(keys)):
            raise ValueError(f"a path needs at least 2 keys of finite numbers, got shape "
                             f"{keys.shape}")
        if not (np.isfinite(self.period) and self.period > 0):
            raise ValueError(f"a path's period must be a positive number of seconds, got "
                             f"{self.period!r}")
        object.__setattr__(self, "keys", tuple(tuple(map(float, row)) for row in keys))
        object.__setattr__(self, "period", float(self.period))

    @property
    def width(self) -> int:
        """Numbers per key (D)."""
        return len(self.keys[0])

    def at(self, seconds: float) -> np.ndarray:
        """(D,) values at time ``seconds`` (the loop repeats every ``period``)."""
        return catmull_rom(np.asarray(self.keys), float(seconds) / self.period)
