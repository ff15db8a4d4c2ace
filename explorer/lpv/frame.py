"""What one frame computed, as numpy arrays (:class:`FrameResult`), and how what the
stages left (:class:`~explorer.lpv.frame_state.FrameState`) becomes one
(:func:`frame_result`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from explorer.lpv import guards
from explorer.lpv.audit import EnergyAudit, GridAudit
from explorer.lpv.deferred import Deferred, DeferredField
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.audit_reduce import CellAuditRecords
from explorer.lpv.passes.display import exposed_image
from explorer.lpv.passes.fog import FogImages
from explorer.lpv.passes.rsm import LightView
from explorer.lpv.settings import Settings
from explorer.lpv.vpl import VplArrays
from explorer.scene.camera import Camera

if TYPE_CHECKING:
    from explorer.lpv.frame_state import FrameState
    from explorer.lpv.timing import PassTimer
    from explorer.scene.model import Scene


@dataclass
class LevelResult:
    """One cascade level (docs/MODEL.md "Cascades"); level 0 is the finest, or the single
    grid enclosing the scene."""

    spec: GridSpec
    accumulated: np.ndarray
    """acc_N, ``(3, N, N, N, 4)`` (L1) or ``(3, N, N, N, 9)`` (``sh_order`` 2)."""
    steps: Sequence[np.ndarray] | None
    """grid_0..grid_N when the frame kept its steps (``keep_steps``) and the level is one
    of the pipeline's ``steps_levels``, else None (the sequence the propagation recorded,
    explorer/lpv/kept_steps.py: the pipeline keeps it only until a job that does not ask
    for steps)."""
    geometry_volume: np.ndarray | None
    """``(N+1, N+1, N+1, 4)`` blocking SH, None when the geometry volume is off."""
    audit: GridAudit
    """Injection and propagation audit of this level. Each cascade holds every VPL
    inside it, so the injected fluxes of the levels overlap and must not be summed."""
    cell_records: CellAuditRecords | None = None
    """The propagation's per-cell audit records, still on the GPU: read one cell at a
    time (``cell_records.read((i, j, k))``) while no later propagation of this level has
    overwritten them; None when the frame ran without the per-step audit."""


@dataclass
class FrameResult:
    """Everything one frame computed, as numpy arrays. Images are ``(H, W, 3)`` float32
    with row 0 at the top; RSM arrays ``(Hr, Wr, 4)``, row 0 at the top.

    ``cascades`` holds every cascade level, finest first (one entry when
    ``settings.cascades == 1``); ``grid_spec``, ``accumulated``, ``steps`` and
    ``geometry_volume`` are level 0's."""

    settings: Settings
    cascades: list[LevelResult]
    direct: np.ndarray
    """Linear direct radiance (no exposure)."""
    indirect: np.ndarray
    """Linear LPV radiance albedo/π·E (no exposure)."""
    albedo: np.ndarray
    gbuffer_position: np.ndarray
    """``(H, W, 4)`` world position of each pixel's surface, w = 1 where one is seen."""
    gbuffer_normal: np.ndarray
    """``(H, W, 4)`` viewer-facing normal, w = the surface's world area under the pixel."""
    rsm_position: np.ndarray
    rsm_normal: np.ndarray
    rsm_flux: np.ndarray
    vpls: VplArrays
    """The VPLs injected (after downsampling, or the ones handed to the pipeline), every
    light's together (``texel_area`` and ``projection`` are the first view's: see
    :attr:`vpl_sets` for each view's own)."""
    audit: EnergyAudit
    """Level 0's audit plus the RSM's flux and the flux the visible surfaces gather
    (the blended gather's with cascades)."""
    timings_ms: dict[str, float]
    """Pass name -> milliseconds of its last run (also for passes skipped this time)."""
    timing_methods: dict[str, str] = field(default_factory=dict)
    """Pass name -> "timer-query" or "wall-clock"."""
    stages_run: tuple[str, ...] = ()
    """The stages that ran for this result (the others were up to date), in
    :data:`explorer.lpv.stage_list.STAGES` order."""
    warnings: list[str] = DeferredField(list)  # type: ignore[assignment]
    """Plain-text warnings of the numeric guards (explorer/lpv/guards.py): a pass whose
    output is not finite (with the switches that are off), flux that grows every step,
    a mesh whose scale makes the light vanish or overflow (checked when first read:
    explorer/lpv/deferred.py)."""
    display_scale: float = 1.0
    """What the display multiplies ``final_image`` by before the tone curve
    (docs/MODEL.md "Display"): the auto exposure key/L̄, 1 without it, or
    ``Pipeline.display_scale_override``. ``render_view("final")`` and the display texture
    both use it."""
    # The camera's view of the frame, for picking and for drawing in the scene
    # (explorer/ui/overlays); with gbuffer_position and gbuffer_normal above.
    camera: Camera | None = None
    """The camera the frame was rendered with (the scene's, with Settings.camera applied)."""
    scene_bounds: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None
    """(min, max) corners of the scene's box; with ``camera`` they fix the projection
    (:meth:`Camera.projection_matrix`)."""
    fog: FogImages | None = None
    """The fog's transmittance and in-scattered radiance (docs/MODEL.md "Fog"); None when
    ``settings.fog`` is off. ``direct`` and ``indirect`` stay the surfaces' own radiance;
    :attr:`final_image` composes the two."""
    vpl_sets: list[VplArrays] = field(default_factory=list)
    """The VPLs of each RSM view (docs/MODEL.md "Several lights"; one entry for one
    light, six for a point light), their own ``texel_area`` and ``projection`` each."""
    light_names: tuple[str, ...] = ()
    """The lights that shone, primary first (``audit.rsm_per_light`` has their order)."""
    view_lights: tuple[int, ...] = ()
    """For each entry of :attr:`vpl_sets`: the index of its light in :attr:`light_names`
    (hand-made VPLs: one set, light 0)."""
    rsm_views: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = field(default_factory=list)
    """Every RSM view's ``(position, normal, flux)`` ``(Hr, Wr, 4)`` arrays, primary light
    first, a point light's six faces in ``CUBE_FACE_AXES`` order (the first is
    ``rsm_position``, ``rsm_normal``, ``rsm_flux``), when the frame kept its steps
    (``keep_steps``) or has one view; empty otherwise. The RSM's VPLs are
    :attr:`vpl_sets`, view by view."""
    light_views: tuple[LightView, ...] = ()
    """The RSM views rendered (primary light first, a point light's six faces in
    ``CUBE_FACE_AXES`` order; :attr:`rsm_views` and :attr:`vpl_sets` follow it): each one's
    light, kind, face and matrices (what a dump's sidecar lists as ``rsm_views``)."""
    vpls_hand_made: bool = False
    """The VPLs were handed to the pipeline (``--vpls``): :attr:`vpl_sets` is their one set,
    not the views'."""
    received: np.ndarray | None = None
    """``(H, W, 3)`` LPV flux [W] each pixel's surface receives: the indirect irradiance E
    times the surface's area under the pixel (the gather's third target; E = received /
    ``gbuffer_normal`` w)."""
    _final_image: np.ndarray | None = field(default=None, init=False, repr=False,
                                            compare=False)

    @property
    def final_image(self) -> np.ndarray:
        """Linear colour, exposure applied (``exposure·indirect`` when ``indirect_only``;
        the fog composed over it when there is one): what the display stage scales by
        :attr:`display_scale`, tone-maps and encodes (computed on first use)."""
        if self._final_image is None:
            s = self.settings
            self._final_image = exposed_image(self.direct, self.indirect, s.exposure,
                                              s.indirect_only, self.fog)
        return self._final_image

    @property
    def image_size(self) -> tuple[int, int]:
        """(height, width) of the frame's images, without computing :attr:`final_image`
        (a 960×540 frame's takes 8–11 ms: the window asks for the size every new frame)."""
        height, width = self.direct.shape[:2]
        return int(height), int(width)

    def final_pixel(self, y: int, x: int, exposure: float | None = None,
                    indirect_only: bool | None = None) -> np.ndarray:
        """``final_image[y, x]``, bit for bit (every step of :func:`exposed_image` is per
        pixel), computed for that pixel alone unless the whole image already is;
        ``exposure`` and ``indirect_only`` (default: the frame's settings') as another
        display shows it (the window runs the pipelines with the display's fields pinned
        and applies its own: explorer/ui/controller.py ``PINNED_DISPLAY``)."""
        s, fog = self.settings, self.fog
        exposure = s.exposure if exposure is None else exposure
        indirect_only = s.indirect_only if indirect_only is None else indirect_only
        if self._final_image is not None and (exposure, indirect_only) == (
                s.exposure, s.indirect_only):
            return self._final_image[y, x]
        at = (slice(y, y + 1), slice(x, x + 1))
        return exposed_image(self.direct[at], self.indirect[at], exposure, indirect_only,
                             None if fog is None else fog.part(at))[0, 0]

    # level 0 (the finest cascade, or the single grid)
    @property
    def grid_spec(self) -> GridSpec:
        return self.cascades[0].spec

    @property
    def accumulated(self) -> np.ndarray:
        return self.cascades[0].accumulated

    @property
    def steps(self) -> Sequence[np.ndarray] | None:
        return self.cascades[0].steps

    @property
    def geometry_volume(self) -> np.ndarray | None:
        return self.cascades[0].geometry_volume

    # every level, finest first
    @property
    def cascade_specs(self) -> list[GridSpec]:
        return [level.spec for level in self.cascades]

    @property
    def cascade_accumulated(self) -> list[np.ndarray]:
        return [level.accumulated for level in self.cascades]

    @property
    def cascade_geometry(self) -> list[np.ndarray | None]:
        return [level.geometry_volume for level in self.cascades]

    @property
    def cascade_audits(self) -> list[GridAudit]:
        return [level.audit for level in self.cascades]


def frame_result(settings: Settings, state: FrameState, scene: Scene, timer: PassTimer,
                 stages_run: tuple[str, ...]) -> FrameResult:
    """The FrameResult of a completed frame: what the stages left in ``state``, ``scene``
    the scene as rendered and ``timer`` the passes' times (the growth warning is added
    to the stages' warnings here, from the audit)."""
    s = settings
    rsm, gbuffer, gather, vpls = state.rsm, state.gbuffer, state.gather, state.vpls
    cascades = [LevelResult(spec, level.accumulated, level.output.steps, level.geometry,
                            level.output.audit, level.output.cell_records)
                for spec, level in zip(state.specs, state.levels)]
    by_stage = dict(state.warnings)     # the stages' checks as this frame left them
    # the sums over the read-back images are taken when somebody reads them
    audit = EnergyAudit.from_grid_audit(cascades[0].audit, rsm=lambda: rsm.total_flux,
                                        gathered=lambda: gather.gathered,
                                        rsm_per_light=lambda: rsm.flux_per_light)
    return FrameResult(
        settings=s, cascades=cascades,
        direct=gather.direct[..., :3], indirect=gather.indirect[..., :3],
        received=gather.received[..., :3],
        albedo=gbuffer.albedo[..., :3], gbuffer_position=gbuffer.position,
        gbuffer_normal=gbuffer.normal,
        rsm_position=rsm.position, rsm_normal=rsm.normal, rsm_flux=rsm.flux,
        vpls=vpls.vpls, vpl_sets=list(vpls.sets),
        light_names=tuple(light.name for light in scene.lights),
        view_lights=vpls.view_lights, audit=audit, rsm_views=list(rsm.views or ()),
        vpls_hand_made=vpls.hand_made, light_views=rsm.light_views,
        timings_ms=dict(timer.timings_ms), timing_methods=dict(timer.methods),
        stages_run=stages_run,
        warnings=Deferred(lambda: guards.frame_warnings(by_stage, s, audit)),
        display_scale=state.display_scale, camera=scene.camera,
        scene_bounds=(tuple(map(float, scene.bounds_min)),
                      tuple(map(float, scene.bounds_max))),
        fog=state.fog if s.fog else None)
