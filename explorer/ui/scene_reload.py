"""What the window reloads from disk while it runs: shaders whose files changed (a failed
compile keeps the last good program and shows its log) and the scene on screen when its
file or mesh is edited (an edit that does not load keeps the scene shown); and the facts
of the scene as loaded (its camera and primary light before any override), which the
panels start from."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

from explorer.ui.lesson_watch import LessonWatch
from explorer.ui.scene_watch import SceneWatch

if TYPE_CHECKING:
    from explorer.gl.program import ProgramCache
    from explorer.ui.controller_state import PipelineLike, SideState
    from explorer.ui.state import AppState

SHADER_POLL_S = 0.5
"""Shader and scene files are looked at this often."""


class Reloads:
    """The controller's file watching: shaders of every side, the scene shown and the
    lesson being read."""

    def __init__(self) -> None:
        self.scene_watch = SceneWatch()
        """The files of the scene on screen (reloaded when edited)."""
        self.lesson_watch = LessonWatch()
        """The file of the lesson being read (reloaded when edited)."""
        self.polled_at = 0.0
        self.defaults_for: str | None = None
        """The scene whose defaults ``runtime.scene_facts`` holds."""

    def poll(self, state: AppState, sides: dict[str, SideState], programs: ProgramCache,
             now: float | None = None) -> None:
        """Recompile shaders whose files changed (every :data:`SHADER_POLL_S`), recording
        compile logs in ``runtime.services.shader_errors``; a side whose programs changed
        renders again. Then the scene's files and the lesson's."""
        now = time.monotonic() if now is None else now
        if now - self.polled_at < SHADER_POLL_S:
            return
        self.polled_at = now
        errors: dict[str, str] = {}
        for side in sides.values():
            if side.pipeline is None:
                continue
            if side.pipeline.reload_shaders():
                side.done = None
                state.notify(f"shaders reloaded ({side.name})")
            errors.update(side.pipeline.programs.errors)
        programs.reload_if_changed()
        errors.update(programs.errors)
        state.runtime.services.shader_errors = errors
        self.reload_scene(state, sides)
        self.lesson_watch.poll(state)

    def poll_now(self, state: AppState, sides: dict[str, SideState],
                 programs: ProgramCache) -> None:
        """Look at the files now, whenever they were last looked at."""
        self.polled_at = 0.0
        self.poll(state, sides, programs)

    def reload_scene(self, state: AppState, sides: dict[str, SideState]) -> None:
        """The scene on screen edited on disk (explorer/ui/scene_watch.py): read it again
        and show it; an edit that does not load keeps the scene as it was and says why."""
        shown = state.runtime.scene_facts.scene
        if shown is None:
            return
        name, scene = shown
        if self.scene_watch.name != name:
            self.scene_watch.watch(name, scene.files)
            return
        if not self.scene_watch.changed():
            return
        from explorer.scene import load_scene

        try:
            edited = load_scene(name)
        except Exception as exc:  # noqa: BLE001 - the user's edit, said in the window
            state.notify(f"{name} changed but does not load ({exc}); the scene shown is "
                         f"the one read before", "error")
            return
        for side in sides.values():
            if side.pipeline is not None and side.pipeline.settings.scene == name:
                side.pipeline.reload_scene(edited)
                side.job, side.request, side.done, side.failed = None, None, None, None
        self.defaults_for = None          # its camera and light defaults anew
        state.runtime.scene_facts.scene = (name, edited)
        self.scene_watch.watch(name, edited.files)
        state.notify(f"{name} changed on disk: reloaded")

    def scene_defaults(self, state: AppState, pipeline: PipelineLike, scene_name: str) -> None:
        """The scene as loaded (``runtime.scene_facts.scene``: its lights, objects and
        paths for the Lights & objects panel) and its own camera and primary light
        (before any override), so orbiting and the light sliders start from what is
        shown. Loaded once per scene."""
        rt = state.runtime
        if self.defaults_for == scene_name:
            return
        self.defaults_for = scene_name
        scene = pipeline.base_scene
        if scene is None:
            try:
                from explorer.scene import load_scene

                scene = load_scene(scene_name)
            except Exception:  # noqa: BLE001 - defaults are a convenience
                scene = None
        rt.scene_facts.scene = None if scene is None else (scene_name, scene)
        for line in (getattr(scene, "notice", ""), *getattr(scene, "warnings", ())):
            if line:        # e.g. where a light was put in a closed mesh, a lost texture
                state.notify(line)
        from explorer.scene import SpotLight

        rt.scene_facts.camera_default = eye_target(scene.camera if scene is not None else None)
        light = None
        if scene is not None:
            try:     # the primary light of the lights that shine (Settings.lights)
                light = scene.with_lights(state.settings.lights).light
            except Exception:  # noqa: BLE001 - lights the scene does not have
                light = scene.light
        rt.scene_facts.light_default = eye_target(light)
        rt.scene_facts.light_flux_default = light.flux if light is not None else None
        facts = rt.scene_facts
        facts.light_is_spot = isinstance(light, SpotLight)
        facts.light_cone_default = light.cone_degrees if facts.light_is_spot else None


def eye_target(value) -> tuple | None:
    """(eye, target) from a camera/light object or pair, or None."""
    if value is None:
        return None
    for eye_name, target_name in (("eye", "target"), ("position", "target")):
        if hasattr(value, eye_name) and hasattr(value, target_name):
            eye, target = getattr(value, eye_name), getattr(value, target_name)
            if callable(eye):   # DirectionalLight.eye(bounds) is a method: use position
                continue
            return (tuple(float(v) for v in eye), tuple(float(v) for v in target))
    try:
        eye, target = value
        return (tuple(float(v) for v in eye), tuple(float(v) for v in target))
    except (TypeError, ValueError):
        return None
