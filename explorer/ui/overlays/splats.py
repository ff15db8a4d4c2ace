"""Oriented discs in the scene (VPLs, geometry-volume blockers, the picked point): one
instanced draw per named set of quantities.Splats."""

from __future__ import annotations

import math

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import scoped
from explorer.scene.transforms import gl_matrix
from explorer.ui.overlays.instanced import InstancedMesh
from explorer.ui.overlays.quantities import Splats

PROGRAM = "overlay_splat.glsl"
DISC_SEGMENTS = 8


def disc_mesh(segments: int = DISC_SEGMENTS) -> tuple[np.ndarray, np.ndarray]:
    """(segments + 1, 2) points of the unit disc (its centre, then the rim) and the
    (3·segments,) indices of its triangle fan: indexed, each point is shaded once."""
    angles = np.arange(segments) * (2.0 * math.pi / segments)
    points = np.concatenate([np.zeros((1, 2)), np.stack([np.cos(angles), np.sin(angles)], -1)])
    fan = [(0, 1 + i, 1 + (i + 1) % segments) for i in range(segments)]
    return points.astype(np.float32), np.asarray(fan, np.int32).ravel()


class SplatRenderer:
    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        points, fan = disc_mesh()
        self._mesh = InstancedMesh(ctx, programs, PROGRAM, points, "2f", ("in_disc",),
                                   "3f 3f 3f 1f", ("in_position", "in_normal", "in_colour",
                                                   "in_radius"), fan)

    def upload(self, name: str, splats: Splats) -> None:
        self._mesh.upload(name, splats.packed())

    def count(self, name: str) -> int:
        return self._mesh.count(name)

    def draw(self, target: moderngl.Framebuffer, view_projection: np.ndarray, name: str,
             instances: int | None = None, lift: float = 0.0, radius_scale: float = 1.0,
             on_top: bool = False) -> None:
        """The first ``instances`` discs of set ``name``, radii times ``radius_scale``,
        each lifted by ``lift`` along its normal; depth-tested unless ``on_top``."""
        program = self._mesh.program()
        set_uniforms(program, {"u_view_projection": gl_matrix(view_projection),
                               "u_lift": float(lift), "u_radius_scale": float(radius_scale)})
        flags = moderngl.NOTHING if on_top else moderngl.DEPTH_TEST
        with scoped(self.ctx, target, flags):
            self._mesh.render(name, instances)

    def release(self) -> None:
        self._mesh.release()
