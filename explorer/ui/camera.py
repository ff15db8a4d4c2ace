"""Orbit a point around a target: the view camera (mouse drag, wheel) and the spot light
(azimuth/elevation sliders) both move this way. Pure functions over ``(eye, target)``
pairs, the form :class:`~explorer.lpv.settings.Settings` stores."""

from __future__ import annotations

import math

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
