"""The stages' cache keys, derived from the declared stage list and the settings schema.

A stage declares only its *upstream* stages (:data:`explorer.lpv.stage_list.STAGE_LIST`,
the one list of stages). The Settings fields it reads come from the settings schema
(:attr:`explorer.schema.Spec.stages` of every field, read through
:func:`explorer.schema.stages_reading`): the field declarations are the single
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
* timing, NaN checks and read-back, which each stage does
  (:mod:`explorer.lpv.stages`).

:func:`describe` prints the table.
"""

from __future__ import annotations

import operator
from functools import cache
from typing import Any

from explorer.lpv.corrections import CORRECTIONS, Corrections
from explorer.lpv.stage_list import (  # noqa: F401  (re-exported: the stage facts)
    DECLARATIONS,
    EXECUTION_ORDER,
    PASSES,
    STAGES,
    StageDecl,
)
from explorer.schema import stages_reading


def check_declarations() -> None:
    """A ValueError unless the execution order runs every declared stage once, after its
    upstream stages."""
    if sorted(EXECUTION_ORDER) != sorted(STAGES):
        raise ValueError(f"execution order {EXECUTION_ORDER} must run the declared "
                         f"stages {STAGES}")
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
    if stage not in DECLARATIONS:
        raise ValueError(f"unknown stage {stage!r}; stages are {STAGES}")
    names, read = _reader(type(settings), stage)
    values = read(settings)
    if Corrections in map(type, values):      # the switches: only those the stage reads
        values = tuple(_nested_inputs(value, stage) if isinstance(value, Corrections)
                       else value for value in values)
    return tuple(zip(names, values))


@cache
def _reader(settings_type: type, stage: str) -> tuple[tuple[str, ...], Any]:
    """The fields ``stage`` reads of ``settings_type`` and a function that reads them
    all at once (a tuple of their values)."""
    names = stages_reading(settings_type, stage)
    if len(names) == 1:
        return names, lambda settings: (getattr(settings, names[0]),)
    return names, (operator.attrgetter(*names) if names else lambda settings: ())


def _nested_inputs(value: Any, stage: str) -> Any:
    """The part of a field's value that ``stage`` reads. Of the corrections only the
    switches the registry says the stage's programs read (:attr:`Correction.stages`,
    derivations/correction_registry.py), so e.g. toggling a switch that only the propagation
    reads re-runs no injection, and the "original" preset (which leaves the geometry
    volume's switch corrected) re-runs no geometry volume."""
    if isinstance(value, Corrections):
        return tuple((name, getattr(value, name)) for name in _corrections_read_by(stage))
    return value


@cache
def _corrections_read_by(stage: str) -> tuple[str, ...]:
    """The correction switches ``stage``'s programs read (the registry's order)."""
    return tuple(entry.name for entry in CORRECTIONS if stage in entry.stages)


def stage_key(settings: Any, stage: str, upstream_keys: dict[str, Any],
              extra: Any = None) -> tuple:
    """The key a completed run of ``stage`` is remembered by (module docstring)."""
    decl = DECLARATIONS[stage]
    return (stage_inputs(settings, stage),
            tuple(upstream_keys[up] for up in decl.upstream_for(settings)), extra)


def remembered_stage_key(memo: dict[str, tuple], settings: Any, stage: str,
                         upstream_keys: dict[str, Any], extra: Any = None) -> tuple:
    """:func:`stage_key`, the key made last for ``stage`` when it was made of the same
    Settings object (frozen: the same values), the same upstream output keys and the same
    ``extra`` (all by identity): a frame re-run with unchanged settings reads no field
    again. ``memo`` (stage -> what the last key was made of, and the key) belongs to the
    caller."""
    last = memo.get(stage)
    same_settings = last is not None and last[0] is settings
    # the upstream stages a Settings object selects are the same for it every time
    names = last[4] if same_settings else tuple(DECLARATIONS[stage].upstream_for(settings))
    upstream = tuple(map(upstream_keys.__getitem__, names))
    if same_settings and last[2] is extra and all(map(operator.is_, last[1], upstream)):
        return last[3]
    key = (stage_inputs(settings, stage), upstream, extra)
    memo[stage] = (settings, upstream, extra, key, names)
    return key


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
