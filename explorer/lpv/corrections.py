"""The correction switches as the LPV reads them: the :class:`Corrections` dataclass (its
fields come from the registry, :mod:`derivations.correction_registry`, written out by the
code generator into :mod:`explorer.lpv.correction_switches`), the presets, and which
uniforms each stage's programs must read (:func:`uniforms_read_by`).

:data:`STAGES`, the stages whose programs may read a switch, comes from the declared
stage list (:data:`explorer.lpv.stage_list.CORRECTION_STAGES`); every registry entry's
stages are checked against it here. This module imports nothing heavy: the window reads
it at start.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from derivations.correction_registry import BY_NAME, CORRECTIONS, Correction
from explorer.lpv.correction_switches import CorrectionSwitches
from explorer.lpv.stage_list import CORRECTION_STAGES as STAGES

__all__ = ["BY_NAME", "CORRECTIONS", "Correction", "Corrections", "PRESETS", "STAGES",
           "preset", "uniforms_read_by"]


def _check_registry() -> None:
    for entry in CORRECTIONS:
        if not entry.stages or not set(entry.stages) <= set(STAGES):
            raise ValueError(f"correction {entry.name}: stages {entry.stages} must be a "
                             f"non-empty subset of {STAGES}")
    written = tuple(f.name for f in fields(CorrectionSwitches))
    if written != tuple(entry.name for entry in CORRECTIONS):
        raise ValueError(f"explorer/lpv/correction_switches.py holds {written}, not the "
                         "registry's switches: run `python -m derivations.codegen`")


_check_registry()


def uniforms_read_by(stage: str) -> tuple[str, ...]:
    """Uniforms of the switches a ``stage`` program must read (registry order); made once
    per stage (the registry is fixed at import; the passes ask every frame)."""
    made = _READ_BY.get(stage)
    if made is None:
        if stage not in STAGES:
            raise ValueError(f"unknown stage {stage!r}; choose one of {STAGES}")
        made = _READ_BY[stage] = tuple(entry.uniform for entry in CORRECTIONS
                                       if stage in entry.stages)
    return made


_READ_BY: dict[str, tuple[str, ...]] = {}


@dataclass(frozen=True)
class Corrections(CorrectionSwitches):
    """Named switches, one per published formula or implementation detail (fields: the
    entries of CORRECTIONS, in order; each True = corrected, the default)."""

    @classmethod
    def names(cls) -> tuple[str, ...]:
        # Made once per class: the frame asks for them many times (fields() walks the
        # dataclass each call).
        names = _FIELD_NAMES.get(cls)
        if names is None:
            names = _FIELD_NAMES[cls] = tuple(f.name for f in fields(cls))
        return names

    def as_uniforms(self) -> dict[str, int]:
        """Uniform values for the shaders: ``u_<field>`` = 0 or 1 (a dict of the caller's
        own; made once per switches, which are frozen)."""
        made = _UNIFORMS.get(self)
        if made is None:
            made = _UNIFORMS[self] = {BY_NAME[name].uniform: int(getattr(self, name))
                                      for name in self.names()}
        return dict(made)


_FIELD_NAMES: dict[type, tuple[str, ...]] = {}
_UNIFORMS: dict[Corrections, dict[str, int]] = {}
"""Each set of switches' uniforms (at most 2¹⁰ sets: one bool per registry entry)."""


PRESETS: dict[str, Corrections] = {
    "original": Corrections(**{entry.name: not entry.published for entry in CORRECTIONS}),
    "corrected": Corrections(),
}
"""Published first, then corrected: the order menus, sweeps and tables list them in."""


def preset(name: str) -> Corrections:
    """The named preset; raises ``KeyError`` listing the valid names."""
    try:
        return PRESETS[name]
    except KeyError:
        raise KeyError(f"unknown preset {name!r}; choose one of {sorted(PRESETS)}") from None
