"""``load_scene``: a built-in scene by name, or any mesh file trimesh reads.

Meshes (OBJ, GLB/glTF, PLY, STL, ...) become a triangle soup with per-corner normals and
linear albedo. Colours come from, in order: vertex colours, face colours, the material's
texture sampled at the vertices, the material's base colour; otherwise a neutral grey.
Colours in files are sRGB-encoded, so they are decoded to linear reflectance. Normals are
the file's vertex normals when it has them, else flat face normals. Every failure is a
:class:`SceneError` naming the file and the problem, never a trimesh traceback.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from explorer.safe_files import UserFileError
from explorer.scene.builtin import BUILTIN_SCENES
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
MIN_TRIANGLE_AREA_FRACTION = 1e-12
"""Triangles smaller than this fraction of the squared scene size have no usable normal."""


def load_scene(name_or_path: str | Path) -> Scene:
    """A built-in scene (``"cornell"``, ``"single-source"``, ``"room"``, ``"atrium"``) or a
    mesh file."""
    key = str(name_or_path)
    if key in BUILTIN_SCENES:
        return BUILTIN_SCENES[key]()
    path = check_scene_name(key)
    parts = _read_mesh(path)
    try:
        return scene_from_mesh(parts, path.stem, str(path))
    except (ValueError, IndexError, TypeError) as exc:
        # trimesh read the file, but its arrays do not fit together (a vertex with two
        # coordinates, a face index past the vertices): a broken file, not our bug.
        raise SceneError(f"{path}: the mesh's data is inconsistent ({type(exc).__name__}: "
                         f"{exc})") from None


def check_scene_name(name_or_path: str | Path) -> Path | None:
    """Without loading anything: None for a built-in scene name, the path of an existing
    file otherwise; a :class:`SceneError` naming the built-in scenes when it is neither
    (commands check ``--scene`` with this before any work)."""
    key = str(name_or_path)
    if key in BUILTIN_SCENES:
        return None
    path = Path(key).expanduser()
    if not path.exists():
        raise SceneError(f"no built-in scene or mesh file named {key!r}: built-in scenes are "
                         f"{', '.join(BUILTIN_SCENES)}; a path must point to a mesh "
                         f"file (OBJ, GLB/glTF, PLY, STL)")
    if not path.is_file():
        raise SceneError(f"{path} is not a file")
    return path


def _read_mesh(path: Path) -> list[tuple[str, object, np.ndarray]]:
    """The file's triangle meshes with their names (scene-graph node) and world
    transforms."""
    import trimesh

    try:
        check_mesh_file(path)         # a regular file within the size caps, unpacked too
    except UserFileError as exc:
        raise SceneError(str(exc)) from None
    # trimesh logs (and sometimes prints tracebacks for) recoverable problems; the user
    # gets our message instead.
    logger = logging.getLogger("trimesh")
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        # no force="mesh": flattening a scene copies visuals through scipy, which is
        # not a dependency; the scene graph is walked below instead.
        loaded = trimesh.load(str(path), process=False)
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
    except Exception as exc:  # trimesh raises many types for broken files
        reason = str(exc) or type(exc).__name__
        raise SceneError(f"{path}: not a mesh trimesh can read ({type(exc).__name__}: "
                         f"{reason})") from None
    finally:
        logger.setLevel(level)
    if not parts:
        raise SceneError(f"{path}: the file holds no triangle mesh")
    return parts


def scene_from_mesh(mesh, name: str, source: str = "<mesh>") -> Scene:
    """A :class:`Scene` from a ``trimesh.Trimesh`` (or a list of ``(mesh, 4×4 transform)``
    pairs or ``(name, mesh, transform)`` triples) with a default camera and light rig
    (:func:`default_camera_and_light`, :func:`spare_lights`). Each part with triangles is
    an object that can be moved, named after its scene-graph node."""
    parts = mesh if isinstance(mesh, list) else [(mesh, np.eye(4))]
    parts = [part if len(part) == 3 else (f"part {k + 1}", *part)
             for k, part in enumerate(parts)]
    soups, names = [], []
    for part_name, part, transform in parts:
        soup = _triangle_soup(part, transform, source)
        if soup is not None:
            soups.append(soup)
            names.append(part_name)
    if not soups:
        raise SceneError(f"{source}: the mesh is empty (no triangles)")
    corners, normals, albedo = (np.concatenate(arrays) for arrays in zip(*soups))
    owner = np.concatenate([np.full(len(soup[0]), k) for k, soup in enumerate(soups)])
    usable = _usable(corners)
    if not np.any(usable):
        raise SceneError(f"{source}: no triangle has a non-zero area, so no normals can be "
                         f"computed ({len(corners)} degenerate triangles)")
    corners, normals, albedo = corners[usable], normals[usable], albedo[usable]
    objects = _objects(names, owner[usable], corners)
    face_normals = _face_normals(corners)
    missing = ~np.all(np.isfinite(normals), axis=(1, 2))
    normals[missing] = np.repeat(face_normals[missing, None, :], 3, axis=1)
    # a file normal opposite to the winding would turn the surface inside out for the
    # light; trust the winding there.
    flipped = np.einsum("tcj,tj->tc", normals, face_normals) < 0.0
    normals[flipped] *= -1.0

    flat = corners.reshape(-1, 3)
    lo, hi = flat.min(axis=0), flat.max(axis=0)
    camera, light = default_camera_and_light(lo, hi)
    return Scene(name, flat.astype(np.float32), normals.reshape(-1, 3).astype(np.float32),
                 albedo.reshape(-1, 3).astype(np.float32), camera,
                 (light, *spare_lights(lo, hi)), tuple(map(float, lo)), tuple(map(float, hi)),
                 objects=objects, lights_on=(light.name,))


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


def _triangle_soup(mesh, transform: np.ndarray, source: str):
    """(corners, normals, albedo), each (T, 3, 3), in world space; normals are NaN where
    the file has none (filled with face normals later); None for a mesh with no faces."""
    faces = np.asarray(mesh.faces, dtype=np.int64).reshape(-1, 3)
    vertices = np.asarray(mesh.vertices, dtype=np.float64).reshape(-1, 3)
    if len(faces) == 0:
        return None
    if not np.all(np.isfinite(vertices)):
        raise SceneError(f"{source}: vertex positions contain NaN or infinity")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise SceneError(f"{source}: faces index vertices that do not exist")
    world = vertices @ transform[:3, :3].T + transform[:3, 3]
    normals = _file_vertex_normals(mesh, len(vertices))
    if normals is None:
        corner_normals = np.full((len(faces), 3, 3), np.nan)
    else:
        # normals transform with the inverse transpose
        normal_matrix = np.linalg.inv(transform[:3, :3]).T
        normals = normals @ normal_matrix.T
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        corner_normals = normals[faces]
    return world[faces], corner_normals, _corner_albedo(mesh, faces)


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


def _corner_albedo(mesh, faces: np.ndarray) -> np.ndarray:
    """(T, 3, 3) linear albedo per triangle corner."""
    visual = getattr(mesh, "visual", None)
    kind = getattr(visual, "kind", None)
    srgb = None
    try:
        if kind == "vertex":
            srgb = np.asarray(visual.vertex_colors)[:, :3][faces]
        elif kind == "face":
            face_rgb = np.asarray(visual.face_colors)[:, :3]
            srgb = np.repeat(face_rgb[:, None, :], 3, axis=1)
        elif kind == "texture":
            srgb = _texture_colours(visual, faces)
    except Exception:
        srgb = None
    if srgb is None:
        return np.full((len(faces), 3, 3), FALLBACK_ALBEDO)
    return srgb_to_linear(np.asarray(srgb, np.float64) / 255.0)


def _texture_colours(visual, faces: np.ndarray) -> np.ndarray | None:
    material = getattr(visual, "material", None)
    uv = getattr(visual, "uv", None)
    image = getattr(material, "image", None) or getattr(material, "baseColorTexture", None)
    if uv is not None and image is not None:
        from trimesh.visual.color import uv_to_color

        colours = np.asarray(uv_to_color(uv, image))[:, :3]
        return colours[faces]
    main = getattr(material, "main_color", None)
    if main is None:
        return None
    return np.broadcast_to(np.asarray(main)[:3], (len(faces), 3, 3))


def srgb_to_linear(encoded: np.ndarray) -> np.ndarray:
    """The sRGB electro-optical transfer function (IEC 61966-2-1)."""
    encoded = np.clip(encoded, 0.0, 1.0)
    return np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)
