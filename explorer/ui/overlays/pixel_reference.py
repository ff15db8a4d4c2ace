"""The one-bounce reference radiance at picked pixels, computed in the background.

The Picked panel's button asks for the reference at the picked pixel
(:func:`explorer.truth.progressive.pixel_reference`: a 1×1 tile of the frame's own image
with the frame's own VPLs, shadow rays for "visible", none for "unoccluded"); the window's
controller advances the work within its background-task budget (``runtime.services.tasks``), and
the values are cached per (settings, pixel, mode), so the tooltip and the panel show them
next to the LPV's indirect radiance whenever that pixel of those settings is under the
mouse or picked again. No imgui here: the cache and the queue are tested headlessly.

The work comes in small units, so that no call of :meth:`PixelReferences.advance` holds
a frame for long even in the atrium (186 000 triangles): the scene's BVH for the shadow
rays, built a few nodes per call (:class:`~explorer.truth.bvh.BvhBuilder`, seconds in
all; kept while the scene's geometry stays the same), then the pixel's gather, a few
chunks of VPLs per call (with the atrium's BVH a chunk is one VPL: thousands of
dispatches). :attr:`PixelReferences.units` counts what the last call did.
"""

from __future__ import annotations

import time
from collections import Counter, OrderedDict
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from explorer.truth.progressive import REFERENCE_MODES, pixel_job

CACHE_SIZE = 256
"""Reference values kept (three numbers each)."""
UNITS = ("scene", "BVH nodes", "VPL chunks", "pixels")
"""What :attr:`PixelReferences.units` counts: posing the scene and starting its BVH (one
unit), BVH nodes built, dispatches of the gather (a chunk of VPLs each), pixels started
or finished (one unit each: the G-buffer and VPL uploads, the read-back)."""


@dataclass(frozen=True)
class _Request:
    key: tuple
    frame: Any
    pixel: tuple[int, int]
    mode: str


class PixelReferences:
    """Reference radiance per (settings, pixel, mode): requested, computed, cached.

    ``loaded_scene(name)``: the scene ``name`` as the window loaded it (before the
    Settings' overrides), or None; the BVH is built from it posed for the frame's settings
    (loaded here when None). ``vpl_chunk``: VPLs per dispatch of the gather."""

    def __init__(self, loaded_scene: Callable[[str], Any] | None = None,
                 vpl_chunk: int = 4096) -> None:
        self.cache: OrderedDict[tuple, np.ndarray] = OrderedDict()
        self.pending: list[_Request] = []
        self.problem: str | None = None
        self.units: Counter = Counter()
        """What the last :meth:`advance` did (:data:`UNITS`)."""
        self.vpl_chunk = int(vpl_chunk)
        self._loaded_scene = loaded_scene
        self._bvh: tuple | None = None       # (geometry key, Bvh) for shadow rays
        self._builder: tuple | None = None   # (geometry key, BvhBuilder) while building
        self._job: tuple | None = None       # (request, ProgressiveReference) in progress
        self._pass = None                    # ReferencePass: compiled once

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

    @property
    def running(self) -> bool:
        """Work is queued (the controller keeps the window drawing)."""
        return bool(self.pending)

    def progress(self) -> str | None:
        """What the work in progress does, in words with its share done, or None."""
        if self._builder is not None and self.pending:
            return f"building BVH… {self._builder[1].fraction:.0%}"
        if self._job is not None:
            return f"gathering the reference… {self._job[1].fraction:.0%}"
        return "starting…" if self.pending else None

    # -- the controller's task interface -----------------------------------------------
    def advance(self, ctx, budget_s: float) -> None:
        """Work on the queue for about ``budget_s`` seconds, at least one unit while any is
        left (:attr:`units`)."""
        start = time.perf_counter()
        self.units = Counter()
        try:
            while self.pending:
                left = budget_s - (time.perf_counter() - start)
                if sum(self.units.values()) and left <= 0.0:
                    break
                if not self._work(ctx, self.pending[0], left):
                    break
        except Exception as exc:  # noqa: BLE001 - shown in the panel, the app goes on
            self.problem = f"{type(exc).__name__}: {exc}"
            self.pending.clear()
            self._drop_work()

    def _work(self, ctx, request: _Request, left_s: float) -> bool:
        """One step of ``request``: its BVH (visible), then its gather, then its value.
        False when the next step is a setup (posing the scene, starting a pixel: tens of
        milliseconds in the atrium) and this call has already worked: it waits for the
        next call, which starts with it."""
        from explorer.truth.reference import ReferencePass

        first = not sum(self.units.values())
        visible = request.mode == "visible"
        if visible:
            if not first and self._bvh_setup_due(request.frame.settings):
                return False
            bvh = self._bvh_for(request.frame.settings, left_s)
            if bvh is None:
                return True                      # still building
        else:
            bvh = None
        if self._job is None or self._job[0] is not request:
            if not first:
                return False
            self._release_job()
            if self._pass is None:
                self._pass = ReferencePass(ctx)
            self._job = (request, pixel_job(ctx, request.frame, *request.pixel, visible,
                                            bvh=bvh, reference_pass=self._pass,
                                            vpl_chunk=self.vpl_chunk))
            self.units["pixels"] += 1
            return True
        job = self._job[1]
        if not job.done:
            self.units["VPL chunks"] += job.advance(left_s)
            return True
        self.units["pixels"] += 1                # the value, on the call after the last chunk
        value = job.radiance_at(*request.pixel)
        self._release_job()
        self.pending.pop(0)
        self.cache[request.key] = value
        self.cache.move_to_end(request.key)
        while len(self.cache) > CACHE_SIZE:
            self.cache.popitem(last=False)
        return True

    @staticmethod
    def _geometry(settings) -> tuple:
        """What the BVH depends on: the scene and its objects' transforms."""
        return (settings.scene, settings.object_transforms)

    def _bvh_setup_due(self, settings) -> bool:
        """Whether the next step of a visible request poses the scene for a new BVH."""
        geometry = self._geometry(settings)
        return (self._bvh is None or self._bvh[0] != geometry) and (
            self._builder is None or self._builder[0] != geometry)

    def _bvh_for(self, settings, left_s: float):
        """The BVH of the scene ``settings`` pose (kept while the geometry stays the same:
        the scene and its objects' transforms), or None while it is being built."""
        from explorer.truth.bvh import BvhBuilder
        from explorer.truth.gbuffer import scene_for, scene_triangles

        geometry = self._geometry(settings)
        if self._bvh is not None and self._bvh[0] == geometry:
            return self._bvh[1]
        if self._builder is None or self._builder[0] != geometry:
            loaded = self._loaded_scene(settings.scene) if self._loaded_scene else None
            scene = scene_for(settings, loaded)
            self._builder = (geometry, BvhBuilder(scene_triangles(scene)))
            self.units["scene"] += 1
            return None
        builder = self._builder[1]
        self.units["BVH nodes"] += builder.advance(left_s)
        if builder.done:         # the gather starts on the next call
            self._bvh, self._builder = (geometry, builder.result()), None
        return None

    def _release_job(self) -> None:
        if self._job is not None:
            self._job[1].release()
            self._job = None

    def _drop_work(self) -> None:
        self._release_job()
        self._builder = None

    def release(self) -> None:
        self.pending.clear()
        self._drop_work()
        self._bvh = None
        if self._pass is not None:
            self._pass.release()
            self._pass = None


def pixel_references(state) -> PixelReferences:
    """The state's PixelReferences, made and handed to the app loop on first use."""
    tasks = state.runtime.services.tasks
    for task in tasks:
        if isinstance(task, PixelReferences):
            return task

    def loaded_scene(name: str):
        loaded = state.runtime.scene_facts.scene
        return loaded[1] if loaded is not None and loaded[0] == name else None

    service = PixelReferences(loaded_scene)
    tasks.append(service)
    return service


def ratio(lpv: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """LPV / reference per channel; NaN where the reference is zero."""
    lpv, reference = np.asarray(lpv, np.float64), np.asarray(reference, np.float64)
    return np.divide(lpv, reference, out=np.full(3, np.nan), where=reference != 0)
