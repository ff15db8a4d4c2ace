"""Energy audit: where each formula gains or loses flux (docs/MODEL.md).

All numbers are flux in watts per colour channel, computed from intensity SH as
``Φ = 2√π·f0``. :class:`GridAudit` is what the propagation pass measures on the GPU (with a
reduction compute shader, ``shaders/audit_reduce.glsl``, reading back only the sums);
:class:`EnergyAudit` adds what the pipeline measures around it.

Balance of one step ``t`` (exact up to rounding, any switches):
``per_step[t] = propagated[t] + clamp_gain[t] − occluded[t] − border_loss[t]``, where
``propagated`` is the flux the unclamped, unoccluded faces carry (``per_step[t−1]`` for the
corrected formulas with side faces and exact constants: the 30 faces cover 4π).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.lpv.grid import GridSpec
from explorer.lpv.settings import Corrections
from explorer.lpv.textures import LpvGrid, dispatch_size

if TYPE_CHECKING:
    from explorer.lpv.geometry import GeometryVolume

AUDIT_VALUES = 12
"""Numbers per audit slot: flux, border loss, clamp gain, occluded (3 channels each)."""


@dataclass
class GridAudit:
    """Flux bookkeeping of one injection + propagation (all float64 watts per channel)."""

    injected: np.ndarray
    """(3,) flux of grid_0."""
    per_step: np.ndarray
    """(iterations+1, 3) flux of grid_t, the light in flight after t steps."""
    border_loss: np.ndarray
    """(iterations, 3) flux sent out of the grid by step t+1."""
    clamp_gain: np.ndarray
    """(iterations, 3) flux created by the front-face clamp in step t+1."""
    occluded: np.ndarray
    """(iterations, 3) flux removed by the geometry volume in step t+1."""
    accumulated: np.ndarray
    """(3,) flux of acc_N = Σ grid_t."""

    @property
    def iterations(self) -> int:
        return int(self.border_loss.shape[0])

    def as_dict(self) -> dict[str, list]:
        """Plain lists, for JSON output and plots."""
        return {name: np.asarray(value).tolist() for name, value in vars(self).items()}


@dataclass
class EnergyAudit(GridAudit):
    """The grid audit plus the pipeline's own measurements."""

    rsm: np.ndarray = field(default_factory=lambda: np.zeros(3))
    """(3,) sum of the RSM texels' flux."""
    gathered: np.ndarray = field(default_factory=lambda: np.zeros(3))
    """(3,) flux received by the visible surfaces in the final gather."""

    @classmethod
    def from_grid_audit(cls, audit: GridAudit, rsm: np.ndarray,
                        gathered: np.ndarray) -> "EnergyAudit":
        return cls(**vars(audit), rsm=np.asarray(rsm, np.float64),
                   gathered=np.asarray(gathered, np.float64))


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


class AuditReducer:
    """Runs ``shaders/audit_reduce.glsl``: per-cell audit terms, summed per workgroup, then
    summed into one slot of 12 floats; :meth:`read` fetches all slots at once.

    Sampler units while it runs: 0..2 "before" (the source grid of a step), 3..5 "after"
    (the grid whose flux is counted), 6 the geometry volume.
    """

    GEOMETRY_UNIT = 6

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._partials: moderngl.Buffer | None = None
        self._results: moderngl.Buffer | None = None
        self._slots = 0

    def begin(self, resolution: int, slots: int) -> None:
        """Prepare ``slots`` zeroed result slots for a ``resolution``³ grid."""
        groups = dispatch_size(resolution)
        partial_bytes = int(np.prod(groups)) * AUDIT_VALUES * 4
        if self._partials is None or self._partials.size < partial_bytes:
            if self._partials is not None:
                self._partials.release()
            self._partials = self.ctx.buffer(reserve=partial_bytes)
        result_bytes = max(slots, 1) * AUDIT_VALUES * 4
        if self._results is None or self._results.size < result_bytes:
            if self._results is not None:
                self._results.release()
            self._results = self.ctx.buffer(reserve=result_bytes)
        self._results.clear()
        self._slots = slots

    def measure(self, slot: int, spec: GridSpec, corrections: Corrections, after: LpvGrid,
                before: LpvGrid | None = None, geometry: GeometryVolume | None = None,
                after_minus_before: bool = False) -> None:
        """Fill ``slot`` with the flux of ``after`` (minus ``before`` when asked) and, when
        ``before`` is given, the face terms of one propagation step from ``before``."""
        if not 0 <= slot < self._slots:
            raise IndexError(f"audit slot {slot} outside 0..{self._slots - 1}")
        (before or after).use_as_textures(0)
        after.use_as_textures(3)
        if geometry is not None:
            geometry.texture.use(self.GEOMETRY_UNIT)
        self._partials.bind_to_storage_buffer(2)
        self._results.bind_to_storage_buffer(3)
        cells = self.programs.get("audit_reduce.glsl", {"AUDIT_STAGE": 0})
        set_uniforms(cells, {
            **spec.uniforms(), **corrections.as_uniforms(),
            "u_before_r": 0, "u_before_g": 1, "u_before_b": 2,
            "u_after_r": 3, "u_after_g": 4, "u_after_b": 5,
            "u_geometry": self.GEOMETRY_UNIT, "u_use_geometry": geometry is not None,
            "u_face_terms": before is not None, "u_after_minus_before": after_minus_before,
        })
        groups = dispatch_size(spec.resolution)
        cells.run(*groups)
        self.ctx.memory_barrier()
        total = self.programs.get("audit_reduce.glsl", {"AUDIT_STAGE": 1})
        set_uniforms(total, {"u_partial_count": int(np.prod(groups)), "u_result_slot": slot})
        total.run(1)
        self.ctx.memory_barrier()

    def read(self) -> np.ndarray:
        """(slots, 12) float64: flux, border loss, clamp gain, occluded (3 channels each)."""
        data = np.frombuffer(self._results.read(size=self._slots * AUDIT_VALUES * 4),
                             dtype=np.float32)
        return data.reshape(self._slots, AUDIT_VALUES).astype(np.float64)

    def release(self) -> None:
        for buffer in (self._partials, self._results):
            if buffer is not None:
                buffer.release()
        self._partials = self._results = None
