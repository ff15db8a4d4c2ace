"""Camera moves of the View panel (explorer/ui/camera.py): pan, frame a box or a point,
fly. Pure math over (eye, target) pairs, checked against the projection the G-buffer
pass uses (explorer/scene)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from explorer.scene.camera import Camera
from explorer.ui import camera

EYE, TARGET = (0.3, 0.8, 3.5), (0.0, 0.1, 0.0)


def _direction(eye, target) -> np.ndarray:
    d = np.subtract(target, eye)
    return d / np.linalg.norm(d)


def _ndc(eye, target, points, aspect, fov=45.0) -> np.ndarray:
    cam = Camera(tuple(eye), tuple(target), fov)
    lo, hi = points.min(axis=0), points.max(axis=0)
    matrix = cam.projection_matrix(aspect, lo, hi) @ cam.view_matrix()
    clip = np.c_[points, np.ones(len(points))] @ matrix.T
    return clip[:, :3] / clip[:, 3:]


def test_view_axes_match_look_at():
    from explorer.scene.transforms import look_at

    right, up, forward = camera.view_axes(EYE, TARGET)
    view = look_at(EYE, TARGET)
    assert np.allclose(view[0, :3], right) and np.allclose(view[1, :3], up)
    assert np.allclose(view[2, :3], -forward)
    assert abs(np.dot(right, up)) < 1e-12 and abs(np.dot(right, forward)) < 1e-12


def test_pan_moves_a_point_at_the_target_depth_with_the_mouse():
    """After a pan by (dx, dy) pixels the old target projects (dx, dy) pixels from the
    image centre: the scene follows the mouse."""
    height, fov, aspect = 600.0, 45.0, 4.0 / 3.0
    dx, dy = 40.0, -25.0
    eye, target = camera.pan(EYE, TARGET, dx, dy, height, fov)
    assert np.allclose(np.subtract(target, eye), np.subtract(TARGET, EYE))   # same view
    ndc = _ndc(eye, target, np.array([TARGET, (2, 2, 2), (-2, -2, -2)], float), aspect, fov)
    pixel = ((ndc[0, 0] + 1) * 0.5 * height * aspect, (1 - ndc[0, 1]) * 0.5 * height)
    centre = (0.5 * height * aspect, 0.5 * height)
    assert pixel[0] - centre[0] == pytest.approx(dx, abs=1e-6)
    assert pixel[1] - centre[1] == pytest.approx(dy, abs=1e-6)


@pytest.mark.parametrize("aspect", [0.5, 1.0, 2.0])
def test_frame_box_shows_the_whole_box_from_the_same_direction(aspect):
    lo, hi = np.array([-1.0, -1.0, -1.0]), np.array([1.0, 3.0, 0.5])
    far_eye = (40.0, 5.0, 60.0)
    eye, target = camera.frame_box(far_eye, TARGET, lo, hi, 45.0, aspect)
    assert np.allclose(target, 0.5 * (lo + hi))
    assert np.allclose(_direction(eye, target), _direction(far_eye, TARGET))
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    ndc = _ndc(eye, target, corners, aspect)
    assert np.all(np.abs(ndc[:, :2]) <= 1.0)
    # and not absurdly far: the box fills a good part of the narrower side
    assert np.max(np.abs(ndc[:, :2])) > 0.5


def test_frame_point_keeps_direction_and_distance():
    point = (0.5, -0.2, 0.7)
    eye, target = camera.frame_point(EYE, TARGET, point)
    assert np.allclose(target, point)
    assert np.allclose(_direction(eye, target), _direction(EYE, TARGET))
    assert np.linalg.norm(np.subtract(target, eye)) == pytest.approx(
        np.linalg.norm(np.subtract(TARGET, EYE)))
    eye, target = camera.frame_point(EYE, TARGET, point, distance=0.25)
    assert np.linalg.norm(np.subtract(target, eye)) == pytest.approx(0.25)


def test_fly_move_translates_along_the_view_axes():
    right, _, forward = camera.view_axes(EYE, TARGET)
    eye, target = camera.fly_move(EYE, TARGET, 2.0, -0.5, 0.25)
    expected = 2.0 * forward - 0.5 * right + np.array([0.0, 0.25, 0.0])
    assert np.allclose(np.subtract(eye, EYE), expected)
    assert np.allclose(np.subtract(target, TARGET), expected)


def test_fly_look_turns_around_the_eye():
    eye, target = camera.fly_look(EYE, TARGET, 30.0, -10.0)
    assert eye == EYE
    assert np.linalg.norm(np.subtract(target, eye)) == pytest.approx(
        np.linalg.norm(np.subtract(TARGET, EYE)))
    az0, el0, _ = camera.to_angles(TARGET, EYE)
    az1, el1, _ = camera.to_angles(target, eye)
    assert (az1 - az0 - 30.0 + 180.0) % 360.0 - 180.0 == pytest.approx(0.0, abs=1e-9)
    assert el1 - el0 == pytest.approx(-10.0)
    # looking back the other way returns to the start
    back = camera.fly_look(eye, target, -30.0, 10.0)[1]
    assert np.allclose(back, TARGET)


def test_fly_look_stops_short_of_the_poles():
    _, target = camera.fly_look(EYE, TARGET, 0.0, 500.0)
    _, elevation, _ = camera.to_angles(target, EYE)
    assert elevation < 90.0 and math.isfinite(elevation)
