"""Write a scene as it is now (its lights, camera, grid box and object poses) to a scene
file (explorer/scene/scene_file.py) that opens the same picture again: the window's
*File → Save scene as...*.

The geometry is referred to, not copied: a built-in scene as ``builtin = NAME``, a mesh
file as one ``[[meshes]]`` entry, a scene file by its own ``[[meshes]]`` entries (their
paths made relative to the new file's folder where they can be). Object poses are written
as the file's ``[poses]``; when the scene came from a scene file that posed its objects
already, the file's pose and the window's are composed into one.

A small TOML writer of this schema's values (texts, booleans, numbers, lists of numbers,
tables and arrays of tables): numbers are written with ``repr`` (the shortest text that
reads back as the same float), texts as JSON strings (a valid TOML basic string).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

from explorer.scene.lights import Light
from explorer.scene.model import Scene, SceneError
from explorer.scene.objects import ObjectTransform, check_transforms


def scene_file_text(scene: Scene, source: str, destination: Path) -> str:
    """The scene file for ``scene`` (the scene as shown: posed, the Settings' camera and
    lights applied), whose geometry came from ``source`` (``Settings.scene``: a built-in
    name, a mesh file or a scene file), to be written at ``destination``."""
    from explorer.scene.builtin import BUILTIN_SCENES
    from explorer.scene.scene_file import is_scene_file

    lines = ["# lpv-explorer scene file (docs/SCENES.md)", f"name = {_text(scene.name)}"]
    file_poses: dict[str, tuple[float, ...]] = {}
    meshes: list[dict] = []
    if source in BUILTIN_SCENES:
        lines.append(f"builtin = {_text(source)}")
    elif is_scene_file(source):
        data = _read_table(Path(source))
        if "builtin" in data:
            lines.append(f"builtin = {_text(data['builtin'])}")
        for entry in data.get("meshes", []):
            entry = dict(entry)
            entry["path"] = _relative(Path(source).parent / entry["path"], destination)
            meshes.append(entry)
        file_poses = dict(check_transforms(data.get("poses", {})) or ())
    else:
        meshes.append({"path": _relative(Path(source), destination)})
    camera = scene.camera
    lines += ["", "[camera]", f"eye = {_numbers(camera.eye)}",
              f"target = {_numbers(camera.target)}", f"fov = {_number(camera.fov_y_degrees)}",
              "", "[grid]", f"min = {_numbers(scene.bounds_min)}",
              f"max = {_numbers(scene.bounds_max)}"]
    for entry in meshes:
        lines += ["", "[[meshes]]"] + [f"{key} = {_value(value)}" for key, value in entry.items()]
    shining = scene.lights_on if scene.lights_on is not None else scene.light_names
    order = [*shining, *(name for name in scene.light_names if name not in shining)]
    by_name = {light.name: light for light in scene.rig}
    for name in order:
        lines += ["", "[[lights]]"] + _light_lines(by_name[name], name in shining)
    poses = _poses(scene, file_poses)
    if poses:
        lines += ["", "[poses]"] + [f"{_text(name)} = {_numbers(values)}"
                                    for name, values in poses]
    return "\n".join(lines) + "\n"


def write_scene_file(scene: Scene, source: str, destination: Path) -> Path:
    """Write :func:`scene_file_text` to ``destination`` whole (a temporary file, then a
    rename); returns the path. A :class:`SceneError` when it cannot be written."""
    destination = Path(destination).expanduser()
    if destination.suffix.lower() != ".toml":
        destination = destination.with_name(destination.name + ".toml")
    from explorer.safe_files import os_error_text, write_atomically

    text = scene_file_text(scene, source, destination)
    try:
        return write_atomically(destination, text)
    except OSError as exc:
        raise SceneError(f"cannot write {destination}: {os_error_text(exc)}") from None


def _light_lines(light: Light, on: bool) -> list[str]:
    lines = [f"kind = {_text(light.kind)}", f"name = {_text(light.name)}",
             f"position = {_numbers(light.position)}"]
    if light.kind != "point":
        lines.append(f"target = {_numbers(light.target)}")
    cone = getattr(light, "cone_degrees", None)
    if cone is not None:
        lines.append(f"cone = {_numbers(cone)}")
    lines += [f"flux = {_number(light.flux)}", f"colour = {_numbers(light.colour)}",
              f"on = {'true' if on else 'false'}"]
    return lines


def _poses(scene: Scene, file_poses: dict[str, tuple[float, ...]]
           ) -> list[tuple[str, tuple[float, ...]]]:
    """Every object's pose to write: the window's (``scene.pose``) after the source file's
    own, composed about the object's pivot into one transform."""
    window = dict(scene.pose)
    poses = []
    for obj in scene.objects:
        first = file_poses.get(obj.name)
        then = window.get(obj.name)
        if first is None and then is None:
            continue
        if first is None or then is None:
            values = first if then is None else then
        else:
            values = _composed(first, then, obj.pivot, obj.name)
        if not ObjectTransform.from_values(values).is_identity:
            poses.append((obj.name, tuple(values)))
    return poses


def _composed(first, then, pivot, name: str) -> tuple[float, ...]:
    """The one transform about ``pivot`` that moves as ``first`` followed by ``then``."""
    matrix = ObjectTransform.from_values(then).matrix(pivot) @ \
        ObjectTransform.from_values(first).matrix(pivot)
    shift = np.eye(4)
    shift[:3, 3] = pivot
    try:
        composed = ObjectTransform.from_model_matrix(matrix @ shift, pivot)
    except ValueError as exc:
        raise SceneError(f"object {name!r}: its pose cannot be saved ({exc})") from None
    if not np.allclose(composed.matrix(pivot), matrix, rtol=1e-9, atol=1e-9):
        raise SceneError(f"object {name!r}: a stretch after a turn shears it, which one "
                         f"pose (translation, rotation, scale) cannot hold")
    return composed.values()


def _read_table(path: Path) -> dict:
    import tomllib

    from explorer.safe_files import UserFileError, parse_toml, read_text

    try:
        return parse_toml(read_text(path, "scene file"), path)
    except (UserFileError, tomllib.TOMLDecodeError) as exc:
        raise SceneError(f"cannot read the scene file {path} again: {exc}") from None


def _relative(path: Path, destination: Path) -> str:
    """``path`` relative to ``destination``'s folder, or absolute when on another drive."""
    path = path.expanduser().resolve()
    try:
        return Path(os.path.relpath(path, destination.expanduser().resolve().parent)).as_posix()
    except ValueError:
        return path.as_posix()


def _value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return _text(value)
    if isinstance(value, (list, tuple)):
        return _numbers(value)
    return _number(value)


def _text(text: str) -> str:
    return json.dumps(str(text), ensure_ascii=False)


def _number(value) -> str:
    value = float(value)
    if not math.isfinite(value):
        raise SceneError(f"cannot write the number {value!r} to a scene file")
    return repr(value)


def _numbers(values) -> str:
    return "[" + ", ".join(_number(v) for v in values) + "]"
