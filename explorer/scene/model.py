"""A scene: a triangle soup with per-corner normals, linear albedo and texture coordinates,
its base-colour textures and which triangles are one-sided, a camera, a rig of lights, the
objects that can move, their animation paths, and the box the light grid must enclose."""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field, replace

import numpy as np

from explorer.scene.camera import Camera
from explorer.scene.lights import Light
from explorer.scene.objects import (
    ObjectTransform,
    SceneObject,
    check_transforms,
    transform_corners,
)
from explorer.scene.paths import KeyframePath

MAX_LIGHTS = 8
"""Lights that may shine at once (a point light renders six RSM faces: 48 at most)."""


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
    rig: tuple[Light, ...]
    """Every light the scene offers (a single light is accepted and made a 1-tuple);
    :attr:`lights_on` says which shine."""
    bounds_min: tuple[float, float, float]
    bounds_max: tuple[float, float, float]
    """The box the LPV grid encloses (at least the geometry's bounding box). Moving an
    object does not move it."""
    objects: tuple[SceneObject, ...] = ()
    """The parts that can be moved (explorer/scene/objects.py); triangles in no object
    stay put."""
    lights_on: tuple[str, ...] | None = None
    """Names of the rig's lights that shine, the first being the *primary* light (the one
    ``Settings.light``, ``light_flux`` and ``spot_cone_degrees`` override); None: all."""
    light_path: KeyframePath | None = None
    """The primary light's animation: keys ``(position, target)``."""
    object_paths: tuple[tuple[str, KeyframePath], ...] = ()
    """Animations of objects by name: keys of nine transform numbers."""
    camera_path: KeyframePath | None = None
    """A camera path (keys ``(eye, target)``, one loop per unit of its parameter): the
    atrium's fly-through."""
    exact_grid: tuple[tuple[int, int, int], tuple[float, float, float], float] | None = None
    """``(cells, origin, cell_size)`` of the light grid a scene file gives exactly
    ([grid] cells, origin, cell_size); None: the grid is fitted around the bounds."""
    pose: tuple[tuple[str, tuple[float, ...]], ...] = ()
    """The object transforms :meth:`posed` applied to this scene's arrays."""
    built: Scene | None = field(default=None, compare=False, repr=False)
    """The scene as built, before :meth:`posed` moved its objects (None: this one)."""
    parts: tuple[str, ...] = ()
    """Names of the scene's surfaces as built (the Cornell box's ``floor``, ``left wall``,
    ...; the atrium's ``north columns``, ...): finer than :attr:`objects` and never
    moved; what ``lpv-explorer compare --region-mask`` measures
    (explorer/scene/parts.py)."""
    triangle_parts: np.ndarray | None = field(default=None, compare=False, repr=False)
    """(T,) index into :attr:`parts` of each triangle, −1 for a triangle in no part; None
    when the scene names no parts."""
    uv: np.ndarray | None = field(default=None, compare=False, repr=False)
    """(3T, 2) float32 texture coordinates per corner (v up: (0, 0) is the image's
    bottom-left corner, trimesh's convention); None: no triangle is textured."""
    textures: tuple[np.ndarray, ...] = field(default=(), compare=False, repr=False)
    """Base-colour textures: (H, W, 3) float32 linear reflectance each, row 0 at the
    image's top (decoded from sRGB when loaded). A textured triangle's albedo is its
    corners' :attr:`albedo` (the material's factor) times the texture sampled per pixel
    at the interpolated :attr:`uv` (explorer/scene/gpu.py, shaders/surface.glsl)."""
    triangle_texture: np.ndarray | None = field(default=None, compare=False, repr=False)
    """(T,) index into :attr:`textures` of each triangle, −1 for an untextured one; None:
    none is textured."""
    one_sided: np.ndarray | None = field(default=None, compare=False, repr=False)
    """(T,) bool: True for a triangle seen only from its front (the side its winding's
    normal points to, counter-clockwise seen from the front); a one-sided triangle seen
    from behind is not there for that view: the RSM, the G-buffer and hence the geometry
    volume skip it. None: every triangle is two-sided (the default, docs/MODEL.md
    "Scene conventions")."""
    notice: str = field(default="", compare=False)
    """What the loader chose for the user and a command prints (e.g. where it put a light
    for a mesh file without one); empty when nothing."""
    warnings: tuple[str, ...] = field(default=(), compare=False)
    """What of the files a mesh names could not be used (a missing or damaged texture,
    skipped), one line each naming the file; a command prints them, the window shows
    them."""
    files: tuple[str, ...] = field(default=(), compare=False)
    """The files the scene was read from (a scene file and its meshes, or a mesh file);
    () for a built-in scene. The window watches them to load an edited scene again."""

    def __post_init__(self) -> None:
        count = len(self.positions)
        if count == 0 or count % 3:
            raise SceneError(f"scene {self.name!r} needs whole triangles, got {count} corners")
        for name in ("normals", "albedo"):
            if np.shape(getattr(self, name)) != (count, 3):
                raise SceneError(f"scene {self.name!r}: {name} must have shape ({count}, 3)")
        rig = self.rig if isinstance(self.rig, tuple) else (self.rig,)
        object.__setattr__(self, "rig", rig)
        names = [light.name for light in rig]
        if not rig or len(set(names)) != len(names):
            raise SceneError(f"scene {self.name!r} needs at least one light and unique light "
                             f"names, got {names}")
        _check_objects(self.name, self.objects, count)
        _check_surfaces(self, count)
        _check_parts(self.name, self.parts, self.triangle_parts, count // 3)
        if self.lights_on is not None:
            self._check_light_names(self.lights_on, "lights_on")
        for name, path in self.object_paths:
            if name not in self.object_names or path.width != 9:
                raise SceneError(f"scene {self.name!r}: the path of {name!r} must move one of "
                                 f"its objects {self.object_names} with 9 numbers per key")
        for path, what in ((self.light_path, "light"), (self.camera_path, "camera")):
            if path is not None and path.width != 6:
                raise SceneError(f"scene {self.name!r}: the {what} path needs 6 numbers per "
                                 f"key (position/eye and target)")

    @property
    def triangle_count(self) -> int:
        return len(self.positions) // 3

    @property
    def light_names(self) -> tuple[str, ...]:
        """The names of every light of the rig, in order."""
        return tuple(light.name for light in self.rig)

    @property
    def object_names(self) -> tuple[str, ...]:
        return tuple(obj.name for obj in self.objects)

    @property
    def lights(self) -> tuple[Light, ...]:
        """The lights that shine, primary first (:attr:`lights_on`)."""
        if self.lights_on is None:
            return self.rig
        by_name = {light.name: light for light in self.rig}
        return tuple(by_name[name] for name in self.lights_on)

    @property
    def light(self) -> Light:
        """The primary light: the first that shines."""
        return self.lights[0]

    def vertex_bytes(self, first: int = 0, stop: int | None = None) -> bytes:
        """Interleaved ``position, normal, albedo, uv`` float32 rows for a vertex buffer
        (format ``"3f 3f 3f 2f"``), of corners ``first`` .. ``stop`` (default: all)."""
        part = slice(first, stop)
        uv = self.uv[part] if self.uv is not None else \
            np.zeros((len(self.positions[part]), 2), np.float32)
        rows = np.hstack([self.positions[part], self.normals[part], self.albedo[part], uv])
        return np.ascontiguousarray(rows, np.float32).tobytes()

    def draw_runs(self) -> tuple[tuple[int, int, int, bool], ...]:
        """``(first corner, corner count, texture index or −1, one-sided)`` of each run of
        consecutive triangles sharing a texture and a sidedness: one draw call each
        (explorer/scene/gpu.py)."""
        triangles = self.triangle_count
        texture = (self.triangle_texture if self.triangle_texture is not None
                   else np.full(triangles, -1))
        sided = self.one_sided if self.one_sided is not None else np.zeros(triangles, bool)
        key = np.stack([np.asarray(texture, np.int64), np.asarray(sided, np.int64)], axis=1)
        starts = np.flatnonzero(np.any(np.diff(key, axis=0, prepend=-2), axis=1))
        stops = np.append(starts[1:], triangles)
        return tuple((3 * int(a), 3 * int(b - a), int(texture[a]), bool(sided[a]))
                     for a, b in zip(starts, stops))

    def corner_albedo(self) -> np.ndarray:
        """(3T, 3) albedo per corner with each texture sampled at the corners' uv (nearest
        texel): the per-vertex approximation of the textured albedo for consumers that
        cannot sample per pixel. Untextured corners: :attr:`albedo`."""
        albedo = np.array(self.albedo, np.float32)
        if self.triangle_texture is None or self.uv is None:
            return albedo
        corner_texture = np.repeat(self.triangle_texture, 3)
        for index, image in enumerate(self.textures):
            mine = corner_texture == index
            height, width = image.shape[:2]
            uv = np.asarray(self.uv[mine], np.float64)
            u, v = np.where((uv >= 0.0) & (uv <= 1.0), uv, uv % 1.0).T   # repeat outside
            column = np.clip((u * width).astype(int), 0, width - 1)
            row = np.clip(((1.0 - v) * height).astype(int), 0, height - 1)
            albedo[mine] *= image[row, column]
        return albedo

    # -- lights --------------------------------------------------------------------------
    def _check_light_names(self, names: Iterable[str], field: str) -> tuple[str, ...]:
        names = tuple(names)
        unknown = [name for name in names if name not in self.light_names]
        if unknown or not names or len(set(names)) != len(names) or len(names) > MAX_LIGHTS:
            raise SceneError(f"{field} must name 1 to {MAX_LIGHTS} different lights of scene "
                             f"{self.name!r} ({', '.join(self.light_names)}), got "
                             f"{list(names)}")
        return names

    def with_lights(self, names: Iterable[str] | None) -> Scene:
        """The scene with the lights ``names`` shining (the first is the primary); None
        keeps the scene's own choice. A :class:`SceneError` names the rig's lights when a
        name is not one of them."""
        if names is None:
            return self
        return replace(self, lights_on=self._check_light_names(names, "lights"))

    def with_primary(self, light: Light) -> Scene:
        """The scene with its primary light replaced by ``light`` (in the rig, by name)."""
        primary = self.light.name
        rig = tuple(light if entry.name == primary else entry for entry in self.rig)
        return replace(self, rig=rig)

    # -- objects -------------------------------------------------------------------------
    def object_named(self, name: str) -> SceneObject:
        for obj in self.objects:
            if obj.name == name:
                return obj
        raise SceneError(f"scene {self.name!r} has no object {name!r}; its objects are "
                         f"{', '.join(self.object_names) or 'none'}")

    def posed(self, transforms) -> Scene:
        """The scene with its objects moved: ``transforms`` is ``((name, nine numbers),
        ...)`` or a table (``Settings.object_transforms``; 3, 6 or 9 numbers each),
        applied to the corners as built (:attr:`built`: a scene already posed is posed
        again from those). A :class:`SceneError` names the scene's objects when a name is
        not one of them."""
        pairs = check_transforms(transforms or ())
        if pairs is None:
            raise SceneError(f"object transforms must map object names to 3, 6 or 9 numbers "
                             f"(translation, rotation in degrees, scale), got {transforms!r}")
        if pairs == self.pose:
            return self
        for name, _ in pairs:
            self.object_named(name)
        built = self.built if self.built is not None else self
        if not pairs:
            return replace(self, positions=built.positions, normals=built.normals, pose=(),
                           built=None)
        positions = built.positions.copy()
        normals = built.normals.copy()
        for name, values in pairs:
            transform = ObjectTransform.from_values(values)
            if transform.is_identity:
                continue
            obj = self.object_named(name)
            part = slice(obj.first, obj.stop)
            moved, turned = transform_corners(built.positions[part], built.normals[part],
                                              transform, obj.pivot)
            positions[part], normals[part] = moved, turned
        return replace(self, positions=positions, normals=normals, pose=pairs, built=built)

    # -- Settings ------------------------------------------------------------------------
    def with_overrides(self, camera=None, light=None, light_flux: float | None = None,
                       spot_cone: bool = True,
                       spot_cone_degrees: tuple[float, float] | None = None,
                       lights: Iterable[str] | None = None, transforms=None,
                       camera_fov: float | None = None,
                       light_kind: str | None = None) -> Scene:
        """The scene with ``Settings.object_transforms`` (``transforms``), ``lights`` (the
        names that shine), ``camera`` / ``camera_fov`` and the primary light's
        ``light_kind`` / ``light`` / ``light_flux`` / ``spot_cone_degrees`` applied
        (``None`` keeps the scene's own); ``spot_cone`` False turns every spot light's cone
        off (the 90° square frustum). Other lights ignore the spot arguments."""
        scene = self.posed(transforms) if transforms is not None else self
        scene = scene.with_lights(lights)
        if camera is not None:
            eye, target = camera
            scene = replace(scene, camera=replace(scene.camera, eye=tuple(map(float, eye)),
                                                  target=tuple(map(float, target))))
        if camera_fov is not None:
            scene = replace(scene, camera=replace(scene.camera, fov_y_degrees=float(camera_fov)))
        if light_kind is not None and light_kind != scene.light.kind:
            position, target = light if light is not None else \
                (scene.light.position, scene.light.target)
            scene = scene.with_primary(light_of_kind(light_kind, scene.light, position, target,
                                                     self.bounds_min, self.bounds_max))
        elif light is not None:
            position, target = light
            scene = scene.with_primary(scene.light.moved(position, target))
        if light_flux is not None:
            scene = scene.with_primary(scene.light.with_flux(light_flux))
        if not spot_cone:
            scene = replace(scene, rig=tuple(entry.with_cone(None) if entry.kind == "spot"
                                             else entry for entry in scene.rig))
        elif spot_cone_degrees is not None and scene.light.kind == "spot":
            scene = scene.with_primary(scene.light.with_cone(spot_cone_degrees))
        return scene

    def for_settings(self, settings) -> Scene:
        """The scene with every override of ``settings`` (an ``explorer.lpv.settings.
        Settings``) applied: object transforms, the lights that shine, camera, the primary
        light's placement and flux, and the spot cones."""
        return self.with_overrides(settings.camera, settings.light, settings.light_flux,
                                   settings.spot_cone, settings.spot_cone_degrees,
                                   settings.lights, settings.object_transforms,
                                   getattr(settings, "camera_fov", None),
                                   getattr(settings, "light_kind", None))


def light_of_kind(kind: str, like: Light, position, target, bounds_min, bounds_max) -> Light:
    """A ``kind`` light named and coloured as ``like``, at ``position`` aimed at ``target``
    (a point light ignores it), with the default flux a scene file's ``[[lights]]`` table
    gives it too (:func:`explorer.scene.lights.default_flux`: 2 W/m² at the target; a
    point light at the box's centre; a directional light on any plane facing it)."""
    from explorer.scene.lights import default_flux, new_light

    flux = default_flux(kind, position, target, bounds_min, bounds_max)
    return new_light(kind, position, target, flux, name=like.name, colour=like.colour)


def _check_objects(scene: str, objects: tuple[SceneObject, ...], count: int) -> None:
    names = [obj.name for obj in objects]
    if len(set(names)) != len(names):
        raise SceneError(f"scene {scene!r}: object names must be unique, got {names}")
    for obj in objects:
        if obj.first % 3 or obj.count % 3 or obj.count <= 0 or obj.first < 0 or \
                obj.stop > count:
            raise SceneError(f"scene {scene!r}: object {obj.name!r} must hold whole "
                             f"triangles within the scene's {count} corners")


def _check_surfaces(scene: Scene, count: int) -> None:
    """The texture coordinates, textures and sidedness fit the triangles."""
    triangles = count // 3
    name = scene.name
    if scene.uv is not None and np.shape(scene.uv) != (count, 2):
        raise SceneError(f"scene {name!r}: uv must have shape ({count}, 2)")
    for image in scene.textures:
        if np.ndim(image) != 3 or np.shape(image)[2] != 3 or min(np.shape(image)[:2]) < 1:
            raise SceneError(f"scene {name!r}: a texture must be an (H, W, 3) image, got "
                             f"shape {np.shape(image)}")
    index = scene.triangle_texture
    if index is not None and (np.shape(index) != (triangles,) or scene.uv is None or np.any(
            (index < -1) | (index >= len(scene.textures)))):
        raise SceneError(f"scene {name!r}: triangle_texture must hold one index in [-1, "
                         f"{len(scene.textures) - 1}] per triangle ({triangles}), with uv")
    if scene.one_sided is not None and np.shape(scene.one_sided) != (triangles,):
        raise SceneError(f"scene {name!r}: one_sided must hold one flag per triangle "
                         f"({triangles})")


def _check_parts(scene: str, parts: tuple[str, ...], triangle_parts, triangles: int) -> None:
    if len(set(parts)) != len(parts):
        raise SceneError(f"scene {scene!r}: part names must be unique, got {list(parts)}")
    if (triangle_parts is None) != (not parts):
        raise SceneError(f"scene {scene!r}: parts and triangle_parts go together")
    if triangle_parts is not None and (
            np.shape(triangle_parts) != (triangles,)
            or np.any((triangle_parts < -1) | (triangle_parts >= len(parts)))):
        raise SceneError(f"scene {scene!r}: triangle_parts must hold one index in "
                         f"[-1, {len(parts) - 1}] per triangle ({triangles})")


class MeshBuilder:
    """Collects quads and boxes into a triangle soup (for the built-in scenes)."""

    def __init__(self) -> None:
        self._positions: list[np.ndarray] = []
        self._normals: list[np.ndarray] = []
        self._albedo: list[np.ndarray] = []
        self._corners = 0
        self.objects: list[SceneObject] = []
        self.parts: list[str] = []
        self._part_of_chunk: list[int] = []    # per added chunk: index into parts, or -1
        self._part = -1

    @contextmanager
    def part(self, name: str) -> Iterator[None]:
        """Everything added inside the ``with`` block belongs to the part ``name`` (a
        named surface, :attr:`Scene.parts`); a block may name a part again to add to it."""
        if self._part != -1:
            raise ValueError(f"part {name!r} inside part {self.parts[self._part]!r}")
        if name not in self.parts:
            self.parts.append(name)
        self._part = self.parts.index(name)
        try:
            yield
        finally:
            self._part = -1

    def part_fields(self) -> dict:
        """``parts`` and ``triangle_parts`` for :class:`Scene` (nothing without parts)."""
        if not self.parts:
            return {}
        counts = [len(chunk) // 3 for chunk in self._positions]
        return {"parts": tuple(self.parts),
                "triangle_parts": np.repeat(np.asarray(self._part_of_chunk, np.int32),
                                            counts)}

    @contextmanager
    def object(self, name: str) -> Iterator[None]:
        """Everything added inside the ``with`` block becomes the object ``name``, pivoting
        about the centre of its bounding box."""
        first, parts = self._corners, len(self._positions)
        yield
        if self._corners == first:
            raise ValueError(f"object {name!r} holds no triangles")
        corners = np.vstack(self._positions[parts:])
        pivot = 0.5 * (corners.min(axis=0) + corners.max(axis=0))
        self.objects.append(SceneObject(name, first, self._corners - first,
                                        tuple(float(v) for v in pivot)))

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
        self._part_of_chunk.append(self._part)
        self._corners += len(positions)

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return tuple(np.vstack(parts).astype(np.float32)
                     for parts in (self._positions, self._normals, self._albedo))
