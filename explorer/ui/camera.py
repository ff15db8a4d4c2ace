"""Camera moves as pure functions over ``(eye, target)`` pairs, the form
:class:`~explorer.lpv.settings.Settings` stores: orbit a point around a target (the view
camera's drag and wheel, the spot light's azimuth/elevation sliders), pan, frame a box or
a point, and fly (move the eye and target together, turn the target around the eye).
Conventions of :func:`explorer.scene.transforms.look_at`: y is up, the view looks from
eye to target."""

from __future__ import annotations

import math

import numpy as np

from explorer.scene.transforms import normalized, up_hint

Point = tuple[float, float, float]

_MAX_ELEVATION = 89.0  # degrees; the poles make the up vector degenerate


def to_angles(eye: Point, target: Point) -> tuple[float, float, float]:
    """(azimuth°, elevation°, distance) of ``eye`` seen from ``target``; y is up,
    azimuth 0 looks along +z."""
    dx, dy, dz = (eye[i] - target[i] for i in range(3))
    distance = math.sqrt(dx * dx + dy * dy + dz * dz)
    if distance == 0.0:
        return 0.0, 0.0, 0.0
    elevation = math.degrees(math.asin(max(-1.0, min(1.0, dy / distance))))
    azimuth = math.degrees(math.atan2(dx, dz))
    return azimuth, elevation, distance


def from_angles(target: Point, azimuth: float, elevation: float, distance: float) -> Point:
    elevation = max(-_MAX_ELEVATION, min(_MAX_ELEVATION, elevation))
    az, el = math.radians(azimuth), math.radians(elevation)
    return (
        target[0] + distance * math.cos(el) * math.sin(az),
        target[1] + distance * math.sin(el),
        target[2] + distance * math.cos(el) * math.cos(az),
    )


def orbit(eye: Point, target: Point, d_azimuth: float, d_elevation: float
          ) -> tuple[Point, Point]:
    """Turn ``eye`` around ``target`` by the given degrees."""
    azimuth, elevation, distance = to_angles(eye, target)
    return from_angles(target, azimuth + d_azimuth, elevation + d_elevation, distance), target


def dolly(eye: Point, target: Point, factor: float, min_distance: float = 1e-3
          ) -> tuple[Point, Point]:
    """Scale the eye–target distance by ``factor`` (wheel zoom)."""
    azimuth, elevation, distance = to_angles(eye, target)
    return from_angles(target, azimuth, elevation, max(distance * factor, min_distance)), target


def as_pair(value) -> tuple[Point, Point]:
    eye, target = value
    return tuple(float(v) for v in eye), tuple(float(v) for v in target)


def view_axes(eye: Point, target: Point) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(right, up, forward) unit vectors of the camera, as :func:`look_at` builds them."""
    forward = normalized(np.subtract(target, eye))
    right = normalized(np.cross(forward, up_hint(forward)))
    return right, np.cross(right, forward), forward


def _point(vector) -> Point:
    return tuple(float(v) for v in vector)


def pan(eye: Point, target: Point, dx_pixels: float, dy_pixels: float, view_height: float,
        fov_y_degrees: float) -> tuple[Point, Point]:
    """Slide eye and target across the view so that a point at the target's depth follows
    the mouse: one pixel is ``2·d·tan(fov/2)/view_height`` world units at distance d.
    ``dx``/``dy``: mouse motion in pixels (x right, y down)."""
    right, up, _ = view_axes(eye, target)
    distance = float(np.linalg.norm(np.subtract(target, eye)))
    per_pixel = 2.0 * distance * math.tan(math.radians(fov_y_degrees) / 2.0) / max(
        view_height, 1.0)
    shift = (-dx_pixels * right + dy_pixels * up) * per_pixel
    return _point(np.add(eye, shift)), _point(np.add(target, shift))


def frame_box(eye: Point, target: Point, bounds_min, bounds_max, fov_y_degrees: float,
              aspect: float, margin: float = 1.05) -> tuple[Point, Point]:
    """Look at the box's centre from the current direction, just far enough that the
    box's bounding sphere fits the narrower of the two fields of view."""
    lo, hi = np.asarray(bounds_min, np.float64), np.asarray(bounds_max, np.float64)
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo))
    half_y = math.radians(fov_y_degrees) / 2.0
    half_x = math.atan(math.tan(half_y) * aspect)
    distance = margin * radius / math.sin(min(half_x, half_y))
    _, _, forward = view_axes(eye, target)
    return _point(centre - distance * forward), _point(centre)


def frame_point(eye: Point, target: Point, point, distance: float | None = None
                ) -> tuple[Point, Point]:
    """Look at ``point`` from the current direction, at ``distance`` (default: the current
    eye–target distance)."""
    _, _, forward = view_axes(eye, target)
    if distance is None:
        distance = float(np.linalg.norm(np.subtract(target, eye)))
    point = np.asarray(point, np.float64)
    return _point(point - distance * forward), _point(point)


def fly_move(eye: Point, target: Point, forward: float, right: float, up: float
             ) -> tuple[Point, Point]:
    """Move eye and target together: ``forward`` along the view direction, ``right``
    along the camera's right, ``up`` along world +y (world units)."""
    axis_right, _, axis_forward = view_axes(eye, target)
    shift = forward * axis_forward + right * axis_right + up * np.array([0.0, 1.0, 0.0])
    return _point(np.add(eye, shift)), _point(np.add(target, shift))


def fly_look(eye: Point, target: Point, d_yaw: float, d_pitch: float) -> tuple[Point, Point]:
    """Turn the view around the eye (the eye stays put): the target moves on the sphere
    around the eye by ``d_yaw`` degrees of azimuth and ``d_pitch`` of elevation."""
    azimuth, elevation, distance = to_angles(target, eye)
    return eye, from_angles(eye, azimuth + d_yaw, elevation + d_pitch, distance)
