"""View and projection matrices (OpenGL conventions, column vectors, right-handed).

Matrices are numpy ``(4, 4)`` float64 arrays applied as ``M @ [x, y, z, 1]``; the view space
looks down ``-z``. :func:`gl_matrix` turns one into the column-major tuple a ``mat4``
uniform expects.
"""

from __future__ import annotations

import math

import numpy as np


def normalized(vector) -> np.ndarray:
    v = np.asarray(vector, dtype=np.float64)
    # np.linalg.norm's own sqrt(v·v) for a vector, without its general set-up
    length = math.sqrt(v.ravel().dot(v.ravel()))
    if not length > 0.0:
        raise ValueError(f"cannot normalise the zero vector {tuple(v)}")
    return v / length


def up_hint(forward: np.ndarray) -> np.ndarray:
    """A world up vector that is not parallel to ``forward`` (+y, or +z when looking
    straight up or down)."""
    return np.array([0.0, 0.0, -1.0]) if abs(forward[1]) > 0.999 else np.array([0.0, 1.0, 0.0])


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.cross`` of two 3-vectors, the same products and differences (so the same
    float64 bits) without its general-shape set-up, which costs ten times the arithmetic
    (a camera frame computes its view matrix every time)."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def look_at(eye, target, up=None) -> np.ndarray:
    """World -> view matrix of a camera at ``eye`` looking at ``target``."""
    eye = np.asarray(eye, dtype=np.float64)
    forward = normalized(np.asarray(target, dtype=np.float64) - eye)
    up = up_hint(forward) if up is None else np.asarray(up, dtype=np.float64)
    right = normalized(cross3(forward, up))
    true_up = cross3(right, forward)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = right, true_up, -forward
    view[:3, 3] = -view[:3, :3] @ eye
    return view


def perspective(fov_y_degrees: float, aspect: float, near: float, far: float) -> np.ndarray:
    """OpenGL perspective projection (clip ``w`` = view depth ``-z``)."""
    if not (0.0 < near < far):
        raise ValueError(f"need 0 < near < far, got near={near}, far={far}")
    f = 1.0 / math.tan(math.radians(fov_y_degrees) / 2.0)
    proj = np.zeros((4, 4))
    proj[0, 0] = f / aspect
    proj[1, 1] = f
    proj[2, 2] = (far + near) / (near - far)
    proj[2, 3] = 2.0 * far * near / (near - far)
    proj[3, 2] = -1.0
    return proj


def orthographic(half_width: float, half_height: float, near: float, far: float) -> np.ndarray:
    """OpenGL orthographic projection of the view box ``[-hw, hw]×[-hh, hh]×[-far, -near]``."""
    if not (half_width > 0 and half_height > 0 and far > near):
        raise ValueError("orthographic box must have positive size and far > near")
    proj = np.eye(4)
    proj[0, 0] = 1.0 / half_width
    proj[1, 1] = 1.0 / half_height
    proj[2, 2] = -2.0 / (far - near)
    proj[2, 3] = -(far + near) / (far - near)
    return proj


def gl_matrix(matrix: np.ndarray) -> tuple[float, ...]:
    """Column-major flattening for a GLSL ``mat4`` uniform."""
    return tuple(np.asarray(matrix, dtype=np.float64).T.ravel().tolist())
