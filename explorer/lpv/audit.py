"""Energy audit: where each formula gains or loses flux (docs/MODEL.md).

All numbers are flux in watts per colour channel, computed from intensity SH as
``Φ = 2√π·f0``. :class:`GridAudit` is what the propagation pass measures on the GPU (the propagation
dispatch writes per-cell records, ``shaders/audit_reduce.glsl`` sums them; only the totals
are read back);
:class:`EnergyAudit` adds what the pipeline measures around it. The per-cell records stay
on the GPU (the last step's, and their sums over the steps): :class:`CellAuditRecords`
(:mod:`explorer.lpv.passes.audit_reduce`) reads one cell's on demand (the window's picked
cell), a small read at its offset.

Balance of one step ``t`` (exact up to rounding, any switches):
``per_step[t] = propagated[t] + clamp_gain[t] − budget_withheld[t] − occluded[t] −
border_loss[t] + reflected[t]``, where
``propagated`` is the flux the unclamped, unoccluded faces carry (``per_step[t−1]`` for the
corrected formulas with side faces and exact constants: the 30 faces cover 4π) and
``budget_withheld`` what the flux budget keeps back (0 without it).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from explorer.lpv.deferred import Deferred, DeferredField

AUDIT_MODES = ("off", "flux", "full")
"""What a propagation measures, least first (each covers the ones before it):
``off`` the injected and accumulated flux only (the minimal kernel, ``PROPAGATE_AUDIT 0``);
``flux`` also the flux in flight after every step, reduced from each step's grid
(:meth:`AuditReducer.measure_flux`, still the minimal kernel); ``full`` also every other
term of the balance and the per-cell records (``PROPAGATE_AUDIT 1``, ~2.5× a step's cost
on llvmpipe)."""
TERMS_OF_FULL_AUDIT = ("border_loss", "clamp_gain", "occluded", "reflected", "blocked",
                       "budget_withheld")
""":class:`GridAudit` terms only the full audit measures (None in the other modes)."""


def audit_mode(value: str | bool) -> str:
    """The audit mode ``value`` names (:data:`AUDIT_MODES`); a bool is the older API:
    True the full audit, False none."""
    if isinstance(value, bool):
        return "full" if value else "off"
    if value not in AUDIT_MODES:
        raise ValueError(f"audit mode must be one of {', '.join(AUDIT_MODES)} (or a bool), "
                         f"got {value!r}")
    return value


def audit_covers(done: str | bool, asked: str | bool) -> bool:
    """Whether a propagation measured in mode ``done`` has what mode ``asked`` needs."""
    return AUDIT_MODES.index(audit_mode(done)) >= AUDIT_MODES.index(audit_mode(asked))


def strongest_audit(*modes: str | bool) -> str:
    """The mode that covers all of ``modes`` (``off`` for none)."""
    return max((audit_mode(m) for m in modes), key=AUDIT_MODES.index, default="off")


@dataclass
class GridAudit:
    """Flux bookkeeping of one injection + propagation (all float64 watts per channel).
    A term the propagation's audit mode (:data:`AUDIT_MODES`) did not measure is None."""

    injected: np.ndarray
    """(3,) flux of grid_0."""
    per_step: np.ndarray
    """(iterations+1, 3) flux of grid_t, the light in flight after t steps (NaN after
    step 0 in mode ``off``)."""
    border_loss: np.ndarray | None
    """(iterations, 3) flux sent out of the grid by step t+1 (full audit only)."""
    clamp_gain: np.ndarray | None
    """(iterations, 3) flux created by the clamp+ in step t+1: of the front faces, or
    under the flux budget of every face (full audit only)."""
    occluded: np.ndarray | None
    """(iterations, 3) flux removed by the geometry volume in step t+1 (full audit only)."""
    accumulated: np.ndarray
    """(3,) flux of acc_N = Σ grid_t."""
    reflected: np.ndarray | None = field(default_factory=lambda: np.zeros((0, 3)))
    """(iterations, 3) flux the geometry volume reflected back in step t+1 (``bounces`` 2,
    docs/MODEL.md "More bounces"); zeros otherwise (full audit only)."""
    blocked: np.ndarray | None = field(default_factory=lambda: np.zeros((0, 3)))
    """(iterations, 3) flux the geometry volume blocked in step t+1 that can bounce: per
    source cell and direction clamped at 0 (``bounces`` 2 only; zeros otherwise; full
    audit only). ``reflected <= blocked`` whenever every albedo is <= 1."""
    budget_withheld: np.ndarray | None = field(default_factory=lambda: np.zeros((0, 3)))
    """(iterations, 3) flux the flux budget kept back in step t+1: ``(1 − β)·S`` per
    source cell, what its clamped faces would send beyond the cell's own flux
    (docs/MODEL.md "Flux budget"); zeros without the budget (full audit only)."""
    mode: str = "full"
    """The audit mode that measured it (:data:`AUDIT_MODES`)."""

    @property
    def steps_measured(self) -> bool:
        """Whether :attr:`per_step` is measured after step 0 (modes ``flux`` and
        ``full``)."""
        return self.mode != "off"

    @property
    def terms_measured(self) -> bool:
        """Whether the terms of :data:`TERMS_OF_FULL_AUDIT` are measured (mode ``full``)."""
        return self.mode == "full"

    @property
    def iterations(self) -> int:
        return int(self.per_step.shape[0]) - 1


@dataclass
class EnergyAudit(GridAudit):
    """The grid audit plus the pipeline's own measurements."""

    # the pipeline's sums over read-back images, summed when first read (deferred.py)
    rsm: np.ndarray = DeferredField(lambda: np.zeros(3))  # type: ignore[assignment]
    """(3,) sum of the RSM texels' flux."""
    gathered: np.ndarray = DeferredField(lambda: np.zeros(3))  # type: ignore[assignment]
    """(3,) flux received by the visible surfaces in the final gather."""
    rsm_per_light: np.ndarray = DeferredField(  # type: ignore[assignment]
        lambda: np.zeros((0, 3)))
    """(L, 3) the RSM flux of each light that shines (``FrameResult.light_names`` order;
    a point light's six faces together); ``rsm`` is their sum."""

    @classmethod
    def from_grid_audit(cls, audit: GridAudit, rsm: np.ndarray | Callable[[], np.ndarray],
                        gathered: np.ndarray | Callable[[], np.ndarray],
                        rsm_per_light: np.ndarray | Callable[[], np.ndarray] | None = None
                        ) -> EnergyAudit:
        """``audit`` with the pipeline's measurements; each may be a function of no
        arguments, called when the field is first read."""
        def as_flux(value) -> np.ndarray:
            return np.asarray(value() if callable(value) else value, np.float64)

        def per_light() -> np.ndarray:
            if rsm_per_light is None:
                return as_flux(rsm)[None]
            return as_flux(rsm_per_light)

        return cls(**vars(audit), rsm=Deferred(lambda: as_flux(rsm)),
                   gathered=Deferred(lambda: as_flux(gathered)),
                   rsm_per_light=Deferred(per_light))


@dataclass(frozen=True)
class CellAudit:
    """One cell's audit record (``shaders/propagate.glsl``; each (3,) watts per channel),
    booked to the cell whose invocation computes it, as
    :func:`explorer.lpv.twin.light_grid.propagation_step_cells` books it."""

    received: np.ndarray
    """Flux the step(s) delivered into the cell (reflections included)."""
    border_loss: np.ndarray
    """Flux the cell sent out of the grid (border cells only)."""
    clamp_gain: np.ndarray
    """Flux the front-face clamp added on the faces the cell gathered through (and, for a
    border cell, on those it sent out of the grid)."""
    occluded: np.ndarray
    """Flux the geometry volume removed on those faces."""
    reflected: np.ndarray
    """Flux the geometry volume reflected back into the cell (``bounces`` 2)."""
    blocked: np.ndarray
    """Flux the cell sent that the volume blocked and that can bounce (``bounces`` 2)."""
    budget_withheld: np.ndarray
    """Flux the flux budget kept back on the faces the cell gathered through (and, for a
    border cell, on those it sent out of the grid)."""

    @classmethod
    def from_record(cls, values) -> CellAudit:
        """From the 21 numbers of a record (the order of ``shaders/audit_reduce.glsl``)."""
        values = np.asarray(values, np.float64).reshape(7, 3)
        return cls(*values)


def rgb_sums(image: np.ndarray) -> np.ndarray:
    """(3,) float64: the sums of an ``(..., C)`` image's first three channels (C >= 3),
    each added pixel after pixel in row order. The channels are summed as they lie (no
    copy of the rgb slice); each channel's sum is the same whatever the others."""
    channels = image.shape[-1]
    pixels = np.ascontiguousarray(image).reshape(-1, channels)
    return np.add.reduce(pixels, axis=0, dtype=np.float64)[:3]


def flux_per_light(flux: Sequence[np.ndarray], light_of_view: Sequence[int]) -> np.ndarray:
    """``(lights, 3)`` float64: the flux of every RSM view's flux image (``(H, W, 4)``),
    summed into its light's row (a point light's six views make one light)."""
    per_view = np.array([rgb_sums(f) for f in flux])
    per_light = np.zeros((max(light_of_view) + 1, 3))
    np.add.at(per_light, list(light_of_view), per_view)
    return per_light


def check_finite(array: np.ndarray, pass_name: str) -> np.ndarray:
    """``array`` unchanged if every value is finite; otherwise a FloatingPointError naming
    the pass, how many values are NaN or infinite, and where the first one is."""
    values = np.asarray(array)
    bad = ~np.isfinite(values)
    if bad.any():
        first = tuple(int(i) for i in np.argwhere(bad)[0])
        raise FloatingPointError(
            f"{pass_name} produced {int(np.isnan(values).sum())} NaN and "
            f"{int(np.isinf(values).sum())} infinite values (of {values.size}); "
            f"first at index {first} of shape {values.shape}")
    return array
