"""The reference's own G-buffer raster (used when a frame carries none)."""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from explorer.truth.gbuffer import flipped, gbuffer_from_frame, oriented_like, rasterize_gbuffer


@dataclass
class TopCamera:
    """Looks straight down -y from height 2 with -z at the top of the picture."""

    def view_matrix(self) -> np.ndarray:
        right, up, back = np.array([1.0, 0, 0]), np.array([0, 0, -1.0]), np.array([0, 1.0, 0])
        view = np.eye(4)
        view[0, :3], view[1, :3], view[2, :3] = right, up, back
        view[:3, 3] = -view[:3, :3] @ np.array([0.0, 2.0, 0.0])
        return view

    def projection_matrix(self, aspect, bounds_min, bounds_max) -> np.ndarray:
        near, far = 0.1, 10.0  # 90° perspective
        proj = np.zeros((4, 4))
        proj[0, 0], proj[1, 1] = 1.0 / aspect, 1.0
        proj[2, 2], proj[2, 3] = (far + near) / (near - far), 2 * far * near / (near - far)
        proj[3, 2] = -1.0
        return proj


def floor_scene():
    """A 10 m floor at y = 0: red where z < 0, green where z > 0."""
    quads, colours = [], []
    for z0, z1, colour in ((-5.0, 0.0, (1.0, 0, 0)), (0.0, 5.0, (0, 1.0, 0))):
        a, b, c, d = ([-5.0, 0, z1], [5.0, 0, z1], [5.0, 0, z0], [-5.0, 0, z0])
        quads += [a, b, c, a, c, d]
        colours += [colour] * 6
    positions = np.array(quads, np.float32)
    normals = np.tile(np.float32([0, 1, 0]), (len(positions), 1))
    albedo = np.array(colours, np.float32)
    return SimpleNamespace(
        positions=positions, normals=normals, albedo=albedo, camera=TopCamera(),
        bounds_min=(-5, 0, -5), bounds_max=(5, 0, 5),
        vertex_bytes=lambda: np.hstack([positions, normals, albedo]).astype(np.float32)
        .tobytes())


def test_raster_gbuffer_sees_the_floor(ctx):
    gbuffer = rasterize_gbuffer(ctx, floor_scene(), 8, 6)
    assert gbuffer.valid.all()
    np.testing.assert_allclose(gbuffer.position[..., 1], 0.0, atol=1e-5)
    np.testing.assert_allclose(gbuffer.normal, np.broadcast_to([0, 1, 0], (6, 8, 3)), atol=1e-6)
    # rows come back bottom first: the bottom of the picture is +z (green)
    assert np.all(gbuffer.albedo[0] == [0, 1, 0]) and np.all(gbuffer.albedo[-1] == [1, 0, 0])
    assert np.all(np.diff(gbuffer.position[:, 0, 2]) < 0)


def test_gbuffer_follows_the_frames_row_order(ctx):
    scene = floor_scene()
    bottom_first = rasterize_gbuffer(ctx, scene, 8, 6)
    top_first = flipped(bottom_first)
    assert oriented_like(bottom_first, top_first.albedo) is not bottom_first
    frame = SimpleNamespace(albedo=top_first.albedo)
    from_frame = gbuffer_from_frame(frame, scene, ctx)
    np.testing.assert_array_equal(from_frame.position, top_first.position)
    # a frame with its own G-buffer is used as it is
    own = SimpleNamespace(albedo=bottom_first.albedo,
                          gbuffer_position=np.concatenate(
                              [bottom_first.position, np.ones((6, 8, 1))], axis=-1),
                          gbuffer_normal=bottom_first.normal)
    np.testing.assert_array_equal(gbuffer_from_frame(own).position, bottom_first.position)
