"""The stages of the LPV frame declared as data: what each depends on.

A stage declares only its *upstream* stages. The Settings fields it reads come from the
settings schema (:attr:`explorer.lpv.schema.Spec.stages` of every field, read through
:func:`explorer.lpv.schema.stages_reading`): the field declarations are the single
source. From the two the pipeline derives

* the *key* of a stage: the values of the fields it reads, the output keys of its
  upstream stages, and its extra inputs (hand-made VPLs for ``downsample``);
  :func:`stage_key`. A stage may also have *conditional* upstream stages
  (:attr:`StageDecl.upstream_when`): their output keys count only while a Settings flag
  says the stage uses them, e.g. the geometry volume reads the G-buffer only with camera
  occluders on, so that otherwise moving the camera does not rebuild it;
* its *output key*, what the stages downstream see: the key itself, or, for a stage
  declared ``by_value``, the value it computed (the cascade grid specs: moving the camera
  with one cascade changes the ``grid`` stage's inputs but not its specs, so nothing
  downstream runs again);
* invalidation: a stage runs when its key differs from the key of its last completed
  run, and invalidating a stage forgets its key (the stages downstream then see a new
  output key as soon as it runs again);
* timing, NaN checks and read-back, which the pipeline does per stage (see
  :mod:`explorer.lpv.pipeline`).

``EXECUTION_ORDER`` is the order a job runs them in: :data:`schema.STAGES` with the
G-buffer first among the passes, so that a progressive picture of the accumulation can
be gathered while the propagation is still running. :func:`describe` prints the table.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from explorer.lpv.corrections import CORRECTIONS, Corrections
from explorer.lpv.schema import STAGES, stages_reading


@dataclass(frozen=True)
class StageDecl:
    """One stage of the frame."""

    name: str
    upstream: tuple[str, ...]
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

    def upstream_for(self, settings: Any) -> tuple[str, ...]:
        """The upstream stages whose output keys make this stage's key for ``settings``."""
        return self.upstream + tuple(stage for stage, flag in self.upstream_when
                                     if getattr(settings, flag))

    @property
    def all_upstream(self) -> tuple[str, ...]:
        """Every stage that may be upstream (the conditional ones included)."""
        return self.upstream + tuple(stage for stage, _ in self.upstream_when)


DECLARATIONS: dict[str, StageDecl] = {decl.name: decl for decl in (
    StageDecl("scene", (), "loads the mesh (once per scene name) and poses its objects "
              "(writes the moved ones' corners)", gpu=False),
    StageDecl("grid", ("scene",), "the GridSpec of each cascade: the grid enclosing the "
              "scene, or the cascades around the camera's focus point", by_value=True,
              gpu=False),
    StageDecl("rsm", ("scene",), "a reflective shadow map per view of every light that "
              "shines (a point light has six), and their atlas"),
    StageDecl("downsample", ("rsm", "grid"), "the VPLs: the RSM texels, merged blocks of "
              "them, or hand-made VPLs"),
    StageDecl("inject", ("downsample", "grid"), "VPLs -> SH light grid of every cascade"),
    StageDecl("geometry", ("downsample", "grid"), "the geometry volume of every cascade "
              "(occluders: the RSM texels, or hand-made VPLs; with camera occluders also the "
              "G-buffer's pixels no RSM view sees)",
              upstream_when=(("gbuffer", "uses_camera_occluders"),)),
    StageDecl("propagate", ("inject", "geometry"), "iterations steps in every cascade "
              "(+ the energy audit on request)"),
    StageDecl("gbuffer", ("scene",), "position, normal, albedo seen by the camera"),
    StageDecl("gather", ("gbuffer", "rsm", "propagate"), "linear direct and LPV indirect "
              "radiance per pixel"),
    StageDecl("fog", (), "single scattering of the LPV and the direct light in a "
              "homogeneous medium, ray-marched per pixel, and its transmittance",
              upstream_when=(("gbuffer", "fog"), ("rsm", "fog"), ("propagate", "fog"))),
    StageDecl("display", ("gather", "fog"), "exposure, auto exposure, tone curve and "
              "encoding of the shown RGBA8 image, the fog composed over the surfaces "
              "(+ Pipeline.display_scale_override)"),
)}

EXECUTION_ORDER = ("scene", "grid", "gbuffer", "rsm", "downsample", "inject", "geometry",
                   "propagate", "gather", "fog", "display")
PASSES = tuple(name for name in STAGES if DECLARATIONS[name].gpu)
"""The timed GPU passes, in the schema's order (FrameResult.timings_ms names these)."""


def check_declarations() -> None:
    """A ValueError unless every schema stage is declared once and the execution order
    runs every stage after its upstream stages."""
    if set(DECLARATIONS) != set(STAGES) or sorted(EXECUTION_ORDER) != sorted(STAGES):
        raise ValueError(f"declared stages {sorted(DECLARATIONS)} and execution order "
                         f"{EXECUTION_ORDER} must both be the schema's {STAGES}")
    for index, name in enumerate(EXECUTION_ORDER):
        late = [up for up in DECLARATIONS[name].all_upstream
                if EXECUTION_ORDER.index(up) >= index]
        if late:
            raise ValueError(f"stage {name} runs before its upstream stage(s) {late}")


def downstream(stage: str, settings: Any = None) -> tuple[str, ...]:
    """``stage`` and every stage that depends on it, directly or not, in :data:`STAGES`
    order: with ``settings``, through the conditional upstream stages those settings
    use; without, through every one that may be used."""
    found = {stage}
    for name in EXECUTION_ORDER:
        decl = DECLARATIONS[name]
        ups = decl.all_upstream if settings is None else decl.upstream_for(settings)
        if any(up in found for up in ups):
            found.add(name)
    return tuple(name for name in STAGES if name in found)


def stage_inputs(settings: Any, stage: str) -> tuple:
    """``(field, value)`` of every Settings field ``stage`` reads (from the schema)."""
    return tuple((name, _nested_inputs(getattr(settings, name), stage))
                 for name in stages_reading(type(settings), stage))


def _nested_inputs(value: Any, stage: str) -> Any:
    """The part of a field's value that ``stage`` reads. Of the corrections only the
    switches the registry says the stage's programs read (:attr:`Correction.stages`,
    explorer/lpv/corrections.py), so e.g. toggling a switch that only the propagation
    reads re-runs no injection, and the "original" preset (which leaves the geometry
    volume's switch corrected) re-runs no geometry volume."""
    if isinstance(value, Corrections):
        return tuple((entry.name, getattr(value, entry.name)) for entry in CORRECTIONS
                     if stage in entry.stages)
    return value


def stage_key(settings: Any, stage: str, upstream_keys: dict[str, Any],
              extra: Any = None) -> tuple:
    """The key a completed run of ``stage`` is remembered by (module docstring)."""
    decl = DECLARATIONS[stage]
    return (stage_inputs(settings, stage),
            tuple(upstream_keys[up] for up in decl.upstream_for(settings)), extra)


def describe(settings_type: type | None = None) -> str:
    """The stage table: each stage, its upstream stages and the fields it reads."""
    if settings_type is None:
        from explorer.lpv.settings import Settings as settings_type
    lines = []
    for name in EXECUTION_ORDER:
        decl = DECLARATIONS[name]
        ups = list(decl.upstream) + [f"{stage} if {flag}" for stage, flag in decl.upstream_when]
        upstream = f"({', '.join(ups)}) " if ups else ""
        fields = ", ".join(stages_reading(settings_type, name)) or "-"
        lines.append(f"{name:<10} {upstream}{fields}: {decl.doc}")
    return "\n".join(lines)


check_declarations()
