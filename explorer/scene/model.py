"""A scene: a triangle soup with per-corner normals and linear albedo, a camera, a light,
and the box the light grid must enclose."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from explorer.scene.camera import Camera
from explorer.scene.lights import Light


class SceneError(ValueError):
    """A scene cannot be loaded or built: the message says what is wrong with which input."""


@dataclass(frozen=True)
class Scene:
    name: str
    positions: np.ndarray
    """(3T, 3) float32 world positions, three rows per triangle."""
    normals: np.ndarray
    """(3T, 3) float32 unit normals per triangle corner."""
    albedo: np.ndarray
    """(3T, 3) float32 linear diffuse reflectance in [0, 1] per corner."""
    camera: Camera
    light: Light
    bounds_min: tuple[float, float, float]
    bounds_max: tuple[float, float, float]
    """The box the LPV grid encloses (at least the geometry's bounding box)."""

    def __post_init__(self) -> None:
        count = len(self.positions)
        if count == 0 or count % 3:
            raise SceneError(f"scene {self.name!r} needs whole triangles, got {count} corners")
        for name in ("normals", "albedo"):
            if np.shape(getattr(self, name)) != (count, 3):
                raise SceneError(f"scene {self.name!r}: {name} must have shape ({count}, 3)")

    @property
    def triangle_count(self) -> int:
        return len(self.positions) // 3

    def vertex_bytes(self) -> bytes:
        """Interleaved ``position, normal, albedo`` float32 rows for a vertex buffer
        (format ``"3f 3f 3f"``)."""
        rows = np.hstack([self.positions, self.normals, self.albedo]).astype(np.float32)
        return np.ascontiguousarray(rows).tobytes()

    def with_overrides(self, camera=None, light=None, light_flux: float | None = None,
                       spot_cone: bool = True,
                       spot_cone_degrees: tuple[float, float] | None = None) -> "Scene":
        """The scene with ``Settings.camera`` / ``light`` / ``light_flux`` /
        ``spot_cone_degrees`` applied (``None`` keeps the scene's own); ``spot_cone``
        False turns a spot light's cone off (the 90° square frustum). A directional light
        ignores the two spot arguments."""
        scene = self
        if camera is not None:
            eye, target = camera
            scene = replace(scene, camera=replace(scene.camera, eye=tuple(map(float, eye)),
                                                  target=tuple(map(float, target))))
        if light is not None:
            position, target = light
            scene = replace(scene, light=scene.light.moved(position, target))
        if light_flux is not None:
            scene = replace(scene, light=scene.light.with_flux(light_flux))
        if hasattr(scene.light, "with_cone"):   # a spot light
            if not spot_cone:
                scene = replace(scene, light=scene.light.with_cone(None))
            elif spot_cone_degrees is not None:
                scene = replace(scene, light=scene.light.with_cone(spot_cone_degrees))
        return scene

    def for_settings(self, settings) -> "Scene":
        """The scene with every override of ``settings`` (an ``explorer.lpv.settings.
        Settings``) applied: camera, light, flux and the spot cone."""
        return self.with_overrides(settings.camera, settings.light, settings.light_flux,
                                   settings.spot_cone, settings.spot_cone_degrees)


class MeshBuilder:
    """Collects quads and boxes into a triangle soup (for the built-in scenes)."""

    def __init__(self) -> None:
        self._positions: list[np.ndarray] = []
        self._normals: list[np.ndarray] = []
        self._albedo: list[np.ndarray] = []

    def quad(self, corners, albedo) -> None:
        """A planar quad; ``corners`` counter-clockwise seen from the side its normal
        points to."""
        a, b, c, d = (np.asarray(p, np.float64) for p in corners)
        normal = np.cross(b - a, d - a)
        normal /= np.linalg.norm(normal)
        self._add(np.array([a, b, c, a, c, d]), np.tile(normal, (6, 1)), albedo)

    def rect(self, centre, normal, u_axis, half_u: float, half_v: float, albedo) -> None:
        """A rectangle facing ``normal`` with edges along ``u_axis`` and ``normal × u_axis``
        (half lengths ``half_u``, ``half_v``)."""
        centre = np.asarray(centre, np.float64)
        n = np.asarray(normal, np.float64)
        u = np.asarray(u_axis, np.float64)
        v = np.cross(n, u)
        u, v = u * half_u, v * half_v
        self.quad([centre - u - v, centre + u - v, centre + u + v, centre - u + v], albedo)

    def box(self, centre, size, albedo, rotation_y_degrees: float = 0.0) -> None:
        """A closed box with outward normals, turned about the vertical axis."""
        half = np.asarray(size, np.float64) / 2.0
        angle = math.radians(rotation_y_degrees)
        rot = np.array([[math.cos(angle), 0.0, math.sin(angle)], [0.0, 1.0, 0.0],
                        [-math.sin(angle), 0.0, math.cos(angle)]])
        centre = np.asarray(centre, np.float64)

        def corner(sx, sy, sz):
            return centre + rot @ (half * np.array([sx, sy, sz], np.float64))

        faces = [  # counter-clockwise seen from outside
            [(1, -1, -1), (1, 1, -1), (1, 1, 1), (1, -1, 1)],        # +x
            [(-1, -1, 1), (-1, 1, 1), (-1, 1, -1), (-1, -1, -1)],    # -x
            [(-1, 1, -1), (-1, 1, 1), (1, 1, 1), (1, 1, -1)],        # +y
            [(-1, -1, 1), (-1, -1, -1), (1, -1, -1), (1, -1, 1)],    # -y
            [(-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)],        # +z
            [(1, -1, -1), (-1, -1, -1), (-1, 1, -1), (1, 1, -1)],    # -z
        ]
        for face in faces:
            self.quad([corner(*c) for c in face], albedo)

    def add_triangles(self, positions, normals, albedo) -> None:
        """A triangle soup: ``(3T, 3)`` corner positions and normals, one albedo for all
        (the procedural scenes' curved parts)."""
        positions = np.asarray(positions, np.float64)
        normals = np.asarray(normals, np.float64)
        if positions.shape != normals.shape or positions.ndim != 2 or \
                positions.shape[1] != 3 or len(positions) % 3:
            raise ValueError(f"positions and normals must both be (3T, 3) arrays, got "
                             f"{positions.shape} and {normals.shape}")
        self._add(positions, normals, albedo)

    def _add(self, positions, normals, albedo) -> None:
        self._positions.append(positions)
        self._normals.append(normals)
        self._albedo.append(np.tile(np.asarray(albedo, np.float64), (len(positions), 1)))

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return tuple(np.vstack(parts).astype(np.float32)
                     for parts in (self._positions, self._normals, self._albedo))
