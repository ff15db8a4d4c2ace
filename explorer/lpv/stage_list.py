"""THE list of the LPV frame's stages: every fact about a stage that another module needs,
declared once, in :data:`STAGE_LIST`.

Each :class:`StageDecl` names its upstream stages, the verb the window shows while it
runs and how it runs (a timed GPU pass, a by-value stage, one that reads correction
switches, one that runs as soon as it can); its work lives in the module of the same name
under :mod:`explorer.lpv.stages` (``frame_stages/gather.py`` for ``gather``). The
Settings fields a stage reads are declared on the fields (``setting(stages=...)``, the
settings schema). Everything else is derived from this list:

* :data:`STAGES`, the names in the list's (data-flow) order, which ``FrameResult``
  reports ``stages_run`` and warnings in;
* :data:`EXECUTION_ORDER`, the order a job runs them in: the list's, with every ``eager``
  stage moved to the first GPU pass after its upstream stages (the G-buffer runs first among the
  passes, so that a progressive picture can be gathered while the propagation runs);
* :data:`PASSES` (the timed GPU passes), :data:`VERBS` (``Job.progress.label``),
  :data:`CORRECTION_STAGES` (the stages whose programs may read a correction uniform,
  ``explorer.lpv.corrections.STAGES``) and :data:`PIXEL_STAGES` (the work per pixel a
  reduced size makes cheaper, the window's camera moves);
* the cache keys and invalidation (:mod:`explorer.lpv.cache_keys`) and the loop that runs
  them (:class:`explorer.lpv.job.Job` over :class:`explorer.lpv.pipeline.Pipeline`).

This module imports nothing of the project, so that the settings schema and the
corrections registry can check their stage names against it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class StageDecl:
    """One stage of the frame."""

    name: str
    upstream: tuple[str, ...]
    verb: str
    """What the window says while it runs (``"propagating 5/8"``)."""
    doc: str
    by_value: bool = False
    """Downstream stages see the stage's value, not its inputs (a cheap stage computed
    every time its inputs change, which counts as run only when its value changed)."""
    gpu: bool = True
    """A timed GPU pass (``scene`` and ``grid`` are CPU work)."""
    upstream_when: tuple[tuple[str, str], ...] = ()
    """``(stage, flag)``: ``stage`` is upstream only while the Settings attribute ``flag``
    (a field or a property) is true; otherwise its output key is left out of this
    stage's key."""
    eager: bool = False
    """Runs as soon as its upstream stages have run, not in the list's place."""
    corrections: bool = False
    """Its programs may read correction uniforms (``set_uniforms(reads=...)``)."""
    per_pixel: bool = False
    """Its work grows with the image's pixels (a reduced size while dragging makes it
    cheaper)."""

    def upstream_for(self, settings: Any) -> tuple[str, ...]:
        """The upstream stages whose output keys make this stage's key for ``settings``."""
        return self.upstream + tuple(stage for stage, flag in self.upstream_when
                                     if getattr(settings, flag))

    @property
    def all_upstream(self) -> tuple[str, ...]:
        """Every stage that may be upstream (the conditional ones included)."""
        return self.upstream + tuple(stage for stage, _ in self.upstream_when)


STAGE_LIST: tuple[StageDecl, ...] = (
    StageDecl("scene", (), "loading the scene", "loads the mesh (once per scene name) and "
              "poses its objects (writes the moved ones' corners)", gpu=False),
    StageDecl("grid", ("scene",), "placing the grids", "the GridSpec of each cascade: the "
              "grid enclosing the scene, or the cascades around the camera's focus point",
              by_value=True, gpu=False),
    StageDecl("rsm", ("scene",), "rendering the RSM", "a reflective shadow map per view of "
              "every light that shines (a point light has six), and their atlas"),
    StageDecl("downsample", ("rsm", "grid"), "downsampling", "the VPLs: the RSM texels, "
              "merged blocks of them, or hand-made VPLs"),
    StageDecl("inject", ("downsample", "grid"), "injecting", "VPLs -> SH light grid of "
              "every cascade", corrections=True),
    StageDecl("geometry", ("downsample", "grid"), "building the geometry volume", "the "
              "geometry volume of every cascade (occluders: the RSM texels, or hand-made "
              "VPLs; with camera occluders also the G-buffer's pixels no RSM view sees)",
              upstream_when=(("gbuffer", "uses_camera_occluders"),), corrections=True),
    StageDecl("propagate", ("inject", "geometry"), "propagating", "iterations steps in "
              "every cascade (+ the energy audit on request)", corrections=True),
    StageDecl("gbuffer", ("scene",), "rendering the G-buffer", "position, normal, albedo "
              "seen by the camera", eager=True, per_pixel=True),
    StageDecl("gather", ("gbuffer", "rsm", "propagate"), "gathering", "linear direct and "
              "LPV indirect radiance per pixel", corrections=True, per_pixel=True),
    StageDecl("fog", (), "marching the fog", "single scattering of the LPV and the direct "
              "light in a homogeneous medium, ray-marched per pixel, and its transmittance",
              upstream_when=(("gbuffer", "fog"), ("rsm", "fog"), ("propagate", "fog")),
              per_pixel=True),
    StageDecl("display", ("gather", "fog"), "displaying", "exposure, auto exposure, tone "
              "curve and encoding of the shown RGBA8 image, the fog composed over the "
              "surfaces (+ Pipeline.display_scale_override)", per_pixel=True),
)

DECLARATIONS: dict[str, StageDecl] = {decl.name: decl for decl in STAGE_LIST}
STAGES: tuple[str, ...] = tuple(DECLARATIONS)
"""The stage names in the list's order."""
PASSES: tuple[str, ...] = tuple(decl.name for decl in STAGE_LIST if decl.gpu)
"""The timed GPU passes (FrameResult.timings_ms names these)."""
VERBS: dict[str, str] = {decl.name: decl.verb for decl in STAGE_LIST}
CORRECTION_STAGES: tuple[str, ...] = tuple(decl.name for decl in STAGE_LIST
                                           if decl.corrections)
PIXEL_STAGES: tuple[str, ...] = tuple(decl.name for decl in STAGE_LIST if decl.per_pixel)
"""The stages whose work grows with the image's pixels."""


def execution_order(stage_list: tuple[StageDecl, ...] = STAGE_LIST) -> tuple[str, ...]:
    """The names of ``stage_list`` in the order a job runs them (module docstring); a
    ValueError when a stage is listed before one of its upstream stages or names a stage
    that is not in the list."""
    names = [decl.name for decl in stage_list]
    by_name = {decl.name: decl for decl in stage_list}
    if len(by_name) != len(names):
        raise ValueError(f"a stage is listed twice: {names}")
    order: list[str] = []
    for decl in stage_list:
        missing = [up for up in decl.all_upstream if up not in names]
        if missing:
            raise ValueError(f"stage {decl.name} names unknown upstream stage(s) {missing}")
        if decl.eager:
            if any(up not in order for up in decl.upstream):
                raise ValueError(f"eager stage {decl.name} is listed before its upstream "
                                 f"stages {decl.upstream}")
            place = max((order.index(up) + 1 for up in decl.upstream), default=0)
            while place < len(order) and not by_name[order[place]].gpu:
                place += 1         # first among the passes: the CPU stages cost nothing
            order.insert(place, decl.name)
        else:
            order.append(decl.name)
    for index, name in enumerate(order):
        late = [up for up in by_name[name].all_upstream if order.index(up) >= index]
        if late:
            raise ValueError(f"stage {name} runs before its upstream stage(s) {late}")
    return tuple(order)


EXECUTION_ORDER: tuple[str, ...] = execution_order()
