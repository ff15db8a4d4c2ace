"""Mesh files to scenes: the triangles, colours, textures and sidedness trimesh reads,
with a default camera and lights (explorer/scene/loader.py ``load_scene`` is the entry).

Meshes (OBJ, GLB/glTF, PLY, STL, ...) become a triangle soup with per-corner normals,
linear albedo and texture coordinates. Colours come from, in order: vertex colours, face
colours, the material's base-colour texture (glTF ``baseColorTexture`` times its linear
``baseColorFactor``, OBJ ``map_Kd``: sampled per pixel on the GPU, with mipmaps), the
material's base colour; otherwise a neutral grey. Colours in files are sRGB-encoded (but
glTF's factor), so they are decoded to linear reflectance. Normals are the file's vertex
normals when it has them, else flat face normals. A glTF material says whether it is
``doubleSided`` (glTF's default: one-sided); other files are two-sided (docs/MODEL.md
"Scene conventions"). Every failure is a :class:`SceneError` naming the file and the
problem, never a trimesh traceback.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from explorer.safe_files import UserFileError
from explorer.scene.camera import Camera
from explorer.scene.lights import (
    DirectionalLight,
    Light,
    PointLight,
    SpotLight,
    flux_for_irradiance,
)
from explorer.scene.mesh_limits import check_mesh_file
from explorer.scene.model import Scene, SceneError
from explorer.scene.objects import SceneObject

FALLBACK_ALBEDO = 0.6
"""Linear grey for meshes that carry no colour."""
MAX_TEXTURE_EDGE = 4096
"""Largest texture edge in texels kept (larger images are reduced when loaded)."""
MAX_MESH_COORDINATE = 1e18
"""Largest coordinate magnitude a mesh may have, in the file and in the world: squared
lengths of 1.8e19 overflow float32, so past this every area, distance and normal the
passes compute is infinite or NaN (smaller but still extreme scales only warn,
explorer/lpv/guards.py ``scale_warning``)."""
MIN_TRIANGLE_AREA_FRACTION = 1e-12
"""Triangles smaller than this fraction of the squared scene size have no usable normal."""

@dataclass(frozen=True)
class MeshFile:
    """The triangle meshes of one mesh file and what could not be read of the files it
    names (each warning one line naming the file: a missing or damaged texture)."""

    parts: list[tuple[str, object, np.ndarray]]
    """``(name, trimesh.Trimesh, 4×4 world transform)`` per scene-graph node."""
    warnings: tuple[str, ...] = ()


def read_mesh_parts(path: Path) -> MeshFile:
    """The file's triangle meshes with their names (scene-graph node) and world
    transforms. The file and every file it names are read through the safe reader
    (explorer/scene/mesh_assets.py), a glTF's layout checked before trimesh allocates."""
    import io

    import trimesh

    from explorer.safe_files import read_bytes
    from explorer.scene.mesh_assets import (
        AssetResolver,
        check_gltf_bytes,
        check_stl_bytes,
        check_textures,
    )

    resolver = AssetResolver(path)
    suffix = "".join(path.suffixes[-2:]).lower() if path.name.lower().endswith(
        (".tar.gz", ".tar.bz2")) else path.suffix.lower()
    try:
        check_mesh_file(path)         # a regular file within the size caps, unpacked too
        data = read_bytes(path, "mesh")
        if suffix in (".glb", ".gltf"):
            check_gltf_bytes(data, suffix, resolver, path)
        elif suffix == ".stl":
            check_stl_bytes(data, path)
    except UserFileError as exc:
        raise SceneError(str(exc)) from None
    # trimesh logs (and sometimes prints tracebacks for) recoverable problems; the user
    # gets our message instead.
    logger = logging.getLogger("trimesh")
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        # no force="mesh": flattening a scene copies visuals through scipy, which is
        # not a dependency; the scene graph is walked below instead. The bytes read
        # above and the resolver: trimesh opens no file itself.
        loaded = trimesh.load(io.BytesIO(data), file_type=suffix.lstrip("."),
                              resolver=resolver, process=False)
        if isinstance(loaded, trimesh.Scene):
            parts = []
            for node in loaded.graph.nodes_geometry:
                transform, geometry_name = loaded.graph[node]
                geometry = loaded.geometry.get(geometry_name)
                if isinstance(geometry, trimesh.Trimesh):
                    parts.append((str(node), geometry, np.asarray(transform, np.float64)))
        elif isinstance(loaded, trimesh.Trimesh):
            parts = [(path.stem, loaded, np.eye(4))]
        else:
            parts = []
            if hasattr(loaded, "vertices"):
                count = len(np.asarray(loaded.vertices))
                raise SceneError(f"{path}: the mesh is empty ({count} points and no "
                                 f"triangles)")
    except SceneError:
        raise
    except UserFileError as exc:      # a buffer the mesh needs
        raise SceneError(str(exc)) from None
    except Exception as exc:  # trimesh raises many types for broken files
        reason = str(exc) or type(exc).__name__
        named = f"; {resolver.warnings[-1]}" if resolver.warnings else ""   # say which
        raise SceneError(f"{path}: not a mesh trimesh can read ({type(exc).__name__}: "
                         f"{reason}){named}") from None
    finally:
        logger.setLevel(level)
    if not parts:
        raise SceneError(f"{path}: the file holds no triangle mesh")
    for name, mesh, _ in parts:
        check_coordinates(np.asarray(mesh.vertices, np.float64), f"{path}: mesh {name!r}")
    warnings = [*resolver.warnings, *check_textures(parts, path)]
    return MeshFile(parts, tuple(dict.fromkeys(warnings)))


@dataclass(frozen=True)
class MeshPart:
    """One mesh of a scene with its world transform and what a scene file overrides."""

    name: str
    mesh: object
    """A ``trimesh.Trimesh``."""
    transform: np.ndarray
    """4×4 model-to-world matrix."""
    albedo: tuple[float, float, float] | None = None
    """Linear albedo replacing the mesh's colours and texture; None: the file's."""
    two_sided: bool | None = None
    """True/False: two-/one-sided; None: the file's (glTF ``doubleSided``), else two-sided
    (docs/MODEL.md "Scene conventions")."""


@dataclass(frozen=True)
class _Surface:
    """One part's triangles in world space, each array (T, 3, ...) per corner."""

    corners: np.ndarray
    normals: np.ndarray
    """NaN where the file has none (filled with face normals later)."""
    albedo: np.ndarray
    """The colour, or the texture's factor for a textured part (linear)."""
    uv: np.ndarray | None
    texture: object
    """The base-colour image (PIL) or None."""
    two_sided: bool


def scene_from_mesh(mesh, name: str, source: str = "<mesh>") -> Scene:
    """A :class:`Scene` from a ``trimesh.Trimesh`` (or a list of ``(mesh, 4×4 transform)``
    pairs, ``(name, mesh, transform)`` triples or :class:`MeshPart`) with a default camera
    and light rig (:func:`default_rig`: a light inside a closed mesh, else a spot above it,
    and :func:`spare_lights`). Each part with triangles is an object that can be moved,
    named after its scene-graph node."""
    scene = scene_from_parts(_mesh_parts(mesh), name, source)
    rig, notice = default_rig(scene)
    return replace(scene, rig=rig, lights_on=(rig[0].name,), notice=notice)


def _mesh_parts(mesh) -> list[MeshPart]:
    parts = mesh if isinstance(mesh, list) else [(mesh, np.eye(4))]
    named = []
    for k, part in enumerate(parts):
        if isinstance(part, MeshPart):
            named.append(part)
        elif len(part) == 3:
            named.append(MeshPart(str(part[0]), part[1], np.asarray(part[2], np.float64)))
        else:
            named.append(MeshPart(f"part {k + 1}", part[0], np.asarray(part[1], np.float64)))
    return named


def scene_from_parts(parts: list[MeshPart], name: str, source: str, camera=None,
                     rig=None, bounds=None) -> Scene:
    """A :class:`Scene` of ``parts``: their triangles, normals, albedo, texture coordinates,
    base-colour textures and sidedness; ``camera`` / ``rig`` / ``bounds`` (lo, hi) as
    given, else the default camera, a provisional spot light and the geometry's box."""
    surfaces, names = [], []
    for part in parts:
        surface = _triangle_soup(part, source)
        if surface is not None:
            surfaces.append(surface)
            names.append(part.name)
    if not surfaces:
        raise SceneError(f"{source}: the mesh is empty (no triangles)")
    corners = np.concatenate([s.corners for s in surfaces])
    normals = np.concatenate([s.normals for s in surfaces])
    albedo = np.concatenate([s.albedo for s in surfaces])
    owner = np.concatenate([np.full(len(s.corners), k) for k, s in enumerate(surfaces)])
    usable = _usable(corners)
    if not np.any(usable):
        raise SceneError(f"{source}: no triangle has a non-zero area, so no normals can be "
                         f"computed ({len(corners)} degenerate triangles)")
    textures, texture_of_surface = _textures(surfaces)
    textured = any(index >= 0 for index in texture_of_surface)
    uv = np.concatenate([s.uv if s.uv is not None else np.zeros((len(s.corners), 3, 2))
                         for s in surfaces])[usable] if textured else None
    triangle_texture = np.asarray(texture_of_surface, np.int64)[owner[usable]] \
        if textured else None
    one_sided = np.array([not s.two_sided for s in surfaces])[owner[usable]]
    corners, normals, albedo = corners[usable], normals[usable], albedo[usable]
    objects = _objects(names, owner[usable], corners)
    face_normals = _face_normals(corners)
    missing = ~np.all(np.isfinite(normals), axis=(1, 2))
    normals[missing] = np.repeat(face_normals[missing, None, :], 3, axis=1)
    # a file normal opposite to the winding would turn the surface inside out for the
    # light; trust the winding there (it also says which side a one-sided surface has).
    flipped = np.einsum("tcj,tj->tc", normals, face_normals) < 0.0
    normals[flipped] *= -1.0

    flat = corners.reshape(-1, 3)
    lo, hi = flat.min(axis=0), flat.max(axis=0)
    if bounds is not None:
        lo, hi = np.minimum(lo, bounds[0]), np.maximum(hi, bounds[1])
    default_camera, light = default_camera_and_light(lo, hi)
    return Scene(name, flat.astype(np.float32), normals.reshape(-1, 3).astype(np.float32),
                 albedo.reshape(-1, 3).astype(np.float32), camera or default_camera,
                 tuple(rig) if rig else (light,), tuple(map(float, lo)),
                 tuple(map(float, hi)), objects=objects,
                 uv=None if uv is None else uv.reshape(-1, 2).astype(np.float32),
                 textures=textures, triangle_texture=triangle_texture,
                 one_sided=one_sided if one_sided.any() else None)


def default_rig(scene: Scene) -> tuple[tuple[Light, ...], str]:
    """The lights for a scene that names none, and a sentence saying where the first is:
    a point light inside the mesh's box, inside the room of a closed mesh, at the most
    enclosed point farthest from every surface (explorer/scene/placement.py casts the
    rays); for a mesh with no such point (a solid object) the spot of
    :func:`default_camera_and_light` above it. The spare lights follow."""
    from explorer.scene.placement import light_inside

    lo, hi = np.asarray(scene.bounds_min), np.asarray(scene.bounds_max)
    inside = light_inside(scene)
    spares = spare_lights(lo, hi)
    if inside is not None:
        bulb = PointLight(tuple(map(float, inside.position)),
                          flux_for_irradiance(inside.distance), name="light")
        where = ", ".join(f"{v:.3g}" for v in inside.position)
        if inside.closed:
            why = ("the mesh is closed, so a point light 'light' is at ({where}) inside it "
                   "(every ray from there meets a wall's front)")
        else:
            why = (f"the mesh is open, so a point light 'light' is at ({{where}}) in its "
                   f"box, its most enclosed point ({inside.enclosed:.0%} of the rays from "
                   f"there meet a surface's front)")
        return (bulb, *spares), f"{scene.name}: no light given; " + why.format(where=where)
    _, spot = default_camera_and_light(lo, hi)
    where = ", ".join(f"{v:.3g}" for v in spot.position)
    aim = ", ".join(f"{v:.3g}" for v in spot.target)
    return (spot, *spares), (f"{scene.name}: no light given; a spot light 'spot' is at "
                             f"({where}) aimed at ({aim}) (no point of the mesh's box is "
                             f"inside a room: the mesh is a solid or a sheet)")


def _textures(surfaces: list[_Surface]) -> tuple[tuple[np.ndarray, ...], list[int]]:
    """The distinct base-colour images of the surfaces as linear float32 arrays, and the
    index of each surface's (−1: untextured)."""
    images, index_of, owner = [], {}, []
    for surface in surfaces:
        image = surface.texture
        if image is None:
            owner.append(-1)
            continue
        if id(image) not in index_of:
            index_of[id(image)] = len(images)
            images.append(texture_linear(image))
        owner.append(index_of[id(image)])
    return tuple(images), owner


def texture_linear(image) -> np.ndarray:
    """A PIL image as (H, W, 3) float32 linear reflectance (sRGB decoded; alpha dropped:
    the explorer has no transparency). An image wider or taller than
    :data:`MAX_TEXTURE_EDGE` is first reduced by a whole factor (a box filter) to fit: the
    texture and its mip chain are float32 on the GPU and in memory (a 4096² texture
    already takes 256 MB with its mipmaps)."""
    factor = -(-max(image.size) // MAX_TEXTURE_EDGE)
    if factor > 1:
        image = image.convert("RGB").reduce(factor)
    encoded = np.asarray(image.convert("RGB"), np.float64) / 255.0
    return srgb_to_linear(encoded).astype(np.float32)


def _objects(names: list[str], owner: np.ndarray, corners: np.ndarray
             ) -> tuple[SceneObject, ...]:
    """One object per part (``owner``: the part of each kept triangle, in order), named
    after the part (a number added to a name that repeats)."""
    objects, seen = [], {}
    starts = np.flatnonzero(np.diff(owner, prepend=-1))
    stops = np.append(starts[1:], len(owner))
    for start, stop in zip(starts, stops):
        base = names[int(owner[start])]
        seen[base] = seen.get(base, 0) + 1
        label = base if seen[base] == 1 else f"{base} {seen[base]}"
        part = corners[start:stop].reshape(-1, 3)
        pivot = 0.5 * (part.min(axis=0) + part.max(axis=0))
        objects.append(SceneObject(label, 3 * int(start), 3 * int(stop - start),
                                   tuple(float(v) for v in pivot)))
    return tuple(objects)


def _triangle_soup(part: MeshPart, source: str) -> _Surface | None:
    """The part's triangles in world space; None for a mesh with no faces."""
    mesh, transform = part.mesh, part.transform
    faces = np.asarray(mesh.faces, dtype=np.int64).reshape(-1, 3)
    vertices = np.asarray(mesh.vertices, dtype=np.float64).reshape(-1, 3)
    if len(faces) == 0:
        return None
    check_coordinates(vertices, f"{source}: mesh {part.name!r}")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise SceneError(f"{source}: faces index vertices that do not exist")
    with np.errstate(over="ignore", invalid="ignore"):
        world = vertices @ transform[:3, :3].T + transform[:3, 3]
    check_coordinates(world, f"{source}: mesh {part.name!r} placed in the world")
    if np.linalg.det(transform[:3, :3]) < 0.0:
        # a mirroring transform reverses the winding: swap two corners to keep the front
        faces = faces[:, [0, 2, 1]]
    normals = _file_vertex_normals(mesh, len(vertices))
    if normals is None:
        corner_normals = np.full((len(faces), 3, 3), np.nan)
    else:
        # normals transform with the inverse transpose
        normal_matrix = np.linalg.inv(transform[:3, :3]).T
        normals = normals @ normal_matrix.T
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        corner_normals = normals[faces]
    albedo, uv, texture, double_sided = _material(mesh, faces, len(vertices))
    if part.albedo is not None:
        albedo, uv, texture = np.broadcast_to(part.albedo, (len(faces), 3, 3)), None, None
    two_sided = part.two_sided if part.two_sided is not None else \
        (double_sided if double_sided is not None else True)
    return _Surface(world[faces], corner_normals, np.array(albedo, np.float64), uv, texture,
                    bool(two_sided))


def check_coordinates(points: np.ndarray, where: str) -> None:
    """A :class:`SceneError` naming ``where`` when a coordinate is NaN, infinite or beyond
    :data:`MAX_MESH_COORDINATE`."""
    if points.size == 0:
        return
    if not np.all(np.isfinite(points)):
        bad = int(np.count_nonzero(~np.all(np.isfinite(points), axis=-1)))
        raise SceneError(f"{where}: {bad} vertex position(s) are NaN or infinite")
    largest = float(np.max(np.abs(points)))
    if largest > MAX_MESH_COORDINATE:
        raise SceneError(f"{where}: a vertex coordinate is {largest:.3g}, beyond the "
                         f"{MAX_MESH_COORDINATE:.0e} a mesh may have (float32 squares "
                         f"overflow); rescale the mesh")


def _face_normals(corners: np.ndarray) -> np.ndarray:
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    return cross / np.linalg.norm(cross, axis=1, keepdims=True)


def _usable(corners: np.ndarray) -> np.ndarray:
    """Triangles with an area large enough to have a normal."""
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    size = float(np.max(np.ptp(corners.reshape(-1, 3), axis=0)))
    return np.linalg.norm(cross, axis=1) > MIN_TRIANGLE_AREA_FRACTION * max(size, 1e-30) ** 2


def default_camera_and_light(lo: np.ndarray, hi: np.ndarray) -> tuple[Camera, SpotLight]:
    """A camera in front of and above the box, and a spot light above-right of it whose
    cone holds the box's bounding sphere inside its inner angle (the sphere subtends
    32.3° from the light, the cone is 35° inner, 45° outer)."""
    centre = 0.5 * (lo + hi)
    radius = max(0.5 * float(np.linalg.norm(hi - lo)), 1e-6)
    eye = centre + radius * np.array([0.0, 0.8, 2.6])
    light_position = centre + radius * np.array([0.5, 1.5, 1.0])
    distance = float(np.linalg.norm(light_position - centre))
    camera = Camera(tuple(map(float, eye)), tuple(map(float, centre)), 45.0)
    light = SpotLight(tuple(map(float, light_position)), tuple(map(float, centre)),
                      flux_for_irradiance(distance), name="spot", cone_degrees=(35.0, 45.0))
    return camera, light


def spare_lights(lo: np.ndarray, hi: np.ndarray) -> tuple[Light, ...]:
    """The lights a loaded mesh offers besides its spot (off until ``Settings.lights``
    names them): a warm point light above the box's centre and daylight from the front
    left, both giving about the spot's irradiance on the box's centre."""
    centre = 0.5 * (np.asarray(lo, np.float64) + np.asarray(hi, np.float64))
    radius = max(0.5 * float(np.linalg.norm(np.subtract(hi, lo))), 1e-6)
    bulb_position = centre + radius * np.array([0.0, 0.9, 0.0])
    side = 2.0 * DirectionalLight.half_width(lo, hi)
    sun_from = centre + radius * np.array([-1.0, 2.0, 1.5])
    return (PointLight(tuple(map(float, bulb_position)), flux_for_irradiance(0.9 * radius),
                       name="bulb", colour=(1.0, 0.72, 0.42)),
            DirectionalLight(tuple(map(float, sun_from)), tuple(map(float, centre)),
                             2.0 * side * side, name="sun", colour=(1.0, 0.95, 0.86)))


def _file_vertex_normals(mesh, vertex_count: int) -> np.ndarray | None:
    """The vertex normals stored in the file, or None (trimesh keeps them in its cache
    when the loader read them; asking ``mesh.vertex_normals`` otherwise would compute
    smoothed ones, which is wrong at hard edges)."""
    try:
        if "vertex_normals" not in mesh._cache:
            return None
        normals = np.asarray(mesh._cache["vertex_normals"], dtype=np.float64)
    except Exception:
        return None
    if normals.shape != (vertex_count, 3) or not np.all(np.isfinite(normals)):
        return None
    length = np.linalg.norm(normals, axis=1)
    if np.any(length < 1e-8):
        return None
    return normals / length[:, None]


def _material(mesh, faces: np.ndarray, vertex_count: int):
    """``(albedo (T, 3, 3) linear, uv (T, 3, 2) or None, texture image or None,
    double_sided or None)`` of a mesh. A glTF material (trimesh's PBRMaterial) gives its
    linear ``baseColorFactor`` times its sRGB ``baseColorTexture`` and says whether it is
    ``doubleSided`` (glTF's default: one-sided); an OBJ ``map_Kd`` is the colour alone
    (exporters write arbitrary ``Kd`` beside it); a file that says nothing is two-sided."""
    visual = getattr(mesh, "visual", None)
    kind = getattr(visual, "kind", None)
    material = getattr(visual, "material", None)
    double_sided = None
    if type(material).__name__ == "PBRMaterial":
        double_sided = bool(getattr(material, "doubleSided", False))
    fallback = np.full((len(faces), 3, 3), FALLBACK_ALBEDO)
    try:
        if kind == "vertex":
            srgb = np.asarray(visual.vertex_colors)[:, :3][faces]
            return _decoded(srgb), None, None, double_sided
        if kind == "face":
            face_rgb = np.asarray(visual.face_colors)[:, :3]
            return _decoded(np.repeat(face_rgb[:, None, :], 3, axis=1)), None, None, \
                double_sided
        if material is None:
            return fallback, None, None, double_sided
        factor = _material_factor(material)
        image = getattr(material, "baseColorTexture", None)
        if image is None:
            image = getattr(material, "image", None)
            texture_factor = np.ones(3)         # OBJ map_Kd: the texture is the colour
        else:
            texture_factor = np.ones(3) if factor is None else factor
        uv = getattr(visual, "uv", None)
        if image is not None and uv is not None and len(uv) == vertex_count:
            corner_uv = np.asarray(uv, np.float64)[:, :2][faces]
            if np.all(np.isfinite(corner_uv)):
                linear = texture_factor
                return np.broadcast_to(linear, (len(faces), 3, 3)), corner_uv, image, \
                    double_sided
        if factor is not None:
            return np.broadcast_to(factor, (len(faces), 3, 3)), None, None, double_sided
    except SceneError:
        raise
    except Exception:       # trimesh visuals of an unusual file: the neutral grey
        pass
    return fallback, None, None, double_sided


def _material_factor(material) -> np.ndarray | None:
    """The material's own colour as linear RGB: glTF's ``baseColorFactor`` is linear
    already, OBJ's ``Kd`` / trimesh's ``main_color`` is sRGB-encoded; None: none."""
    factor = getattr(material, "baseColorFactor", None)
    if factor is not None:
        return np.asarray(factor, np.float64)[:3] / 255.0
    main = getattr(material, "main_color", None)
    if main is None:
        return None
    return _decoded(np.asarray(main)[:3])


def _decoded(srgb8) -> np.ndarray:
    return srgb_to_linear(np.asarray(srgb8, np.float64) / 255.0)


def srgb_to_linear(encoded: np.ndarray) -> np.ndarray:
    """The sRGB electro-optical transfer function (IEC 61966-2-1)."""
    encoded = np.clip(encoded, 0.0, 1.0)
    return np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)
