"""The window's *File → Save scene as...*: the scene as shown (its lights, camera and
object poses, with the Settings' overrides applied) written to a scene file
(explorer/scene/scene_writer.py) that opens the same picture again."""

from __future__ import annotations

from pathlib import Path

SAVE_FILTERS = ["Scene files", "*.toml", "All files", "*"]


def default_save_path(state, fresh: bool = False) -> Path:
    """Where the save dialog starts: ``<scene>.toml`` in the folder the explorer was
    started from (a scene file saved again: beside itself). ``fresh``: a name no file
    has yet (``<scene>-2.toml``, ...), where the menu item saves when this system has no
    file dialog."""
    source = Path(state.settings.scene)
    stem = source.stem or "scene"
    folder = source.parent if source.suffix.lower() == ".toml" else Path.cwd()
    path = folder / f"{stem}.toml"
    number = 1
    while fresh and path.exists():
        number += 1
        path = folder / f"{stem}-{number}.toml"
    return path


def save_current_scene(state, path: str | Path) -> Path | None:
    """Write the scene ``state`` shows to ``path`` (``.toml`` added when missing) and say
    so in the window; a problem is a message, never an exception (nothing is lost: the
    file is written whole or not at all)."""
    from explorer.scene import SceneError
    from explorer.scene.scene_writer import write_scene_file
    from explorer.truth.gbuffer import scene_for

    loaded = state.runtime.scene_facts.scene
    if loaded is None or loaded[0] != state.settings.scene:
        state.notify("the scene is still loading: save it again in a moment", "warning")
        return None
    try:
        scene = scene_for(state.settings, loaded[1])
        written = write_scene_file(scene, state.settings.scene, Path(path))
    except (SceneError, ValueError) as exc:
        state.notify(f"could not save the scene: {exc}", "error")
        return None
    state.notify(f"scene saved to {written}")
    return written
