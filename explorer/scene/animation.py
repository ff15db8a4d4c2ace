"""What a scene's animation paths say at a time: Settings changes.

A scene's paths (explorer/scene/paths.py) move its primary light (``Scene.light_path``)
and some objects (``Scene.object_paths``). :func:`pose_changes` evaluates the paths that
play at time ``t`` and returns them as the Settings fields they set (``light`` and
``object_transforms``), so an animated frame is an ordinary frame: the window writes
these changes into its Settings every frame while playing, ``lpv-explorer render --time``
once, and the pipeline's stage keys re-run exactly what the changes touch (a moving light
re-renders the RSM and what follows it, a moving object also the G-buffer).
"""

from __future__ import annotations

from collections.abc import Iterable

from explorer.scene.model import Scene, SceneError

LIGHT = "light"
"""The name that selects the primary light's path among the paths that play."""


def path_names(scene: Scene) -> tuple[str, ...]:
    """The paths a scene offers: ``"light"`` when it has a light path, then its animated
    objects."""
    names = (LIGHT,) if scene.light_path is not None else ()
    return names + tuple(name for name, _ in scene.object_paths)


def check_path_names(scene: Scene, names: Iterable[str]) -> tuple[str, ...]:
    """``names`` as a tuple; a :class:`SceneError` naming the scene's paths when one is
    not among them."""
    names = tuple(names)
    offered = path_names(scene)
    unknown = [name for name in names if name not in offered]
    if unknown:
        raise SceneError(f"scene {scene.name!r} has no animation path {unknown[0]!r}; its "
                         f"paths are {', '.join(offered) or 'none'}")
    return names


def pose_changes(scene: Scene, seconds: float, names: Iterable[str] | None = None,
                 transforms=()) -> dict[str, object]:
    """The Settings changes that put the paths ``names`` (default: all the scene's) at
    time ``seconds``: ``light`` = the light path's (position, target), and
    ``object_transforms`` = ``transforms`` (the current ones) with every animated object's
    transform replaced by its path's."""
    names = path_names(scene) if names is None else check_path_names(scene, names)
    changes: dict[str, object] = {}
    if LIGHT in names:
        values = scene.light_path.at(seconds)
        changes["light"] = (tuple(map(float, values[:3])), tuple(map(float, values[3:])))
    paths = dict(scene.object_paths)
    moved = {name: tuple(map(float, paths[name].at(seconds)))
             for name in names if name in paths}
    if moved:
        changes["object_transforms"] = tuple(sorted({**dict(transforms or ()),
                                                     **moved}.items()))
    return changes


def camera_at(scene: Scene, parameter: float) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """``(eye, target)`` of the scene's camera path at ``parameter`` (one loop per unit,
    wrapping): the atrium's fly-through. A :class:`SceneError` when the scene has none."""
    if scene.camera_path is None:
        raise SceneError(f"scene {scene.name!r} has no camera path (a fly-through); the "
                         f"atrium has one")
    values = scene.camera_path.at(parameter)
    return tuple(map(float, values[:3])), tuple(map(float, values[3:]))
