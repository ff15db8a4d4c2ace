"""Scene files: a TOML file that names meshes, lights, the camera and the grid's box.

The format (every key but a mesh's ``path`` is optional; docs/SCENES.md shows it whole)::

    name = "textured room"
    builtin = "cornell"          # instead of [[meshes]]: a built-in scene's geometry

    [camera]
    eye = [0.0, 1.2, 3.5]
    target = [0.0, 0.8, 0.0]
    fov = 50.0                   # vertical, degrees, in [1, 170]

    [grid]                       # the box the light grid encloses (grown to hold
    min = [-2.0, 0.0, -2.0]      # every mesh as placed; the poses move objects, not
    max = [2.0, 2.5, 2.0]        # the box, as the window does; the notice says so)
    cells = [16, 12, 26]         # or (also) an exact grid, all three together:
    origin = [-1.6, 0.0, -2.6]   # cells along x, y, z, the minimum corner and the
    cell_size = 0.2              # cells' edge (world units)

    [[meshes]]
    path = "room.glb"            # relative to this file
    translate = [0.0, 0.0, 0.0]  # the mesh's placement: scale, then rotate (degrees
    rotate = [0.0, 90.0, 0.0]    # about x, then y, then z), then translate
    scale = 1.0                  # or [sx, sy, sz]
    albedo = [0.7, 0.7, 0.7]     # linear; replaces the file's colours and texture
    two_sided = false            # replaces the file's sidedness (glTF doubleSided)

    [[lights]]
    kind = "spot"                # spot, point or directional
    name = "key"
    position = [0.0, 2.3, 0.0]
    target = [0.0, 0.0, 0.0]     # spot and directional (a point light: where
    cone = [30.0, 45.0]          # irradiance is meant); a spot's inner, outer half-angles
    flux = 40.0                  # watts per channel, or:
    irradiance = 2.0             # W/m² at the target facing the light (directional: on
    colour = [1.0, 0.9, 0.8]     # any plane facing it)
    on = true                    # shines when the scene opens (the first is primary)

    [poses]                      # objects (a mesh's scene-graph nodes) moved as the
    "room" = [0.0, 0.1, 0.0]     # window's gizmo moves them: 3, 6 or 9 numbers

A scene without lights gets one (inside a closed mesh, explorer/scene/placement.py) and
says where in :attr:`Scene.notice`. Every mistake is a :class:`SceneError` of one line
naming the file, the table and the key; unknown keys are refused (a typo never passes
silently). The file is data: it is parsed by :mod:`tomllib`, never evaluated.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from explorer.scene.camera import Camera
from explorer.scene.lights import (
    LIGHT_KINDS,
    MAX_CONE_DEGREES,
    Light,
    default_flux,
    flux_for_irradiance,
    new_light,
)
from explorer.scene.model import MAX_LIGHTS, Scene, SceneError
from explorer.scene.objects import MAX_SCALE, MIN_SCALE, ObjectTransform, check_transforms

SCENE_FILE_SUFFIX = ".toml"
TOP_KEYS = ("name", "builtin", "camera", "grid", "meshes", "lights", "poses")
CAMERA_KEYS = ("eye", "target", "fov")
GRID_KEYS = ("min", "max", "cells", "origin", "cell_size")
GRID_BOX_KEYS = ("min", "max")
EXACT_GRID_KEYS = ("cells", "origin", "cell_size")
MAX_GRID_CELLS = 256
"""Cells along one axis at most (``explorer.lpv.settings.MAX_GRID_SIZE``, which this layer
does not import)."""
MESH_KEYS = ("path", "translate", "rotate", "scale", "albedo", "two_sided")
LIGHT_KEYS = ("kind", "name", "position", "target", "cone", "flux", "irradiance", "colour",
              "on")
FOV_RANGE = (1.0, 170.0)
MAX_COORDINATE = 1e6
MAX_FLUX = 1e12


def is_scene_file(name_or_path: str | Path) -> bool:
    return str(name_or_path).lower().endswith(SCENE_FILE_SUFFIX)


def read_scene_file(path: Path) -> Scene:
    """The scene ``path`` describes (module docstring); :class:`SceneError` for any
    mistake, naming the file and the key."""
    import tomllib

    from explorer.safe_files import UserFileError, parse_toml, read_text

    try:
        data = parse_toml(read_text(path, "scene file"), path)
    except UserFileError as exc:
        raise SceneError(str(exc)) from None
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{path}: not valid TOML ({exc})") from None
    return scene_from_table(data, path)


def scene_from_table(data: dict, path: Path) -> Scene:
    """The scene of a parsed scene file ``data``; relative mesh paths are relative to
    ``path``'s folder."""
    where = str(path)
    _known(data, TOP_KEYS, where, "the file")
    name = _text(data, "name", where, "the file", default=path.stem)
    if ("builtin" in data) == ("meshes" in data):
        raise SceneError(f"{where}: give either builtin = NAME or [[meshes]] (one or more), "
                         f"not {'both' if 'builtin' in data else 'neither'}")
    if "builtin" in data:
        base = _builtin(data, where)
    else:
        base = _meshes(data, path)
    base = replace(base, files=(str(path.resolve()), *base.files))
    bounds = _grid(data.get("grid"), where)
    exact = _exact_grid(data.get("grid"), where)
    if exact is not None:
        base = replace(base, exact_grid=exact)
    grown = ""
    if bounds is not None:
        lo = np.minimum(base.bounds_min, bounds[0])
        hi = np.maximum(base.bounds_max, bounds[1])
        if not (np.array_equal(lo, bounds[0]) and np.array_equal(hi, bounds[1])):
            grown = (f"{where}: [grid] grown to min {_shown(lo)}, max {_shown(hi)} to hold "
                     f"every mesh")
        base = replace(base, bounds_min=tuple(map(float, lo)), bounds_max=tuple(map(float, hi)))
    camera = _camera(data.get("camera"), where, base.camera)
    scene = replace(base, name=name, camera=camera)
    if "lights" in data:
        rig, shining = _lights(data["lights"], where, scene)
        scene = replace(scene, rig=rig, lights_on=shining, notice="", light_path=None)
    elif "meshes" in data:
        from explorer.scene.meshes import default_rig

        rig, notice = default_rig(scene)
        scene = replace(scene, rig=rig, lights_on=(rig[0].name,), notice=notice)
    if "poses" in data:
        scene = _posed(scene, data["poses"], where)
    if grown:
        scene = replace(scene, notice="; ".join(filter(None, (scene.notice, grown))))
    return scene


def _shown(values) -> str:
    return "[" + ", ".join(f"{float(v):.4g}" for v in values) + "]"


# --- sections ---------------------------------------------------------------------------

def _builtin(data: dict, where: str) -> Scene:
    from explorer.scene.builtin import BUILTIN_SCENES

    key = _text(data, "builtin", where, "the file")
    if key not in BUILTIN_SCENES:
        raise SceneError(f"{where}: builtin = {key!r} is not a built-in scene; they are "
                         f"{', '.join(BUILTIN_SCENES)}")
    return BUILTIN_SCENES[key]()


def _meshes(data: dict, path: Path) -> Scene:
    from explorer.scene.meshes import MeshPart, read_mesh_parts, scene_from_parts

    where = str(path)
    entries = data["meshes"]
    if not isinstance(entries, list) or not entries or \
            not all(isinstance(entry, dict) for entry in entries):
        raise SceneError(f"{where}: meshes must be one or more [[meshes]] tables")
    parts: list[MeshPart] = []
    files: dict[str, None] = {}             # the mesh files read, in order, once each
    warnings: dict[str, None] = {}
    for k, entry in enumerate(entries, 1):
        table = f"[[meshes]] #{k}"
        _known(entry, MESH_KEYS, where, table)
        if "path" not in entry:
            raise SceneError(f"{where}: {table} needs path = \"mesh file\"")
        mesh_path = mesh_file(path, _text(entry, "path", where, table))
        files[str(mesh_path.resolve())] = None
        transform = mesh_matrix(entry, where, table)
        albedo = _vector(entry, "albedo", where, table, low=0.0, high=1.0) \
            if "albedo" in entry else None
        two_sided = _flag(entry, "two_sided", where, table) if "two_sided" in entry else None
        try:
            mesh_read = read_mesh_parts(mesh_path)
        except SceneError as exc:
            raise SceneError(f"{where}: {table}: {exc}") from None
        warnings.update(dict.fromkeys(mesh_read.warnings))
        for node, mesh, node_transform in mesh_read.parts:
            parts.append(MeshPart(node, mesh, transform @ node_transform,
                                  None if albedo is None else tuple(albedo), two_sided))
    return replace(scene_from_parts(parts, path.stem, where), files=tuple(files),
                   warnings=tuple(warnings))


def mesh_file(scene_path: Path, text: str) -> Path:
    """A mesh entry's path (relative to the scene file's folder) checked to exist."""
    mesh_path = Path(text).expanduser()
    if not mesh_path.is_absolute():
        mesh_path = scene_path.parent / mesh_path
    if is_scene_file(mesh_path):
        raise SceneError(f"{scene_path}: a mesh path must name a mesh file, not a scene file "
                         f"({text})")
    if mesh_path.exists() and not mesh_path.is_file():
        raise SceneError(f"{scene_path}: mesh path {text!r} is not a file ({mesh_path})")
    if mesh_path.is_symlink() and not mesh_path.exists():
        raise SceneError(f"{scene_path}: mesh path {text!r} is a symbolic link that leads "
                         f"nowhere (a loop, or its target is missing: {mesh_path})")
    if not mesh_path.is_file():
        raise SceneError(f"{scene_path}: mesh file {text!r} not found (looked for "
                         f"{mesh_path})")
    return mesh_path


def mesh_matrix(entry: dict, where: str, table: str) -> np.ndarray:
    """The 4×4 placement ``T·Rz·Ry·Rx·S`` of a mesh entry."""
    translate = _vector(entry, "translate", where, table, default=(0.0, 0.0, 0.0))
    rotate = _vector(entry, "rotate", where, table, default=(0.0, 0.0, 0.0))
    scale = entry.get("scale", 1.0)
    if _is_number(scale):
        scale = [scale] * 3
    scale = _vector({"scale": scale}, "scale", where, table, low=MIN_SCALE, high=MAX_SCALE)
    transform = ObjectTransform(tuple(translate), tuple(rotate), tuple(scale))
    return transform.matrix((0.0, 0.0, 0.0))


def _grid(table: Any, where: str) -> tuple[np.ndarray, np.ndarray] | None:
    if table is None:
        return None
    if not isinstance(table, dict):
        raise SceneError(f"{where}: grid must be a table [grid] with min and max (or cells, "
                         f"origin and cell_size)")
    _known(table, GRID_KEYS, where, "[grid]")
    box = [key for key in GRID_BOX_KEYS if key in table]
    if not box and any(key in table for key in EXACT_GRID_KEYS):
        return None                     # an exact grid alone (_exact_grid)
    if len(box) != len(GRID_BOX_KEYS):
        raise SceneError(f"{where}: [grid] needs both min and max")
    lo = np.asarray(_vector(table, "min", where, "[grid]"))
    hi = np.asarray(_vector(table, "max", where, "[grid]"))
    if not np.all(lo < hi):
        raise SceneError(f"{where}: [grid] min must be below max on every axis, got min "
                         f"{lo.tolist()} and max {hi.tolist()}")
    return lo, hi


def _exact_grid(table: Any, where: str
                ) -> tuple[tuple[int, int, int], tuple[float, float, float], float] | None:
    """``(cells, origin, cell_size)`` of [grid] when it gives an exact grid, else None
    (``_grid`` has checked that it is a table)."""
    if table is None:
        return None
    given = [key for key in EXACT_GRID_KEYS if key in table]
    if not given:
        return None
    missing = [key for key in EXACT_GRID_KEYS if key not in table]
    if missing:
        raise SceneError(f"{where}: [grid] gives an exact grid with cells, origin and "
                         f"cell_size together; missing {', '.join(missing)}")
    cells = table["cells"]
    if not isinstance(cells, list) or len(cells) != 3 or not all(
            isinstance(n, int) and not isinstance(n, bool) and 1 <= n <= MAX_GRID_CELLS
            for n in cells):
        raise SceneError(f"{where}: [grid]: cells must be 3 whole numbers in [1, "
                         f"{MAX_GRID_CELLS}] (cells along x, y, z), got {cells!r}")
    origin = _vector(table, "origin", where, "[grid]")
    cell_size = _number(table, "cell_size", where, "[grid]", low=0.0, low_open=True)
    return (tuple(int(n) for n in cells), tuple(origin), cell_size)


def _camera(table: Any, where: str, default: Camera) -> Camera:
    if table is None:
        return default
    if not isinstance(table, dict):
        raise SceneError(f"{where}: camera must be a table [camera]")
    _known(table, CAMERA_KEYS, where, "[camera]")
    eye = _vector(table, "eye", where, "[camera]", default=default.eye)
    target = _vector(table, "target", where, "[camera]", default=default.target)
    fov = _number(table, "fov", where, "[camera]", low=FOV_RANGE[0], high=FOV_RANGE[1],
                  default=default.fov_y_degrees)
    if np.allclose(eye, target):
        raise SceneError(f"{where}: [camera] eye and target must differ, both are "
                         f"{list(eye)}")
    return Camera(tuple(eye), tuple(target), fov)


def _lights(entries: Any, where: str, scene: Scene) -> tuple[tuple[Light, ...], tuple[str, ...]]:
    if not isinstance(entries, list) or not entries or \
            not all(isinstance(entry, dict) for entry in entries):
        raise SceneError(f"{where}: lights must be one or more [[lights]] tables")
    rig, shining = [], []
    for k, entry in enumerate(entries, 1):
        light = light_from_table(entry, where, f"[[lights]] #{k}", scene, k)
        if light.name in (other.name for other in rig):
            raise SceneError(f"{where}: [[lights]] #{k}: the name {light.name!r} is taken; "
                             f"give each light its own name")
        rig.append(light)
        if _flag(entry, "on", where, f"[[lights]] #{k}", default=True):
            shining.append(light.name)
    if not shining or len(shining) > MAX_LIGHTS:
        raise SceneError(f"{where}: 1 to {MAX_LIGHTS} lights must be on, got {len(shining)}")
    return tuple(rig), tuple(shining)


def light_from_table(entry: dict, where: str, table: str, scene: Scene, number: int) -> Light:
    """One ``[[lights]]`` table as a light (its flux from ``flux`` or ``irradiance``)."""
    _known(entry, LIGHT_KEYS, where, table)
    kind = _text(entry, "kind", where, table, default="spot")
    if kind not in LIGHT_KINDS:
        raise SceneError(f"{where}: {table}: kind must be one of {', '.join(LIGHT_KINDS)}, "
                         f"got {kind!r}")
    name = _text(entry, "name", where, table, default=f"{kind} {number}")
    table = f"{table} ({name!r})"
    if "position" not in entry:
        raise SceneError(f"{where}: {table} needs position = [x, y, z]")
    position = _vector(entry, "position", where, table)
    colour = _vector(entry, "colour", where, table, low=0.0, high=1e3, default=(1.0, 1.0, 1.0))
    if not any(colour):
        raise SceneError(f"{where}: {table}: colour must not be all 0")
    target = _vector(entry, "target", where, table) if "target" in entry else None
    if kind in ("spot", "directional") and target is None:
        raise SceneError(f"{where}: {table}: a {kind} light needs target = [x, y, z]")
    if target is not None and np.allclose(position, target):
        raise SceneError(f"{where}: {table}: position and target must differ")
    if kind != "spot" and "cone" in entry:
        raise SceneError(f"{where}: {table}: cone is for spot lights, not {kind} ones")
    cone = None
    if "cone" in entry:
        cone = _vector(entry, "cone", where, table, size=2, low=0.0, high=MAX_CONE_DEGREES)
        if not (cone[0] <= cone[1] and cone[1] > 0.0):
            raise SceneError(f"{where}: {table}: cone = [inner, outer] needs inner <= outer "
                             f"and outer > 0, got {list(cone)}")
    flux = _light_flux(entry, where, table, kind, position, target, scene)
    return new_light(kind, position, target, flux, name=name, colour=colour,
                     cone_degrees=None if cone is None else tuple(cone))


def _light_flux(entry: dict, where: str, table: str, kind: str, position, target,
                scene: Scene) -> float:
    """``flux`` as given, or the flux that gives ``irradiance`` (W/m²) at the target
    facing the light (a directional light: on any plane facing it; a point light: at its
    ``target``, which it then needs); neither: :func:`default_flux`, as ``--light`` gives
    it."""
    if "flux" in entry and "irradiance" in entry:
        raise SceneError(f"{where}: {table}: give flux or irradiance, not both")
    if "flux" in entry:
        return _number(entry, "flux", where, table, low=0.0, high=MAX_FLUX, low_open=True)
    lo, hi = scene.bounds_min, scene.bounds_max
    if "irradiance" not in entry:
        return default_flux(kind, position, target, lo, hi)
    irradiance = _number(entry, "irradiance", where, table, low=0.0, high=MAX_FLUX,
                         low_open=True)
    if kind == "point":         # meant at a point of its choosing, not the default one
        if target is None:
            raise SceneError(f"{where}: {table}: a point light's irradiance needs target = "
                             f"[x, y, z], the point where it is meant")
        distance = float(np.linalg.norm(np.subtract(target, position)))
        return flux_for_irradiance(max(distance, 1e-6), irradiance)
    return default_flux(kind, position, target, lo, hi, irradiance)


def _posed(scene: Scene, table: Any, where: str) -> Scene:
    """The scene with the file's poses baked in: its objects as built are where the file
    puts them (their pivots stay those of the mesh as read, so the window's gizmo and
    the saved poses agree)."""
    pairs = check_transforms(table) if isinstance(table, dict) else None
    if pairs is None:
        raise SceneError(f"{where}: [poses] must map object names to 3, 6 or 9 numbers "
                         f"(translation, rotation in degrees, scale in [{MIN_SCALE:g}, "
                         f"{MAX_SCALE:g}])")
    try:
        posed = scene.posed(pairs)
    except SceneError as exc:
        raise SceneError(f"{where}: [poses]: {exc}") from None
    return replace(posed, pose=(), built=None)


# --- values -----------------------------------------------------------------------------

def _known(table: dict, keys: tuple[str, ...], where: str, name: str) -> None:
    unknown = [key for key in table if key not in keys]
    if unknown:
        raise SceneError(f"{where}: {name}: unknown key{'s' if len(unknown) > 1 else ''} "
                         f"{', '.join(map(repr, unknown))}; allowed: {', '.join(keys)}")


def _is_number(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _number(table: dict, key: str, where: str, name: str, low: float = -MAX_COORDINATE,
            high: float = MAX_COORDINATE, low_open: bool = False, default: Any = None) -> float:
    if key not in table:
        if default is None:
            raise SceneError(f"{where}: {name} needs {key}")
        return float(default)
    value = table[key]
    ok = _is_number(value) and math.isfinite(value) and \
        (value > low if low_open else value >= low) and value <= high
    if not ok:
        raise SceneError(f"{where}: {name}: {key} must be a number in "
                         f"{'(' if low_open else '['}{low:g}, {high:g}], got {value!r}")
    return float(value)


def _vector(table: dict, key: str, where: str, name: str, size: int = 3,
            low: float = -MAX_COORDINATE, high: float = MAX_COORDINATE,
            default: Any = None) -> tuple[float, ...]:
    if key not in table:
        if default is None:
            raise SceneError(f"{where}: {name} needs {key}")
        return tuple(map(float, default))
    value = table[key]
    if not isinstance(value, list) or len(value) != size or not all(
            _is_number(v) and math.isfinite(v) and low <= v <= high for v in value):
        raise SceneError(f"{where}: {name}: {key} must be {size} numbers in [{low:g}, "
                         f"{high:g}], got {value!r}")
    return tuple(float(v) for v in value)


def _text(table: dict, key: str, where: str, name: str, default: str | None = None) -> str:
    if key not in table:
        if default is None:
            raise SceneError(f"{where}: {name} needs {key}")
        return default
    value = table[key]
    if not isinstance(value, str) or not value.strip():
        raise SceneError(f"{where}: {name}: {key} must be non-empty text, got {value!r}")
    return value


def _flag(table: dict, key: str, where: str, name: str, default: bool | None = None) -> bool:
    if key not in table:
        return bool(default)
    value = table[key]
    if not isinstance(value, bool):
        raise SceneError(f"{where}: {name}: {key} must be true or false, got {value!r}")
    return value
