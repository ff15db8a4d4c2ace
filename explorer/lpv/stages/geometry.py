"""The ``geometry`` stage: the geometry volume of every cascade
(explorer/lpv/passes/geometry.py; per cascade one unit, or its draws in batches of points
and, for a large grid, each view's draws, copies and merge:
``MergedGeometryPass.unit_count``), built from the RSM texels or hand-made VPLs and, with
camera occluders, the G-buffer's pixels no RSM view sees
(docs/MODEL.md "Camera occluders"); each level's volume is copied for reading as it is
built and every level's taken in one more unit, once the copies are done
(explorer/gl/gpu_sync.py ``DeferredRead``)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from explorer.gl.gpu_sync import DeferredRead, GpuWait
from explorer.lpv import guards
from explorer.lpv.cascades import level_pass_name
from explorer.lpv.corrections import Corrections
from explorer.lpv.passes.geometry import CameraSurfels, MergedGeometryPass, camera_pixel_area
from explorer.lpv.passes.inject import vpl_count
from explorer.lpv.stage_list import StageDecl
from explorer.lpv.stages.base import Stage as StageBase
from explorer.lpv.stages.base import StageHost

if TYPE_CHECKING:
    from explorer.lpv.job import Job


@dataclass(frozen=True)
class Params:
    """What the geometry volume reads of the Settings."""

    corrections: Corrections
    mode: str
    """``geometry_volume``: off, one-sided or double-sided."""
    grid_format: str
    camera_occluders: bool
    image_height: int
    """The G-buffer's height: a camera surfel's pixel area."""

    @classmethod
    def of(cls, settings) -> Params:
        return cls(settings.corrections, settings.geometry_volume, settings.grid_format,
                   bool(settings.uses_camera_occluders), int(settings.height))


class Stage(StageBase):
    def __init__(self, host: StageHost, decl: StageDecl) -> None:
        super().__init__(host, decl)
        self.geometry = MergedGeometryPass(host.ctx, host.programs)
        self.reads: list[DeferredRead] = []
        """One deferred read per cascade level (made as levels appear, reused)."""

    def units(self, job: Job) -> int:
        # the units of each level's volume, then one that takes their copies (none when off)
        if job.settings.geometry_volume == "off":
            return len(self.state.specs)
        occluders = self.host.light_views.occluders(hand_made=job.vpls is not None)
        views = [vpl_count(vpls) for vpls in occluders]
        camera = None
        if job.settings.uses_camera_occluders:
            width, height = self.state.gbuffer_pass.position.size
            camera = width * height
        return sum(MergedGeometryPass.unit_count(views, camera, spec.cells)
                   for spec in self.state.specs) + 1

    def work(self, job: Job) -> Iterator[GpuWait | None]:
        p, host, state = Params.of(job.settings), self.host, self.state
        levels = self.levels()
        if p.mode == "off":
            host.timer.forget("geometry")
            state.warnings["geometry"] = []
            for level in levels:
                level.release_volume()
            return
        occluders = host.light_views.occluders(hand_made=job.vpls is not None)
        camera = self.camera_surfels(p) if p.camera_occluders else None
        host.timer.reset("geometry")
        while len(self.reads) < len(levels):
            self.reads.append(DeferredRead(host.ctx))
        volumes = []
        for k, (level, spec) in enumerate(zip(levels, state.specs)):
            volume = level.geometry_volume(spec.cells, p.grid_format)
            units = self.geometry.run_units(occluders, spec, p.corrections, p.mode, volume,
                                            camera)
            while host.timer.timed("geometry", lambda: next(units, False),
                                   accumulate=True) is None:
                yield None                   # the level's next unit follows
            volume.volume.read_later(self.reads[k])
            volumes.append(volume.volume)
            yield None if k < len(levels) - 1 else GpuWait(self.reads[:len(levels)])
        warnings = []
        for k, (level, volume, read) in enumerate(zip(levels, volumes, self.reads)):
            level.geometry = volume.texels(read.wait())
            warnings.append(guards.arrays_warnings_later(
                level_pass_name("geometry", k, len(levels)), [level.geometry], job.settings))
        state.warnings["geometry"] = guards.joined(warnings)

    def camera_surfels(self, p: Params) -> CameraSurfels:
        """The G-buffer as occluder surfels, tested against every RSM view's shadow map
        (docs/MODEL.md "Camera occluders")."""
        host, gbuffer = self.host, self.state.gbuffer_pass
        camera, lights = host.scene_state.scene.camera, host.light_views
        return CameraSurfels(
            position=gbuffer.position, normal=gbuffer.normal, albedo=gbuffer.albedo,
            view=camera.view_matrix(),
            pixel_area=camera_pixel_area(camera.fov_y_degrees, p.image_height),
            shadow=lights.rsm_textures, views=tuple(lights.views),
            tiles=tuple(lights.shadow_tiles))

    def release(self) -> None:
        self.geometry.release()
        for read in self.reads:
            read.release()
        self.reads.clear()
