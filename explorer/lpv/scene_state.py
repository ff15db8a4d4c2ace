"""The scene side of a frame: the mesh as loaded (once per scene name), its objects posed
by ``Settings.object_transforms`` in the vertex buffer, and the posed scene with the
Settings' camera, lights, flux and spot cone applied.

:class:`SceneState` is owned by the pipeline (``Pipeline.scene_state``); its ``scene``
stage calls :meth:`SceneState.load_and_pose`, and the stages after it read the posed
scene through :meth:`SceneState.for_settings` and draw :attr:`SceneState.buffers`.
"""

from __future__ import annotations

import time

import moderngl

from explorer.lpv.settings import Settings
from explorer.scene import Scene, load_scene
from explorer.scene.gpu import SceneBuffers


class SceneState:
    """The loaded scene, its posed copy and vertex buffer, and the last scene a stage
    asked for with the Settings applied."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self._loaded: dict[str, Scene] = {}
        """Scene name -> the scene as loaded (the last name only)."""
        self._posed: Scene | None = None
        """The loaded scene with the Settings' object transforms applied."""
        self.scene: Scene | None = None
        """The posed scene with the Settings applied, as :meth:`for_settings` last made
        it (the frame's camera and lights)."""
        self.buffers: SceneBuffers | None = None
        """The posed scene's vertex buffer on the GPU."""
        self._made: tuple[Settings, Scene, Scene] | None = None
        """(Settings, posed scene, the scene made of them) of the last :meth:`for_settings`."""
        self.pose_ms = 0.0
        """Wall-clock milliseconds :meth:`load_and_pose` last spent posing objects and
        writing their corners to the vertex buffer (``lpv-explorer bench``'s moving
        object)."""

    def base(self, name: str) -> Scene | None:
        """The scene ``name`` as loaded, before any Settings (None when not loaded)."""
        return self._loaded.get(name)

    def load_and_pose(self, s: Settings, wait: bool = True) -> Scene:
        """Load the mesh (once per scene name) and pose its objects: only the corners of
        objects whose transform changed are written to the vertex buffer again. Returns
        the scene as loaded. ``wait``: :attr:`pose_ms` includes the upload's GPU work
        (a ``finish``); queued passes (``PassTimer.queued``) do not wait."""
        base = self._loaded.get(s.scene)
        if base is None:
            base = self.adopt(s.scene, load_scene(s.scene))
        started = time.perf_counter()
        self._posed = base.posed(s.object_transforms)
        self.buffers.show(self._posed)
        if wait:
            self.ctx.finish()
        self.pose_ms = (time.perf_counter() - started) * 1e3
        return base

    def adopt(self, name: str, scene: Scene) -> Scene:
        """Hold ``scene`` as the scene ``name`` loaded (a scene file edited and read again
        by the window) and put it on the GPU; the next :meth:`load_and_pose` poses it."""
        self._loaded = {name: scene}
        self._posed = None
        if self.buffers is not None:
            self.buffers.release()
        self.buffers = SceneBuffers(self.ctx, scene)
        return scene

    def for_settings(self, s: Settings) -> Scene:
        """The posed scene with the Settings' lights, camera, light, flux and spot cone
        applied (kept as :attr:`scene`)."""
        posed = self._posed if self._posed is not None else self._loaded[s.scene]
        made = self._made
        if made is not None and made[0] is s and made[1] is posed:
            return made[2]      # Settings are frozen: several stages of a frame ask
        self.scene = posed.for_settings(s)
        self._made = (s, posed, self.scene)
        return self.scene

    def forget(self) -> None:
        """Load the mesh again at the next :meth:`load_and_pose` (a scene file edited)."""
        self._loaded.clear()

    def release(self) -> None:
        if self.buffers is not None:
            self.buffers.release()
            self.buffers = None
