"""Numeric guards: cheap checks of every run, turned into plain-text warnings
(``FrameResult.warnings``; ``Settings.debug_nan`` still raises instead, with the index
of the first bad value).

* Non-finite pass output: each pass's output is checked through what the pipeline
  has anyway (an array it reads back, tested elementwise, or a flux the audit reduction
  measures on the GPU), so no extra read-back is needed. The warning names the pass and
  the correction switches that are off.
* Growing flux: a propagation step maps flux Φ to ``π·k_R·k_I·k_P·(covered/4π)·Φ``
  (docs/MODEL.md "Propagation", flux per step), in place to ``(1 + that)·Φ``. The
  published injection alone (``injection_pi`` off with the other factors corrected)
  makes it ×π per step, 7·10⁹ after 16 steps, and in place it overflows float32 within
  64 steps. :func:`growth_explanation` says why wherever the growth is shown.
* Mesh scale: positions are float32 and the shaders square lengths, so a scene much
  smaller than :data:`MIN_SCENE_EXTENT` loses its light (squared distances fall below
  the shaders' guards) and one larger than :data:`MAX_SCENE_EXTENT` overflows (the
  G-buffer's pixel area ∝ size² is a length of a cross product, whose square ∝ size⁴
  passes 3.4·10³⁸; beyond ~10¹⁹ the RSM's flux, ∝ size², does too).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from explorer.lpv.audit import EnergyAudit, check_finite
from explorer.lpv.constants import (
    DX11_FRONT_SHARE,
    DX11_SIDE_SHARE,
    FRONT_FACE_SOLID_ANGLE,
    PI,
    PUBLISHED_FRONT_FACE_SOLID_ANGLE,
    PUBLISHED_PI,
    PUBLISHED_SIDE_FACE_SOLID_ANGLE,
    SIDE_FACE_SOLID_ANGLE,
)
from explorer.lpv.corrections import CORRECTIONS
from explorer.lpv.deferred import Deferred
from explorer.lpv.stage_list import STAGES

FLOAT32_MAX = float(np.finfo(np.float32).max)
MIN_SCENE_EXTENT = 1e-5
"""Below this edge of the scene's bounding box (world units) the light fades: the
gather's squared-distance guard (1e-12) takes over (measured: the Cornell box scaled to
2e-7 keeps 4 % of its light, at 2e-6 all of it)."""
MAX_SCENE_EXTENT = 1e9
"""Above it the G-buffer's pixel areas overflow (measured: the Cornell box scaled to
2e10 has infinite areas at its silhouettes, at 2e9 none; at 2e19 the RSM is NaN)."""


def switches_off(corrections) -> tuple[str, ...]:
    """The correction switches that are off (the published behaviour)."""
    return tuple(name for name in corrections.names() if not getattr(corrections, name))


def switch_text(corrections) -> str:
    off = switches_off(corrections)
    return f"switches off: {', '.join(off)}" if off else "all corrections on"


def nonfinite_text(array: np.ndarray) -> str:
    """How many values of ``array`` are NaN and how many infinite."""
    values = np.asarray(array)
    return (f"{int(np.isnan(values).sum())} NaN and {int(np.isinf(values).sum())} infinite "
            f"values (of {values.size})")


def all_finite(array: np.ndarray) -> bool:
    """True when every value of ``array`` is finite (an elementwise test: on the read-back
    images it takes half the time of the float64 sum it replaced)."""
    return bool(np.isfinite(array).all())


def pass_warning(pass_name: str, corrections, detail: str) -> str:
    """The warning of a pass whose output is not finite."""
    text = f"the {pass_name} pass produced {detail}; {switch_text(corrections)}"
    if growth_explanation(corrections) is not None:
        text += (f"; with these switches the flux grows ×{growth_per_step(corrections):.4g} "
                 f"per step")
    return text


def array_warning(pass_name: str, array: np.ndarray, corrections) -> str | None:
    """A warning if ``array`` (read back anyway) holds NaN or infinity."""
    if all_finite(array):
        return None
    return pass_warning(pass_name, corrections, nonfinite_text(array))


def arrays_warnings(pass_name: str, arrays: Iterable[np.ndarray], settings) -> list[str]:
    """The warning of the first of a pass's read-back ``arrays`` that holds NaN or
    infinity (one per pass), [] when all are finite; with ``settings.debug_nan`` a
    FloatingPointError naming the pass instead (:func:`explorer.lpv.audit.check_finite`)."""
    for array in arrays:
        if settings.debug_nan:
            check_finite(np.asarray(array), f"the {pass_name} pass")
        warning = array_warning(pass_name, array, settings.corrections)
        if warning is not None:
            return [warning]
    return []


StageWarnings = list[str] | Deferred
"""A stage's warnings (``FrameState.warnings``): a list, or a :class:`Deferred` that makes
it when the frame's warnings are read (:func:`arrays_warnings_later`)."""


def arrays_warnings_later(pass_name: str, arrays: Iterable[np.ndarray], settings
                          ) -> StageWarnings:
    """:func:`arrays_warnings`, checked when the frame's warnings are first read (most
    frames' never are); at once with ``settings.debug_nan``, whose error must stop the
    pass."""
    if settings.debug_nan:
        return arrays_warnings(pass_name, arrays, settings)
    arrays = list(arrays)
    return Deferred(lambda: arrays_warnings(pass_name, arrays, settings))


def joined(parts: Sequence[StageWarnings]) -> StageWarnings:
    """The warnings of ``parts`` in their order: a list, or a Deferred when one is."""
    if not any(type(part) is Deferred for part in parts):
        return [warning for part in parts for warning in part]  # type: ignore[union-attr]
    kept = list(parts)
    return Deferred(lambda: [warning for part in kept for warning in resolved(part)])


def resolved(warnings: StageWarnings) -> list[str]:
    """A stage's warnings as a list (a Deferred's computed now, once)."""
    return warnings.value() if type(warnings) is Deferred else warnings  # type: ignore


def flux_warning(pass_name: str, flux: np.ndarray, corrections) -> str | None:
    """A warning if a flux the GPU reduced (e.g. the injected or accumulated flux of a
    grid) is not finite: some texel of that grid is NaN or infinite."""
    flux = np.asarray(flux, np.float64)
    if np.all(np.isfinite(flux)):
        return None
    return pass_warning(pass_name, corrections, f"a total flux of {_vector(flux)} (a NaN or "
                                                "infinite value in its grid)")


def step_flux_factor(corrections) -> float:
    """What one ping-pong step multiplies the flux of isotropic light by, before
    clamping, occlusion and border losses: ``π·k_R·k_I·k_P`` times the share of the
    sphere the faces cover (docs/MODEL.md "Corrections", "Propagation")."""
    c = corrections
    pi = PI if c.exact_constants else PUBLISHED_PI
    k_i = 1.0 / pi if c.injection_pi else 1.0
    k_p = 1.0 if c.propagation_4pi else 1.0 / (4.0 * pi)
    k_r = 1.0 if c.reprojection_pi else 1.0 / pi
    front = FRONT_FACE_SOLID_ANGLE if c.exact_constants else PUBLISHED_FRONT_FACE_SOLID_ANGLE
    side = SIDE_FACE_SOLID_ANGLE if c.exact_constants else PUBLISHED_SIDE_FACE_SOLID_ANGLE
    if not c.model_face_weights:   # the DX11 weights replace k_R·k_I·k_P per face
        covered = 6.0 * (DX11_FRONT_SHARE * front
                         + (4.0 * DX11_SIDE_SHARE * side if c.side_faces else 0.0))
        return covered / (4.0 * PI)
    covered = 6.0 * (front + (4.0 * side if c.side_faces else 0.0))
    return pi * k_r * k_i * k_p * covered / (4.0 * PI)


def growth_per_step(corrections) -> float:
    """Factor of the light a step leaves (ping-pong: in flight; in place: accumulated)."""
    factor = step_flux_factor(corrections)
    return factor if corrections.ping_pong else 1.0 + factor


def growth_explanation(corrections) -> str | None:
    """Why the flux grows every step with these switches, or None when it does not (the
    text the audit plot, the warnings and the CLI show next to the growth)."""
    factor = step_flux_factor(corrections)
    growth = growth_per_step(corrections)
    if growth <= 1.0 + 1e-6:
        return None
    reasons = []
    if factor > 1.0 + 1e-6:
        # the switches that are off and change this factor when turned on
        off = [entry.title for entry in CORRECTIONS if not getattr(corrections, entry.name)
               and not math.isclose(step_flux_factor(dataclasses.replace(
                   corrections, **{entry.name: True})), factor)]
        reasons.append(f"π·k_R·k_I·k_P = {factor:.4g} instead of 1 (off: {', '.join(off)}): "
                       f"the published injection keeps the 1/π that only the corrected "
                       f"propagation and reprojection compensate")
    if not corrections.ping_pong:
        reasons.append(f"updated in place (ping-pong off) every step adds the propagated "
                       f"accumulated light to itself, "
                       f"×(1 + {factor:.4g})")
    return (f"the flux grows ×{growth:.4g} per step: {'; '.join(reasons)} (docs/MODEL.md "
            f"\"Propagation\", flux per step)")


def growth_warning(corrections, iterations: int, measured: float | None = None
                   ) -> str | None:
    """The growth explanation with its size after ``iterations`` steps, or None."""
    explanation = growth_explanation(corrections)
    if explanation is None or iterations < 1:
        return None
    total = growth_per_step(corrections) ** iterations
    if not math.isfinite(total) or total > FLOAT32_MAX:
        text = f"{explanation}; after {iterations} steps beyond float32's range (3.4e38)"
    else:
        text = f"{explanation}; ×{total:.3g} after {iterations} steps"
    if measured is not None and math.isfinite(measured):
        text += f" (measured: accumulated/injected flux = {measured:.3g})"
    return text


def frame_warnings(by_stage: Mapping[str, StageWarnings], settings,
                   audit: EnergyAudit) -> list[str]:
    """A frame's warnings: every stage's (``by_stage``), in :data:`STAGES` order, then
    the growth warning with the accumulated/injected flux ``audit`` measured."""
    warnings = [w for stage in STAGES for w in resolved(by_stage.get(stage, []))]
    if settings.iterations > 0:
        injected = float(np.sum(audit.injected))
        ratio = float(np.sum(audit.accumulated)) / injected if injected else None
        warnings += found(growth_warning(settings.corrections, settings.iterations, ratio))
    return warnings


def found(*warnings: str | None) -> list[str]:
    """The warnings that were found (None: a check that found nothing)."""
    return [warning for warning in warnings if warning is not None]


def scale_warning(bounds_min, bounds_max) -> str | None:
    """A warning with the scene's size when its scale makes the light vanish or
    overflow in float32 (module docstring)."""
    extent = float(np.max(np.asarray(bounds_max, np.float64) -
                          np.asarray(bounds_min, np.float64)))
    if MIN_SCENE_EXTENT <= extent <= MAX_SCENE_EXTENT:
        return None
    if extent < MIN_SCENE_EXTENT:
        effect = (f"smaller than {MIN_SCENE_EXTENT:g}: squared distances and areas fall "
                  f"below what float32 and the shaders resolve, so the light fades to black")
    else:
        effect = (f"larger than {MAX_SCENE_EXTENT:g}: squared lengths overflow float32 "
                  f"(infinite pixel areas, NaN or infinity in the RSM)")
    return (f"the scene is {extent:.3g} world units across, {effect}; rescale the mesh "
            f"(e.g. to metres)")


def _vector(values: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.4g}" for v in np.asarray(values).ravel()) + ")"
