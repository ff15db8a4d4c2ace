"""Temporal stability: how much the indirect image changes from frame to frame while the
light, an object or the camera moves slowly (docs/MODEL.md "Moving objects and temporal
stability").

Frame ``t`` moves the thing by ``t·step`` world units along an axis; ``move =
"light-turn"`` turns the primary light instead, its target by ``t·step`` degrees about the
axis through the light's position (the light stays where it is). The change between
frames ``t−1`` and ``t`` is measured on the luminance ``Y`` (Rec. 709) of the linear
indirect image, over the pixels that show the same surface point in both frames (a
moving object's own pixels show other points each frame: their change is the motion,
not the light), relative to the first frame's mean indirect luminance ``Ȳ_0``:

* ``mean_change[t] = mean_pixels |Y_t − Y_{t−1}| / Ȳ_0``,
* ``peak_change[t] = max_pixels |Y_t − Y_{t−1}| / Ȳ_0``.

A moving camera changes the picture itself, so for ``move = "camera"`` every frame's LPV
is gathered (numpy, :func:`explorer.lpv.twin.light_grid.gather_cascades`) at the surface points
the *first* frame sees: only the light moves, as it would on a fixed wall in the world.
With cascades that follow the camera, snapping them to their cells
(``Settings.cascade_snap``) keeps the light still between snaps; without it the VPLs move
to other cells every frame (the light *swims*). A moving light's RSM snapped to its texels
(``Settings.rsm_snap``, explorer/lpv/rsm_snap.py) keeps its VPLs in place between snaps.
The snap is a translation of the light's eye in its image plane: it leaves a turn as it
is (a turning spot's eye does not move, so its VPLs move every frame either way).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from explorer.lpv.settings import Settings
from explorer.lpv.twin.light_grid import gather_cascades, indirect_radiance
from explorer.lpv.twin.tonemap import luminance
from explorer.scene.model import Scene, SceneError

MOVES = ("light", "object", "camera", "light-turn")
SNAPS = {"cascades": "cascade_snap", "rsm": "rsm_snap"}
"""What a stability run's two rows flip: the Settings field of each snapping switch."""
AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


@dataclass(frozen=True)
class Motion:
    """What moves, how far per frame and along which axis."""

    move: str
    step: float
    """World units per frame (``light-turn``: degrees per frame)."""
    axis: str = "x"
    object: str | None = None
    """The object that moves (``move == "object"``; None: the scene's second object, or
    its first when it has one)."""

    def __post_init__(self) -> None:
        if self.move not in MOVES:
            raise ValueError(f"move must be one of {MOVES}, got {self.move!r}")
        if self.axis not in AXES:
            raise ValueError(f"axis must be one of {tuple(AXES)}, got {self.axis!r}")
        if not np.isfinite(self.step):
            raise ValueError(f"step must be a finite distance, got {self.step!r}")

    def offset(self, frame: int) -> np.ndarray:
        return frame * self.step * np.asarray(AXES[self.axis])

    def turned(self, position, target, frame: int) -> np.ndarray:
        """``target`` turned by ``frame·step`` degrees about the axis through
        ``position`` (Rodrigues' rotation)."""
        angle = np.radians(frame * self.step)
        k = np.asarray(AXES[self.axis])
        v = np.asarray(target, np.float64) - np.asarray(position, np.float64)
        turned = (v * np.cos(angle) + np.cross(k, v) * np.sin(angle)
                  + k * (k @ v) * (1.0 - np.cos(angle)))
        return np.asarray(position, np.float64) + turned

    def object_name(self, scene: Scene) -> str:
        if self.object is not None:
            return scene.object_named(self.object).name
        if not scene.objects:
            raise SceneError(f"scene {scene.name!r} has no object that can move")
        return scene.objects[min(1, len(scene.objects) - 1)].name

    def settings(self, base: Settings, scene: Scene, frame: int) -> Settings:
        """``base`` with the thing moved by frame ``frame``'s offset (``scene``: the
        scene ``base`` renders, with its overrides applied)."""
        shift = self.offset(frame)
        if self.move == "camera":
            eye, target = (np.asarray(p, np.float64) + shift
                           for p in (scene.camera.eye, scene.camera.target))
            return base.with_changes(camera=(tuple(eye), tuple(target)))
        if self.move == "light-turn":
            light = scene.light
            target = self.turned(light.position, light.target, frame)
            return base.with_changes(light=(tuple(float(v) for v in light.position),
                                            tuple(float(v) for v in target)))
        if self.move == "light":
            light = scene.light
            position = np.asarray(light.position, np.float64) + shift
            target = np.asarray(light.target, np.float64) + shift
            return base.with_changes(light=(tuple(position), tuple(target)))
        name = self.object_name(scene)
        current = dict(base.object_transforms)
        values = list(current.get(name, (0.0,) * 6 + (1.0,) * 3))
        values[:3] = np.asarray(values[:3]) + shift
        current[name] = tuple(float(v) for v in values)
        return base.with_changes(object_transforms=current)


@dataclass
class StabilityRun:
    """The frame-to-frame changes of one sequence (module docstring)."""

    snap: bool
    mean_change: np.ndarray
    """(frames,) relative mean change between frame t−1 and t, t = 1..frames."""
    peak_change: np.ndarray
    """(frames,) relative largest per-pixel change."""
    reference: float
    """Ȳ_0: the first frame's mean indirect luminance."""

    @property
    def mean(self) -> float:
        return float(np.mean(self.mean_change))

    @property
    def peak(self) -> float:
        return float(np.max(self.peak_change))

    @property
    def frames_changed(self) -> int:
        """Frame pairs with any change at all."""
        return int(np.count_nonzero(self.peak_change > 0.0))


SAME_POINT = 1e-6
"""Pixels whose surface point moved less than this fraction of the scene's size between
two frames show the same point (a still surface is rasterised to the same bits)."""


def frame_changes(images: list[np.ndarray], positions: list[np.ndarray]
                  ) -> tuple[np.ndarray, np.ndarray, float]:
    """``(mean_change, peak_change, Ȳ_0)`` of a sequence of linear (H, W, 3) images whose
    pixels see the (H, W, 4) G-buffer ``positions`` (w = 1 where a surface is seen):
    module docstring."""
    lum = [luminance(np.asarray(image, np.float64)) for image in images]
    valid = [np.asarray(p)[..., 3] > 0.5 for p in positions]
    reference = float(np.mean(lum[0][valid[0]])) if np.any(valid[0]) else 0.0
    if not reference > 0.0:
        raise ValueError("the first frame has no indirect light to compare against")
    points = [np.asarray(p, np.float64)[..., :3] for p in positions]
    seen = points[0][valid[0]]
    tolerance = SAME_POINT * max(float(np.ptp(seen, axis=0).max()), 1e-30)
    means, peaks = [], []
    for t in range(1, len(images)):
        moved = np.linalg.norm(points[t] - points[t - 1], axis=-1)
        both = valid[t] & valid[t - 1] & (moved <= tolerance)
        difference = np.abs(lum[t] - lum[t - 1])[both]
        means.append(float(difference.mean()) / reference if difference.size else 0.0)
        peaks.append(float(difference.max()) / reference if difference.size else 0.0)
    return np.array(means), np.array(peaks), reference


def measure(run_frame: Callable[[Settings], object], scene_for: Callable[[Settings], Scene],
            base: Settings, motion: Motion, frames: int, snap: bool,
            switch: str = "cascades") -> StabilityRun:
    """Render ``frames + 1`` frames of ``motion`` from ``base`` (with the ``switch``'s
    field of :data:`SNAPS` set to ``snap``) through ``run_frame`` (a pipeline's ``run``)
    and measure the changes between consecutive ones. ``scene_for(settings)`` gives the
    scene a Settings renders (for the positions the motion starts from)."""
    if frames < 1:
        raise ValueError(f"frames must be at least 1, got {frames}")
    if switch not in SNAPS:
        raise ValueError(f"switch must be one of {tuple(SNAPS)}, got {switch!r}")
    base = base.with_changes(**{SNAPS[switch]: bool(snap)})
    scene = scene_for(base)
    images, positions, first = [], [], None
    for t in range(frames + 1):
        result = run_frame(motion.settings(base, scene, t))
        if motion.move == "camera":
            first = first or result
            images.append(_regathered(result, first))
            positions.append(first.gbuffer_position)
        else:
            images.append(np.asarray(result.indirect, np.float64))
            positions.append(np.array(result.gbuffer_position))
    means, peaks, reference = frame_changes(images, positions)
    return StabilityRun(bool(snap), means, peaks, reference)


def _regathered(result, first) -> np.ndarray:
    """``result``'s LPV gathered at the surface points ``first`` sees (numpy), as an
    indirect image of ``first``'s size."""
    mask = first.gbuffer_position[..., 3] > 0.5
    positions = first.gbuffer_position[..., :3][mask]
    normals = first.gbuffer_normal[..., :3][mask]
    # the net-flux gather's own exitance a·E_direct = π·direct, a property of the surface
    exitance = (np.pi * np.asarray(first.direct, np.float64)[..., :3][mask]
                if result.settings.gather_net_flux else None)
    irradiance = gather_cascades(result.cascade_accumulated, result.cascade_specs, positions,
                                 normals, result.settings.gather_damping,
                                 irradiance=result.settings.corrections.irradiance_gather,
                                 exitance=exitance)
    image = np.zeros(mask.shape + (3,))
    image[mask] = indirect_radiance(first.albedo[mask], irradiance)
    return image
