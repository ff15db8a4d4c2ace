"""Legend labels that say what differs between two configurations.

A legend entry "A: custom" tells the reader nothing; "B: Propagation: no 1/(4π) per face
off" tells them what they are comparing, in the words of the Corrections panel and the
settings' labels (never a field name). :func:`side_labels` turns the Settings of A and B into such a
pair; :func:`describe` names one configuration alone (its preset, or the switches it
turns off relative to the corrected preset).
"""

from __future__ import annotations

import dataclasses

from explorer.lpv.settings import PRESETS, Corrections, Settings, preset_name

IGNORED_FIELDS = ("width", "height", "exposure", "debug_nan", "camera", "light")
"""Fields that do not change what a plot of flux shows (B follows A's view and light;
auto-exposure sets each side's exposure on its own)."""
MAX_NAMED = 2
"""Differences listed by name before a label falls back to preset names."""


def _switch(value: bool) -> str:
    return "on" if value else "off"


def _value(value) -> str:
    return str(value).lower() if isinstance(value, bool) else str(value)


def words(name: str) -> str:
    """A switch's or a setting's name as the panels write it: the correction's title,
    the setting's label, else the name with spaces."""
    from explorer.lpv.corrections import CORRECTIONS
    from explorer.schema import specs

    for entry in CORRECTIONS:
        if entry.name == name:
            return entry.title
    spec = specs(Settings).get(name)
    return (getattr(spec, "label", "") or name.replace("_", " "))


def differences(a: Settings, b: Settings) -> list[tuple[str, str, str]]:
    """(name, A's value, B's value) of every correction switch and setting that differs,
    switches first, in declaration order; fields in :data:`IGNORED_FIELDS` are skipped."""
    rows = [(name, _switch(getattr(a.corrections, name)), _switch(getattr(b.corrections, name)))
            for name in Corrections.names()
            if getattr(a.corrections, name) != getattr(b.corrections, name)]
    for field in dataclasses.fields(Settings):
        if field.name in IGNORED_FIELDS + ("corrections",):
            continue
        va, vb = getattr(a, field.name), getattr(b, field.name)
        if va != vb:
            rows.append((field.name, _value(va), _value(vb)))
    return rows


def describe_corrections(corrections: Corrections) -> str:
    """"corrected preset", "original preset", or the switches that differ from the
    corrected preset ("side_faces off, ping_pong off")."""
    name = preset_name(corrections)
    if name != "custom":
        return f"{name} preset"
    off = [f"{words(n)} {_switch(getattr(corrections, n))}" for n in Corrections.names()
           if getattr(corrections, n) != getattr(PRESETS["corrected"], n)]
    return _join(off)


def describe(settings: Settings) -> str:
    """One configuration in words, for a legend with only A."""
    return describe_corrections(settings.corrections)


def side_labels(a: Settings, b: Settings) -> tuple[str, str]:
    """Legend labels of A and B naming what differs, e.g.
    ``("A: propagation_4pi on", "B: propagation_4pi off")``; with many differences the
    preset names (``"A: corrected preset"``, ``"B: original preset"``) plus any setting
    that differs besides the corrections."""
    rows = differences(a, b)
    if not rows:
        return f"A: {describe(a)}", "B: same as A"
    if len(rows) <= MAX_NAMED:
        return ("A: " + _join(f"{words(n)} {va}" for n, va, _ in rows),
                "B: " + _join(f"{words(n)} {vb}" for n, _, vb in rows))
    switches = set(Corrections.names())
    others = [row for row in rows if row[0] not in switches]
    labels = []
    for side, settings, column in (("A", a, 1), ("B", b, 2)):
        parts = []
        if len(others) < len(rows):        # the corrections differ too
            parts.append(describe_corrections(settings.corrections))
        parts += [f"{words(row[0])} {row[column]}" for row in others]
        labels.append(f"{side}: " + _join(parts))
    return labels[0], labels[1]


def _join(parts, most: int = 3) -> str:
    parts = list(parts)
    if len(parts) > most:
        return ", ".join(parts[:most]) + f" (+{len(parts) - most} more)"
    return ", ".join(parts)
