"""Stage-by-stage difference between an engine's arrays and this tool's (``lpv-explorer
diff``): for every array both hold, the largest error and the largest relative error per
element (a grid cell, a pixel, an RSM texel, a VPL) and where they are, and the relative
L2 error of the whole stage.

An element's error is the Euclidean norm of its difference over its components (colour
channels and SH coefficients for a cell, channels for a pixel); its relative error divides
by the norm of ours there. Where ours is nearly zero that ratio means nothing, so the
relative error is taken over the elements whose norm is at least :data:`RELATIVE_FLOOR`
of the stage's largest (the others still count in the largest error).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from explorer.exchange.stages import GRID_STEP

RELATIVE_FLOOR = 1e-6
"""Elements of ours below this fraction of the stage's largest element norm are left out of
the relative error per element (their relative error would be noise over zero)."""


@dataclass(frozen=True)
class StageDiff:
    """The comparison of one array."""

    stage: str
    element: str                 # "cell", "geometry cell", "pixel", "texel", "VPL", "value"
    elements: int
    shape: list[int]
    differing: int               # elements whose error is not 0
    max_error: float | None
    max_error_at: list[int] | None
    """Index of the element with the largest error: cell (x, y, z), pixel/texel (x, y)
    with y the row from the top, VPL (i,), or the array index of a value."""
    theirs_at_max: list[float] | None
    ours_at_max: list[float] | None
    max_relative: float | None
    max_relative_at: list[int] | None
    relative_l2: float | None
    """‖theirs − ours‖ / ‖ours‖ over the whole array; None when ours is all zero."""
    problem: str | None = None
    """Why it was not compared (different shapes, values that are not finite), else
    None."""

    def as_dict(self) -> dict:
        return asdict(self)


def element_kind(name: str, array: np.ndarray) -> str:
    """What one element of array ``name`` is (see :class:`StageDiff`)."""
    base = name.partition("_")[2] if name.startswith("cascade") and "_" in name else name
    if GRID_STEP.match(name) or base == "accumulated" or GRID_STEP.match(base):
        return "cell"
    if base == "geometry_volume":
        return "geometry cell"
    if name.startswith("vpl_") and array.ndim >= 1:
        return "VPL"
    if name.startswith("rsm_"):
        return "texel"
    if array.ndim >= 2 and not base.startswith("grid_"):
        return "pixel"
    return "value"


def _elements(kind: str, array: np.ndarray) -> tuple[np.ndarray, tuple[int, ...]]:
    """``(E, K)`` float64 rows, one per element, and the shape its flat index unravels in
    (for pixels (H, W): reported as (x, y))."""
    values = np.asarray(array, np.float64)
    if kind == "cell":                          # (3, N, N, N, C) -> (N³, 3·C)
        moved = np.moveaxis(values, 0, -2)      # (N, N, N, 3, C)
        return moved.reshape(-1, values.shape[0] * values.shape[-1]), values.shape[1:4]
    if kind == "geometry cell":                 # (M, M, M, 4)
        return values.reshape(-1, values.shape[-1]), values.shape[:3]
    if kind in ("pixel", "texel"):              # (H, W[, C])
        rows = values.reshape(values.shape[0] * values.shape[1], -1)
        return rows, values.shape[:2]
    if kind == "VPL":                           # (M[, K])
        return values.reshape(values.shape[0], -1), values.shape[:1]
    return values.reshape(-1, 1), values.shape or (1,)


def _where(kind: str, flat: int, shape: tuple[int, ...]) -> list[int]:
    index = [int(i) for i in np.unravel_index(flat, shape)]
    return index[::-1] if kind in ("pixel", "texel") else index   # (row, col) -> (x, y)


def stage_diff(name: str, theirs: np.ndarray, ours: np.ndarray) -> StageDiff:
    """The comparison of one array (module docstring)."""
    kind = element_kind(name, ours)
    if np.shape(theirs) != np.shape(ours):
        return _not_compared(name, kind, theirs, f"shape {tuple(np.shape(theirs))}, ours "
                                                 f"{tuple(np.shape(ours))}")
    a, shape = _elements(kind, theirs)
    b, _ = _elements(kind, ours)
    for side, rows in (("theirs", a), ("ours", b)):
        bad = ~np.all(np.isfinite(rows), axis=1)
        if np.any(bad):
            first, count = int(np.flatnonzero(bad)[0]), int(np.count_nonzero(bad))
            return _not_compared(name, kind, theirs,
                                 f"{side} not finite at {count} {kind}{'s' * (count != 1)}, "
                                 f"the first{_at(kind, _where(kind, first, shape))}")
    error = np.linalg.norm(a - b, axis=1)
    size = np.linalg.norm(b, axis=1)
    worst = int(np.argmax(error)) if error.size else 0
    max_error = float(error[worst]) if error.size else 0.0
    relative = relative_at = None
    counted = size >= RELATIVE_FLOOR * (float(size.max()) if size.size else 0.0)
    counted &= size > 0
    if np.any(counted):
        ratios = np.where(counted, error / np.where(counted, size, 1.0), -1.0)
        best = int(np.argmax(ratios))
        relative, relative_at = float(ratios[best]), _where(kind, best, shape)
    total = float(np.linalg.norm(b))
    return StageDiff(
        name, kind, int(error.size), list(np.shape(ours)), int(np.count_nonzero(error)),
        max_error, _where(kind, worst, shape) if error.size else None,
        a[worst].tolist() if error.size else None, b[worst].tolist() if error.size else None,
        relative, relative_at,
        float(np.linalg.norm(a - b)) / total if total > 0 else None)


def _not_compared(name: str, kind: str, theirs: np.ndarray, problem: str) -> StageDiff:
    return StageDiff(name, kind, 0, list(np.shape(theirs)), 0, None, None, None, None, None,
                     None, None, problem=problem)


def diff_arrays(theirs: dict[str, np.ndarray], ours: dict[str, np.ndarray]
                ) -> tuple[list[StageDiff], list[str], list[str]]:
    """Every array both hold compared (in our order), and the names only theirs and only
    ours hold."""
    diffs = [stage_diff(name, theirs[name], ours[name]) for name in ours if name in theirs]
    only_theirs = [name for name in theirs if name not in ours]
    only_ours = [name for name in ours if name not in theirs]
    return diffs, only_theirs, only_ours


def _at(kind: str, index: list[int] | None) -> str:
    if index is None:
        return ""
    return f" at {kind} ({', '.join(map(str, index))})"


def format_table(diffs: list[StageDiff]) -> str:
    """One line per stage: its elements, the largest error and where, the largest relative
    error per element and where, the relative L2 error of the stage."""
    lines = ["| stage | elements | differing | largest error | largest relative error | "
             "rel. L2 |", "|---|---:|---:|---|---|---:|"]
    for d in diffs:
        if d.problem is not None:
            lines.append(f"| {d.stage} | – | – | not compared: {d.problem} | – | – |")
            continue
        relative = "–" if d.max_relative is None else f"{d.max_relative:.3g}" + (
            _at(d.element, d.max_relative_at) if d.max_relative else "")
        l2 = "–" if d.relative_l2 is None else f"{d.relative_l2:.3g}"
        largest = f"{d.max_error:.3g}" + (_at(d.element, d.max_error_at) if d.max_error else "")
        plural = "" if d.elements == 1 else "s"
        lines.append(f"| {d.stage} | {d.elements} {d.element}{plural} | {d.differing} | "
                     f"{largest} | {relative} | {l2} |")
    return "\n".join(lines)
