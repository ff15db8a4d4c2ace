"""The tolerances ``lpv-explorer diff`` holds a stage to, and the verdict of one stage.

Per value, as :func:`numpy.isclose` with ours as the reference:
``|theirs − ours| ≤ atol + rtol·|ours|`` for every component of every element (a cell's
colours × SH coefficients, a pixel's channels); an element fails when any of its
components does. Per stage: ``‖theirs − ours‖₂ / ‖ours‖₂ ≤ rel_l2``. ``max_relative`` is
the older per-element test (the norm of an element's error over the norm of ours there,
elements below :data:`explorer.exchange.diff.RELATIVE_FLOOR` of the stage's largest left
out), kept for ``--tolerance``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Tolerances:
    """What a stage must meet; a field left None is not tested. With only one of atol and
    rtol given the other is 0 (numpy's defaults are not applied behind the user's back)."""

    atol: float | None = None
    rtol: float | None = None
    rel_l2: float | None = None
    max_relative: float | None = None

    @property
    def per_value(self) -> bool:
        """Whether the isclose test applies (atol or rtol given)."""
        return self.atol is not None or self.rtol is not None

    @property
    def any(self) -> bool:
        """Whether anything is tested at all (else no stage has a verdict)."""
        return self.per_value or self.rel_l2 is not None or self.max_relative is not None

    def allowed(self, ours: np.ndarray) -> np.ndarray:
        """``atol + rtol·|ours|`` per value."""
        return (self.atol or 0.0) + (self.rtol or 0.0) * np.abs(ours)

    def as_dict(self) -> dict:
        return {"atol": self.atol, "rtol": self.rtol, "rel_l2": self.rel_l2,
                "tolerance": self.max_relative}


def outside(theirs: np.ndarray, ours: np.ndarray, tolerances: Tolerances) -> np.ndarray:
    """Per value: True where ``numpy.isclose(theirs, ours, rtol, atol)`` is False."""
    return ~np.isclose(theirs, ours, rtol=tolerances.rtol or 0.0, atol=tolerances.atol or 0.0,
                       equal_nan=False)


def closeness(theirs: np.ndarray, ours: np.ndarray, tolerances: Tolerances) -> np.ndarray:
    """Per value: ``|theirs − ours| / (atol + rtol·|ours|)`` (above 1 fails; inf where
    nothing is allowed and the values differ, 0 where they are equal)."""
    error = np.abs(theirs - ours)
    allowed = tolerances.allowed(ours)
    ratio = np.divide(error, allowed, out=np.zeros_like(error), where=allowed > 0)
    return np.where((allowed <= 0) & (error > 0), np.inf, ratio)


def stage_failures(tolerances: Tolerances, *, failing: int | None, element: str,
                   relative_l2: float | None, theirs_nonzero: bool,
                   max_relative: float | None) -> list[str]:
    """Why a compared stage fails ``tolerances``, one phrase per test it fails (empty:
    it passes)."""
    reasons = []
    if failing:
        plural = "" if failing == 1 else "s"
        reasons.append(f"{failing} {element}{plural} outside atol + rtol·|ours|")
    if tolerances.rel_l2 is not None:
        if relative_l2 is None and theirs_nonzero:
            reasons.append("rel. L2 infinite (ours all zero, theirs not)")
        elif relative_l2 is not None and relative_l2 > tolerances.rel_l2:
            reasons.append(f"rel. L2 {relative_l2:.3g} > {tolerances.rel_l2:g}")
    if (tolerances.max_relative is not None and max_relative is not None
            and max_relative > tolerances.max_relative):
        reasons.append(f"largest relative error {max_relative:.3g} > "
                       f"{tolerances.max_relative:g}")
    return reasons
