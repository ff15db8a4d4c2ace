"""Marks: labelled points a lesson step places in its scene ("dark side", "leak",
"negative lobe"), drawn in the 3D view with an arrow to the point, and probes of the light
there.

A mark is one ``[[steps.marks]]`` table::

    [[steps.marks]]
    id = "dark"                       # quoted as {{mark.dark.irradiance}} and in checks
    label = "dark side"               # the text drawn in the view (optional: a mark
                                      # without a label measures but is not drawn)
    at = [0.33, 0.4, -0.6]            # the world point the arrow points at (metres)
    normal = [1, 0, 0]                # optional: the surface's normal there

A mark with a ``normal`` measures :data:`READOUTS` at its point: the indirect irradiance
the LPV's final gather computes there (docs/MODEL.md "Final gather", the numpy twin
``explorer.lpv.twin.light_grid.gather_cascades`` on the frame's accumulated grids), so a claim
such as "the dark side receives more than 1 % of the lit side's light" is a check of one
mark's number over another's (explorer/lessons/checks.py). The ``*over_reference``
readouts hold that irradiance against the project's one-bounce reference at the same
point (the frame's VPLs summed directly, with shadow rays: explorer/truth/reference.py
``point_reference_irradiance``), the error of the surface the mark is on.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

Vec3 = tuple[float, float, float]
READOUTS = {"irradiance": ("indirect irradiance the LPV gathers at the mark (sum of the "
                           "three channels)", "W/m²"),
            "red_share": ("red's share of the indirect irradiance at the mark (a third for "
                          "white light)", ""),
            "green_share": ("green's share of the indirect irradiance at the mark (a third "
                            "for white light)", ""),
            "blue_share": ("blue's share of the indirect irradiance at the mark (a third for "
                           "white light)", ""),
            "over_reference": ("indirect irradiance at the mark over the one-bounce "
                               "reference's there (the frame's VPLs summed with shadow rays; "
                               "channels summed; 1 is exact)", ""),
            "red_over_reference": ("the red channel's irradiance at the mark over the "
                                   "reference's red there", ""),
            "green_over_reference": ("the green channel's irradiance at the mark over the "
                                     "reference's green there", ""),
            "blue_over_reference": ("the blue channel's irradiance at the mark over the "
                                    "reference's blue there", "")}
"""What a mark with a normal measures: readout -> (doc, unit)."""
KEYS = ("id", "label", "at", "normal")
_ID = re.compile(r"^[a-z][a-z0-9_]*$")
MAX_LABEL = 40
"""Labels are drawn in the view: a few words."""


class MarkError(ValueError):
    def __init__(self, field: str, message: str) -> None:
        super().__init__(message)
        self.field = field


@dataclass(frozen=True)
class Mark:
    id: str
    label: str
    """Drawn in the view; "" for a mark that only measures."""
    at: Vec3
    normal: Vec3 | None = None
    """Unit normal (normalised when read), or None: the mark only labels its point."""


def _vector(value: Any, field: str, unit: bool) -> Vec3:
    if (not isinstance(value, list) or len(value) != 3
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                       and math.isfinite(v) for v in value)):
        raise MarkError(field, f"must be three finite numbers [x, y, z], got {value!r}")
    vector = tuple(float(v) for v in value)
    if unit:
        length = math.sqrt(sum(v * v for v in vector))
        if length == 0:
            raise MarkError(field, "must not be the zero vector")
        vector = tuple(v / length for v in vector)
    return vector  # type: ignore[return-value]


def parse_mark(table: Any, bounds: tuple[Vec3, Vec3] | None = None, prefix: str = "") -> Mark:
    """The mark ``table`` validated; ``bounds`` (the scene's box): the point must lie in
    it. MarkError names the field otherwise."""
    if not isinstance(table, Mapping):
        raise MarkError(prefix.rstrip("."), "must be a table {id, label, at}")
    for key in table:
        if key not in KEYS:
            raise MarkError(prefix + str(key), f"unknown field; expected one of {list(KEYS)}")
    for key in ("id", "at"):
        if key not in table:
            raise MarkError(prefix + key, "missing (required)")
    ident, label = table["id"], table.get("label", "")
    if "label" not in table and "normal" not in table:
        raise MarkError(prefix + "label", "a mark needs a label (to be drawn) or a normal "
                                          "(to measure), or both")
    if not isinstance(ident, str) or not _ID.match(ident):
        raise MarkError(prefix + "id", f"must be lower-case letters, digits and '_', "
                                       f"starting with a letter; got {ident!r}")
    if not isinstance(label, str) or ("label" in table and not label.strip()) \
            or len(label) > MAX_LABEL:
        raise MarkError(prefix + "label", f"must be a few words (1..{MAX_LABEL} characters), "
                                          f"got {label!r}")
    at = _vector(table["at"], prefix + "at", unit=False)
    if bounds is not None:
        lo, hi = bounds
        margin = 0.05
        if not all(lo[i] - margin <= at[i] <= hi[i] + margin for i in range(3)):
            raise MarkError(prefix + "at", f"{list(at)} lies outside the scene's box "
                                           f"{list(lo)}..{list(hi)}")
    normal = _vector(table["normal"], prefix + "normal", unit=True) if "normal" in table \
        else None
    return Mark(ident, label.strip(), at, normal)


def readout(mark: Mark, result: Any, name: str) -> float:
    """The :data:`READOUTS` entry ``name`` of ``mark`` on ``result``."""
    if name == "irradiance":
        return irradiance(mark, result)
    channels = irradiance_rgb(mark, result)
    if name.endswith("over_reference"):
        truth = reference_irradiance_rgb(mark, result)
        channel = CHANNELS.get(name.split("_")[0])
        lpv, want = ((channels.sum(), truth.sum()) if channel is None
                     else (channels[channel], truth[channel]))
        if not want > 0.0:
            raise ValueError(f"the reference has no light at mark {mark.id!r}")
        return float(lpv / want)
    total = float(channels.sum())
    if total <= 0.0:
        raise ValueError(f"no indirect light at mark {mark.id!r}")
    return float(channels[CHANNELS[name.split("_")[0]]] / total)


CHANNELS = {"red": 0, "green": 1, "blue": 2}


def reference_irradiance_rgb(mark: Mark, result: Any) -> np.ndarray:
    """(3,) the project's one-bounce reference irradiance (W/m²) at the mark: the frame's
    lit VPLs summed at the point with shadow rays against the scene's triangles, the 1/r²
    clamped at half a cell of the finest grid as the Error panel's reference is. Kept per
    frame (the window reads it every frame the step shows)."""
    key = (id(result), mark.at, mark.normal)
    kept = _REFERENCE_KEPT.get(key)
    if kept is not None and kept[0] is result:
        return kept[1]
    from explorer.truth.gbuffer import scene_for, scene_triangles
    from explorer.truth.reference import point_reference_irradiance
    from explorer.truth.render import lit_vpls

    if mark.normal is None:
        raise ValueError(f"mark {mark.id!r} has no normal: it measures nothing")
    triangles = scene_triangles(scene_for(result.settings))
    value = point_reference_irradiance(mark.at, mark.normal, lit_vpls(result.vpls),
                                       0.5 * result.grid_spec.cell_size, triangles,
                                       visibility=True)
    if len(_REFERENCE_KEPT) >= 16:
        _REFERENCE_KEPT.pop(next(iter(_REFERENCE_KEPT)))
    _REFERENCE_KEPT[key] = (result, value)
    return value


_REFERENCE_KEPT: dict[tuple, tuple[Any, np.ndarray]] = {}
"""The last few marks' reference irradiance, with the frame each belongs to."""


def irradiance(mark: Mark, result: Any) -> float:
    """The indirect irradiance (W/m², channels summed) the final gather computes at the
    mark on ``result`` (a FrameResult)."""
    return float(irradiance_rgb(mark, result).sum())


def irradiance_rgb(mark: Mark, result: Any) -> np.ndarray:
    """(3,) indirect irradiance (W/m²) per channel at the mark: the cascades' accumulated
    grids read by the numpy twin of the gather, damped as the frame's settings say."""
    from explorer.lpv.twin.light_grid import gather_cascades

    if mark.normal is None:
        raise ValueError(f"mark {mark.id!r} has no normal: it measures nothing")
    grids = [level.accumulated for level in result.cascades]
    specs = [level.spec for level in result.cascades]
    point = np.asarray([mark.at], np.float64)
    normal = np.asarray([mark.normal], np.float64)
    settings = result.settings
    damping = bool(getattr(settings, "gather_damping", False))
    return gather_cascades(grids, specs, point, normal, damping,
                           irradiance=settings.corrections.irradiance_gather)[0]
