"""``load_scene``: a built-in scene by name, a scene file (``.toml``,
explorer/scene/scene_file.py), or any mesh file trimesh reads (explorer/scene/meshes.py:
colours, per-pixel textures, sidedness, a light put in when it has none). Every failure
is a :class:`SceneError` naming the file and the problem, never a trimesh traceback.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from explorer.scene.builtin import BUILTIN_SCENES
from explorer.scene.meshes import read_mesh_parts, scene_from_mesh
from explorer.scene.model import Scene, SceneError


def load_scene(name_or_path: str | Path) -> Scene:
    """A built-in scene (``"cornell"``, ``"single-source"``, ``"room"``, ``"atrium"``), a
    scene file (``.toml``, explorer/scene/scene_file.py) or a mesh file."""
    from explorer.scene.scene_file import is_scene_file, read_scene_file

    key = str(name_or_path)
    if key in BUILTIN_SCENES:
        return BUILTIN_SCENES[key]()
    path = check_scene_name(key)
    try:
        if is_scene_file(path):
            return read_scene_file(path)
        mesh_file = read_mesh_parts(path)
        return replace(scene_from_mesh(mesh_file.parts, path.stem, str(path)),
                       files=(str(path.resolve()),), warnings=mesh_file.warnings)
    except SceneError:
        raise
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
                         f"{', '.join(BUILTIN_SCENES)}; a path must point to a scene "
                         f"file (.toml) or a mesh file (OBJ, GLB/glTF, PLY, STL)")
    if not path.is_file():
        raise SceneError(f"{path} is not a file")
    return path
