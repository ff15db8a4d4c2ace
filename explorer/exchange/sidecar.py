"""The JSON beside a dump (``out.npz`` -> ``out.json``): where the arrays sit in the world
and what they hold, so that an engine can read them without this code.

It holds the settings (``Settings.to_dict()``, which ``Settings.from_dict`` reads back:
``lpv-explorer diff --settings out.json`` renders the same frame), every cascade's grid
with its axis and texel conventions, the camera's matrices, the lights that shone, every
RSM view (each face of a point light) with its light, matrices, texel area, RSM arrays
and the rows of its VPLs, the porting sheet's conventions and, per array, its
shape, dtype, units and meaning (:data:`explorer.exchange.stages.ARRAYS`).
"""

from __future__ import annotations

import dataclasses
import json
import os
import re
from pathlib import Path

import numpy as np

from explorer.exchange.stages import doc_of

FORMAT = "lpv-explorer dump 1"
MATRIX_CONVENTION = ("4×4 nested lists, row-major (matrix[row][column]), column vectors: "
                     "clip = projection · view · (x, y, z, 1); OpenGL clip space (z in "
                     "[-w, w]), the camera looks along its view space -z")
GRID_CONVENTION = ("array index [colour, x, y, z, k]: x, y, z the cell index along world +x, "
                   "+y, +z (y up); cell (i, j, k) spans origin + [i, i+1)·cell_size (likewise "
                   "j, k), its centre at origin + (index + 1/2)·cell_size; texture coordinate "
                   "(p - origin)/(cell_size·cells) per axis, texel centres at "
                   "(index + 1/2)/cells (cells = [nx, ny, nz])")
IMAGE_CONVENTION = "images (H, W, ...) and RSM arrays: row 0 at the top, column 0 at the left"


def sidecar_path(npz: Path) -> Path:
    return npz.with_suffix(".json")


def _plain(value):
    """JSON-able form of a light field (tuples, numpy scalars)."""
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def light_entry(light, bounds) -> dict:
    """One light as plain data: its kind, every field of its dataclass and, for a light
    with one RSM view (spot, directional), that view's matrices (:data:`MATRIX_CONVENTION`)
    for the scene box ``bounds``."""
    fields = {f.name: _plain(getattr(light, f.name)) for f in dataclasses.fields(light)}
    entry = {"kind": getattr(light, "kind", type(light).__name__), **fields}
    if entry["kind"] in ("spot", "directional"):
        entry["rsm_view_matrix"] = np.asarray(light.view_matrix(*bounds)).tolist()
        entry["rsm_projection_matrix"] = np.asarray(light.projection_matrix(*bounds)).tolist()
    return entry


FACE_NAMES = ("+x", "-x", "+y", "-y", "+z", "-z")
"""A point light's faces by ``LightView.face`` (``explorer.scene.lights.CUBE_FACE_AXES``)."""


def _view_arrays(k: int) -> list[str]:
    prefix = f"view{k}_" if k else ""
    return [f"{prefix}rsm_{part}" for part in ("position", "normal", "flux")]


def rsm_view_entries(result) -> list[dict]:
    """Every RSM view of the frame: its light, kind, face, matrices
    (:data:`MATRIX_CONVENTION`), size and texel area, the names of its RSM arrays and
    which rows of the ``vpl_*`` arrays are its VPLs (``vpl_first``, ``vpls`` and their
    texel area after downsampling; None when the VPLs were handed in)."""
    first = 0
    entries = []
    sets = None if result.vpls_hand_made else result.vpl_sets
    for k, view in enumerate(result.light_views):
        count = sets[k].count if sets is not None and k < len(sets) else None
        entries.append({
            "view": k, "light": view.light_name, "light_index": view.light_index,
            "kind": view.kind, "face": FACE_NAMES[view.face] if view.face >= 0 else None,
            "view_matrix": np.asarray(view.view).tolist(),
            "projection_matrix": np.asarray(view.projection).tolist(),
            "matrix_convention": MATRIX_CONVENTION,
            "projection": "orthographic" if view.orthographic else "perspective",
            "size": [view.size, view.size], "texel_area": view.texel_area,
            "arrays": _view_arrays(k) if result.rsm_views else [],
            "vpl_first": first if count is not None else None, "vpls": count,
            "vpl_texel_area": sets[k].texel_area if count is not None else None})
        first += count or 0
    return entries


def camera_entry(result) -> dict:
    camera = result.camera
    s = result.settings
    aspect = s.width / s.height
    lo, hi = result.scene_bounds
    return {"eye": list(camera.eye), "target": list(camera.target),
            "fov_y_degrees": camera.fov_y_degrees, "aspect": aspect,
            "image_size": [s.width, s.height],
            "view_matrix": camera.view_matrix().tolist(),
            "projection_matrix": camera.projection_matrix(aspect, lo, hi).tolist(),
            "matrix_convention": MATRIX_CONVENTION}


def grid_entry(result) -> list[dict]:
    s = result.settings
    return [{"cascade": k, "origin": list(spec.origin), "cell_size": spec.cell_size,
             "cells": list(spec.cells),
             "resolution": spec.cells[0] if spec.is_cube else None,
             "sh_order": s.sh_order,
             "coefficients": 4 if s.sh_order == 1 else 9, "format": s.grid_format,
             "geometry_volume_cells": [n + 1 for n in spec.cells],
             "geometry_volume_resolution": spec.cells[0] + 1 if spec.is_cube else None,
             "geometry_volume_origin": list(spec.origin),
             "geometry_volume_convention": "geometry cell g centred at origin + g·cell_size "
                                           "(the light grid's corners)",
             "convention": GRID_CONVENTION}
            for k, spec in enumerate(result.cascade_specs)]


def array_entries(arrays: dict[str, np.ndarray]) -> dict[str, dict]:
    entries = {}
    for name, array in arrays.items():
        doc = doc_of(name)
        entries[name] = {"shape": list(array.shape), "dtype": str(array.dtype),
                         "units": doc.units if doc else "", "holds": doc.holds if doc else ""}
    return entries


def scene_entry(scene: str, folder: Path | None) -> str:
    """``Settings.scene`` as a sidecar in ``folder`` holds it: a built-in scene's name as
    it is; a scene or mesh file relative to the sidecar's folder (the dump, its sidecar and
    the scene move together, and ``diff --settings`` finds it from any working folder), or
    absolute where no relative path leads there (another drive)."""
    from explorer.scene.builtin import BUILTIN_SCENES

    if scene in BUILTIN_SCENES or folder is None:
        return scene
    path = Path(scene).expanduser().resolve()
    try:
        return Path(os.path.relpath(path, Path(folder).resolve())).as_posix()
    except ValueError:
        return str(path)


def scene_from_entry(scene: str, folder: Path) -> str:
    """The scene a sidecar in ``folder`` names: a relative path that names a file beside
    the sidecar is that file (as :func:`scene_entry` wrote it); anything else as written
    (a built-in name, an absolute path, a path relative to the working folder)."""
    from explorer.scene.builtin import BUILTIN_SCENES

    if scene in BUILTIN_SCENES or Path(scene).is_absolute():
        return scene
    beside = Path(folder) / scene
    return str(beside) if beside.is_file() else scene


def sidecar(result, arrays: dict[str, np.ndarray], scene=None, extra: dict | None = None,
            folder: Path | None = None) -> dict:
    """The sidecar of a dump of ``result`` holding ``arrays``; ``scene``: the scene as
    rendered (its lights), ``extra``: more entries (compare's reference options),
    ``folder``: where the sidecar is written (a scene file is named relative to it)."""
    from derivations.porting import conventions

    s = result.settings
    settings = s.to_dict()
    settings["scene"] = scene_entry(s.scene, folder)
    data = {
        "format": FORMAT,
        "settings": settings,
        "grids": grid_entry(result),
        "camera": camera_entry(result),
        "scene_bounds": [list(result.scene_bounds[0]), list(result.scene_bounds[1])],
        "lights": [light_entry(light, result.scene_bounds) for light in scene.lights]
        if scene is not None else [],
        "light_names": list(result.light_names),
        "rsm_views": rsm_view_entries(result),
        "vpls_hand_made": result.vpls_hand_made,
        "display_scale": result.display_scale,
        "image_convention": IMAGE_CONVENTION,
        "conventions": [{"title": title, "text": text} for title, text in conventions()],
        "arrays": array_entries(arrays),
    }
    data.update(extra or {})
    return data


_NUMBER_LIST = re.compile(r"\[\s+([-+0-9.eE,\s]+?)\s+\]")
"""A JSON list of plain numbers spread over lines by ``indent``."""


def write_sidecar(path: Path, data: dict) -> None:
    """``data`` as indented JSON, each list of numbers (a vector, a matrix row, a shape) on
    one line."""
    text = json.dumps(data, indent=2, ensure_ascii=False, allow_nan=False)
    text = _NUMBER_LIST.sub(lambda m: "[" + " ".join(m.group(1).split()) + "]", text)
    path.write_text(text + "\n", encoding="utf-8")


def read_settings(path: Path | str):
    """The Settings of a sidecar (``diff --settings``); one-line errors."""
    from explorer.exchange.files import FileFormatError
    from explorer.lpv.settings import Settings
    from explorer.safe_files import UserFileError, parse_json, read_text
    from explorer.schema import SettingError

    try:        # regular files only, within the cap, nesting bounded
        data = parse_json(read_text(path, "settings file"), path)
    except UserFileError as exc:
        raise FileFormatError(f"--settings {exc}") from None
    if not isinstance(data, dict) or "settings" not in data:
        raise FileFormatError(f"--settings {path}: no \"settings\" entry (a dump's sidecar "
                              f"has one)")
    table = data["settings"]
    if isinstance(table, dict) and isinstance(table.get("scene"), str):
        table = {**table, "scene": scene_from_entry(table["scene"], Path(path).parent)}
    try:
        return Settings.from_dict(table, where=f"--settings {path}")
    except SettingError as exc:
        raise FileFormatError(str(exc)) from None
