"""The one-bounce reference radiance at picked pixels, computed in the background.

The Picked panel's button asks for the reference at the picked pixel
(:func:`explorer.truth.progressive.pixel_reference`: a 1×1 tile of the frame's own image
with the frame's own VPLs, shadow rays for "visible", none for "unoccluded"); the app loop
computes one pixel per call of :meth:`PixelReferences.advance` (``runtime.tasks``), and the
values are cached per (settings, pixel, mode), so the tooltip and the panel show them next
to the LPV's indirect radiance whenever that pixel of those settings is under the mouse or
picked again. No imgui here: the cache and the queue are tested headlessly.
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass
from typing import Any

import numpy as np

from explorer.truth.progressive import REFERENCE_MODES, pixel_reference

CACHE_SIZE = 256
"""Reference values kept (three numbers each)."""


@dataclass(frozen=True)
class _Request:
    key: tuple
    frame: Any
    pixel: tuple[int, int]
    mode: str


class PixelReferences:
    """Reference radiance per (settings, pixel, mode): requested, computed, cached."""

    def __init__(self) -> None:
        self.cache: OrderedDict[tuple, np.ndarray] = OrderedDict()
        self.pending: list[_Request] = []
        self.problem: str | None = None
        self._scene: tuple | None = None     # (scene name, scene, bvh) for shadow rays

    @staticmethod
    def key(frame, pixel, mode: str) -> tuple:
        return (frame.settings, (int(pixel[0]), int(pixel[1])), mode)

    def value(self, frame, pixel, mode: str) -> np.ndarray | None:
        """The cached reference radiance (3,) of ``pixel`` of ``frame``, or None."""
        return self.cache.get(self.key(frame, pixel, mode))

    def values(self, frame, pixel) -> tuple[tuple[str, np.ndarray], ...]:
        """(mode, radiance) of every mode computed for this pixel of this frame."""
        found = ((mode, self.value(frame, pixel, mode)) for mode in REFERENCE_MODES)
        return tuple((mode, value) for mode, value in found if value is not None)

    def request(self, frame, pixel, modes=REFERENCE_MODES) -> None:
        """Queue the modes of ``pixel`` that are neither cached nor queued."""
        self.problem = None
        queued = {request.key for request in self.pending}
        for mode in modes:
            if mode not in REFERENCE_MODES:
                raise ValueError(f"mode must be one of {REFERENCE_MODES}, got {mode!r}")
            key = self.key(frame, pixel, mode)
            if key not in self.cache and key not in queued:
                self.pending.append(_Request(key, frame, (int(pixel[0]), int(pixel[1])), mode))

    def computing(self, frame, pixel) -> bool:
        """Whether a mode of this pixel of this frame is queued."""
        where = (frame.settings, (int(pixel[0]), int(pixel[1])))
        return any(request.key[:2] == where for request in self.pending)

    # -- the app loop's task interface -------------------------------------------------
    def advance(self, ctx, budget_s: float) -> None:
        """Compute one queued pixel (one mode): a single tile, all VPLs."""
        if not self.pending:
            return
        request = self.pending.pop(0)
        try:
            scene, bvh = self._scene_for(request.frame, request.mode == "visible")
            value = pixel_reference(ctx, request.frame, *request.pixel,
                                    request.mode == "visible", scene=scene, bvh=bvh)
        except Exception as exc:  # noqa: BLE001 - shown in the panel, the app goes on
            self.problem = f"{type(exc).__name__}: {exc}"
            self.pending.clear()
            return
        self.cache[request.key] = value
        self.cache.move_to_end(request.key)
        while len(self.cache) > CACHE_SIZE:
            self.cache.popitem(last=False)

    def _scene_for(self, frame, visibility: bool):
        """(scene, bvh) for shadow rays, kept while the scene stays the same (a mesh's
        BVH is the costly part); (None, None) without visibility."""
        if not visibility:
            return None, None
        name = frame.settings.scene
        if self._scene is None or self._scene[0] != name:
            from explorer.truth.bvh import build_bvh
            from explorer.truth.gbuffer import scene_for, scene_triangles

            scene = scene_for(frame.settings)
            self._scene = (name, scene, build_bvh(scene_triangles(scene)))
        return self._scene[1], self._scene[2]

    def release(self) -> None:
        self.pending.clear()
        self._scene = None


def pixel_references(state) -> PixelReferences:
    """The state's PixelReferences, made and handed to the app loop on first use."""
    tasks = state.runtime.tasks
    for task in tasks:
        if isinstance(task, PixelReferences):
            return task
    service = PixelReferences()
    tasks.append(service)
    return service


def ratio(lpv: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """LPV / reference per channel; NaN where the reference is zero."""
    lpv, reference = np.asarray(lpv, np.float64), np.asarray(reference, np.float64)
    return np.divide(lpv, reference, out=np.full(3, np.nan), where=reference != 0)
