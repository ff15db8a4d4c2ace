"""Objects of a scene: named ranges of its triangle soup that can be moved.

A :class:`SceneObject` is a run of whole triangles (``first`` .. ``first + count`` corners)
with a pivot (the centre of its bounding box as built). An :class:`ObjectTransform`
(translation, rotation in degrees about x, y and z, scale per axis) moves it about its
pivot: a corner ``p`` goes to ``M·p`` with

``M = T(pivot + translation) · Rz · Ry · Rx · S · T(−pivot)``

(x rotation applied first: the order ImGuizmo's ``RecomposeMatrixFromComponents`` uses),
and a normal ``n`` to ``normalize((R·S)⁻ᵀ·n) = normalize(R·S⁻¹·n)``. The scene's box (what
the light grid encloses) does not move with its objects: an object moved out of it leaves
the LPV.

Transforms travel in :class:`explorer.lpv.settings.Settings` as nine numbers
``[tx, ty, tz, rx, ry, rz, sx, sy, sz]`` per object name (:func:`check_transforms`).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

IDENTITY_VALUES = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0)
MIN_SCALE = 0.01
MAX_SCALE = 100.0
MAX_OFFSET = 1e6
"""Largest translation (world units) and rotation (degrees) a transform may hold."""


@dataclass(frozen=True)
class SceneObject:
    """``count`` corners (whole triangles) from corner ``first`` of the scene's arrays,
    moved about ``pivot``."""

    name: str
    first: int
    count: int
    pivot: tuple[float, float, float]

    @property
    def stop(self) -> int:
        return self.first + self.count


@dataclass(frozen=True)
class ObjectTransform:
    """Translation, rotation (degrees about x, then y, then z) and scale of one object."""

    translation: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation_degrees: tuple[float, float, float] = (0.0, 0.0, 0.0)
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)

    @classmethod
    def from_values(cls, values) -> ObjectTransform:
        """From nine numbers ``[tx, ty, tz, rx, ry, rz, sx, sy, sz]``."""
        v = tuple(float(x) for x in values)
        return cls(v[0:3], v[3:6], v[6:9])

    def values(self) -> tuple[float, ...]:
        return (*self.translation, *self.rotation_degrees, *self.scale)

    @property
    def is_identity(self) -> bool:
        return self.values() == IDENTITY_VALUES

    def rotation(self) -> np.ndarray:
        """``Rz·Ry·Rx`` (3, 3)."""
        rx, ry, rz = (math.radians(a) for a in self.rotation_degrees)
        cx, sx, cy, sy, cz, sz = (math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry),
                                  math.cos(rz), math.sin(rz))
        x = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
        y = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
        z = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
        return z @ y @ x

    def linear(self) -> np.ndarray:
        """``R·S`` (3, 3): the part that turns and stretches."""
        return self.rotation() * np.asarray(self.scale, np.float64)[None, :]

    def model_matrix(self, pivot) -> np.ndarray:
        """``T(pivot + translation)·R·S`` (4, 4): the object's frame in the world (what a
        gizmo shows and edits); :meth:`matrix` is this times ``T(−pivot)``."""
        matrix = np.eye(4)
        matrix[:3, :3] = self.linear()
        matrix[:3, 3] = np.asarray(pivot, np.float64) + np.asarray(self.translation)
        return matrix

    def matrix(self, pivot) -> np.ndarray:
        """The (4, 4) matrix that moves the object's corners (module docstring)."""
        shift = np.eye(4)
        shift[:3, 3] = -np.asarray(pivot, np.float64)
        return self.model_matrix(pivot) @ shift

    @classmethod
    def from_model_matrix(cls, matrix, pivot) -> ObjectTransform:
        """The transform whose :meth:`model_matrix` is ``matrix`` (rotation and positive
        scale; a shear, which no transform holds, is dropped): the inverse of
        :meth:`model_matrix`, for a gizmo's result."""
        matrix = np.asarray(matrix, np.float64).reshape(4, 4)
        linear = matrix[:3, :3]
        scale = np.linalg.norm(linear, axis=0)
        if np.any(scale <= 0) or not np.all(np.isfinite(matrix)):
            raise ValueError("the matrix has no usable rotation and scale")
        rotation = linear / scale[None, :]
        if np.linalg.det(rotation) < 0:
            raise ValueError("the matrix mirrors the object, which no transform holds")
        # R = Rz·Ry·Rx: R[2,0] = −sin(ry), R[2,1] = cos(ry)·sin(rx), R[1,0] = sin(rz)·cos(ry)
        ry = math.asin(float(np.clip(-rotation[2, 0], -1.0, 1.0)))
        if abs(math.cos(ry)) > 1e-9:
            rx = math.atan2(rotation[2, 1], rotation[2, 2])
            rz = math.atan2(rotation[1, 0], rotation[0, 0])
        else:                                 # gimbal lock: only rx − rz (or rx + rz) counts
            rx = math.atan2(-rotation[1, 2], rotation[1, 1])
            rz = 0.0
        translation = matrix[:3, 3] - np.asarray(pivot, np.float64)
        return cls(tuple(map(float, translation)),
                   tuple(math.degrees(a) for a in (rx, ry, rz)), tuple(map(float, scale)))


def transform_corners(positions: np.ndarray, normals: np.ndarray, transform: ObjectTransform,
                      pivot) -> tuple[np.ndarray, np.ndarray]:
    """``(positions', normals')`` of an object's corners moved by ``transform`` (module
    docstring): normals by the inverse transpose of ``R·S``, renormalised."""
    matrix = transform.matrix(pivot)
    moved = np.asarray(positions, np.float64) @ matrix[:3, :3].T + matrix[:3, 3]
    normal_matrix = np.linalg.inv(transform.linear()).T
    turned = np.asarray(normals, np.float64) @ normal_matrix.T
    turned /= np.linalg.norm(turned, axis=1, keepdims=True)
    return moved, turned


def check_transform_values(values: Any) -> tuple[float, ...] | None:
    """Nine floats from 3 (translation), 6 (+ rotation) or 9 (+ scale) finite numbers, or
    None when ``values`` is not such a list or a number is out of range (each scale in
    [:data:`MIN_SCALE`, :data:`MAX_SCALE`], the others within ±:data:`MAX_OFFSET`)."""
    if isinstance(values, (str, bytes, Mapping)):
        return None
    try:
        items = list(values)
    except TypeError:
        return None
    if len(items) not in (3, 6, 9) or any(
            isinstance(v, bool) or not isinstance(v, numbers.Real) for v in items):
        return None
    numbers_ = [float(v) for v in items] + list(IDENTITY_VALUES[len(items):])
    if not all(math.isfinite(v) for v in numbers_):
        return None
    if any(abs(v) > MAX_OFFSET for v in numbers_[:6]):
        return None
    if any(not MIN_SCALE <= v <= MAX_SCALE for v in numbers_[6:]):
        return None
    return tuple(numbers_)


def check_transforms(value: Any) -> tuple[tuple[str, tuple[float, ...]], ...] | None:
    """Object transforms as ``((name, nine numbers), ...)`` sorted by name, from a table
    ``{name: numbers}`` or a list of ``[name, numbers]`` pairs; None when malformed (a
    name that is not a non-empty text, a name twice, bad numbers)."""
    if isinstance(value, Mapping):
        pairs = list(value.items())
    elif isinstance(value, (str, bytes)):
        return None
    else:
        try:
            pairs = [tuple(pair) for pair in value]
        except TypeError:
            return None
        if any(len(pair) != 2 for pair in pairs):
            return None
    checked = {}
    for name, numbers_ in pairs:
        if not isinstance(name, str) or not name.strip() or name in checked:
            return None
        values = check_transform_values(numbers_)
        if values is None:
            return None
        checked[name] = values
    return tuple(sorted(checked.items()))
