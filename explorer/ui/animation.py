"""Playing the scene's animation paths and its fly-through in the window.

The window's clock advances :class:`Animation` once per frame (:func:`tick`): while the
paths play, their values at the animation time become Settings changes
(``explorer.scene.animation.pose_changes``: the primary light's placement, the animated
objects' transforms), and while the fly-through plays the camera follows the scene's
camera path. So an animated frame is an ordinary frame: the pipeline's stage keys re-run
what the changes touch. While either plays the window must keep drawing frames
(:attr:`Animation.active`: a reason not to idle).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from explorer.scene import SceneError
from explorer.scene.animation import camera_at, path_names, pose_changes

MAX_STEP_S = 0.25
"""The clock advances at most this much per frame: a slow frame (a pipeline run on a
software renderer) slows the animation down rather than making it jump."""
GIZMO_OPERATIONS = ("move", "turn", "scale")


@dataclass
class Animation:
    """The window's animation clock, the paths that play and the object the gizmo moves
    (never persisted)."""

    playing: bool = False
    seconds: float = 0.0
    """The paths' time."""
    speed: float = 1.0
    """Animation seconds per second."""
    paths: tuple[str, ...] | None = None
    """The paths that play (``explorer.scene.animation.path_names``); None: all."""
    flying: bool = False
    fly_parameter: float = 0.0
    """Where the camera is on the scene's camera path (one loop per unit)."""
    fly_speed: float = 0.02
    """Loops per second of the fly-through."""
    selected: str | None = None
    """The object the gizmo moves."""
    operation: str = "move"
    scene: str | None = None
    """The scene name this state belongs to (a new scene starts afresh)."""
    last_tick: float | None = None

    @property
    def active(self) -> bool:
        """Something plays: the window must draw the next frame without waiting for an
        event."""
        return self.playing or self.flying


def animation_of(state) -> Animation:
    """The state's animation clock (made on first use; reset when the scene changes)."""
    services = state.runtime.services
    animation = services.animation
    if animation is None or animation.scene != state.settings.scene:
        animation = services.animation = Animation(scene=state.settings.scene)
    return animation


def scene_of(state):
    """The scene the window shows as loaded (before the Settings' overrides), or None
    while the pipeline has not loaded it yet."""
    loaded = state.runtime.scene_facts.scene
    if loaded is None or loaded[0] != state.settings.scene:
        return None
    return loaded[1]


def tick(state, now: float | None = None) -> bool:
    """Advance the clock to ``now`` (default: the monotonic clock) and write what plays
    into configuration A. Returns whether something plays."""
    animation = animation_of(state)
    now = time.monotonic() if now is None else float(now)
    step = 0.0 if animation.last_tick is None else min(max(now - animation.last_tick, 0.0),
                                                       MAX_STEP_S)
    animation.last_tick = now
    scene = scene_of(state)
    if scene is None or not animation.active:
        return animation.active
    try:
        if animation.playing:
            animation.seconds += step * animation.speed
            names = tuple(name for name in path_names(scene)
                          if animation.paths is None or name in animation.paths)
            if names:
                state.update(**pose_changes(scene, animation.seconds, names,
                                            state.settings.object_transforms))
        if animation.flying:
            animation.fly_parameter = (animation.fly_parameter
                                       + step * animation.fly_speed) % 1.0
            state.update(camera=camera_at(scene, animation.fly_parameter))
    except SceneError as exc:          # e.g. the scene has no camera path: stop, say why
        animation.playing = animation.flying = False
        state.notify(f"animation stopped: {exc}", "error")
    return animation.active
