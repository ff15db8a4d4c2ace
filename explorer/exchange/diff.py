"""Stage-by-stage difference between an engine's arrays and this tool's (``lpv-explorer
diff``): for every array both hold, the largest error and the largest relative error per
element (a grid cell, a pixel, an RSM texel, a VPL) and where they are, and the relative
L2 error of the whole stage.

An element's error is the Euclidean norm of its difference over its components (colour
channels and SH coefficients for a cell, channels for a pixel); its relative error divides
by the norm of ours there. Where ours is nearly zero that ratio means nothing, so the
relative error is taken over the elements whose norm is at least :data:`RELATIVE_FLOOR`
of the stage's largest (the others still count in the largest error).

Given :class:`~explorer.exchange.tolerances.Tolerances`, each stage also gets a verdict
(numpy's isclose per value, the relative L2 of the stage) and the elements that miss them
by most, with their values on both sides.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

from explorer.exchange.stages import GRID_STEP, VIEW_PREFIX
from explorer.exchange.tolerances import Tolerances, closeness, outside, stage_failures

RELATIVE_FLOOR = 1e-6
"""Elements of ours below this fraction of the stage's largest element norm are left out of
the relative error per element (their relative error would be noise over zero)."""


@dataclass(frozen=True)
class WorstElement:
    """One element that misses the tolerances (or, with none given, differs) by much."""

    at: list[int]                # as StageDiff.max_error_at
    component: str               # its worst value: "[g, k=2]" of a cell, "[b]" of a pixel
    theirs: float                # that value on both sides
    ours: float
    error: float                 # |theirs − ours| there
    allowed: float | None        # atol + rtol·|ours| there; None without atol/rtol
    theirs_element: list[float]  # every value of the element (a cell: colour-major, then k)
    ours_element: list[float]


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
    failing: int | None = None
    """Elements with a value outside ``atol + rtol·|ours|``; None without atol/rtol."""
    passed: bool | None = None
    """The verdict against the tolerances; None when none was given."""
    failures: list[str] = field(default_factory=list)
    """Why it failed, one phrase per tolerance missed."""
    worst: list[WorstElement] = field(default_factory=list)
    """The elements missing the tolerances by most (the largest ratio of error to allowed
    error first), or with no atol/rtol the largest errors first."""

    def as_dict(self) -> dict:
        return asdict(self)


def element_kind(name: str, array: np.ndarray) -> str:
    """What one element of array ``name`` is (see :class:`StageDiff`)."""
    base = VIEW_PREFIX.sub("", name)         # cascade<k>_ and view<k>_ name the same kinds
    if GRID_STEP.match(name) or base == "accumulated" or GRID_STEP.match(base):
        return "cell"
    if base == "geometry_volume":
        return "geometry cell"
    if name.startswith("vpl_") and array.ndim >= 1:
        return "VPL"
    if base.startswith("rsm_"):
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


def _component(kind: str, i: int, components: int) -> str:
    """The name of value ``i`` of one element: colour and SH coefficient of a cell
    (values colour-major), the channel of a pixel or texel, the index of a VPL's."""
    if kind == "cell":
        per_colour = components // 3
        return f"[{'rgb'[i // per_colour]}, k={i % per_colour}]"
    if kind == "geometry cell":
        return f"[k={i}]"
    if kind in ("pixel", "texel") and components <= 4:
        return f"[{'rgba'[i]}]"
    return f"[{i}]" if components > 1 else ""


def _worst(kind: str, a: np.ndarray, b: np.ndarray, shape: tuple[int, ...],
           tolerances: Tolerances, count: int) -> list[WorstElement]:
    """The ``count`` elements that miss the tolerances by most (with atol/rtol: the
    largest error over allowed error, failing elements only), else the largest errors."""
    if count <= 0 or a.size == 0:
        return []
    if tolerances.per_value:
        ratio = closeness(a, b, tolerances)
        ratio[~outside(a, b, tolerances)] = 0.0           # isclose decides who fails
    else:
        ratio = np.abs(a - b)
    score = ratio.max(axis=1)
    candidates = np.flatnonzero(score > 0)
    order = candidates[np.argsort(-score[candidates], kind="stable")][:count]
    rows = []
    for e in order:
        i = int(np.argmax(ratio[e]))
        rows.append(WorstElement(
            _where(kind, int(e), shape), _component(kind, i, a.shape[1]), float(a[e, i]),
            float(b[e, i]), float(abs(a[e, i] - b[e, i])),
            float(tolerances.allowed(b[e, i])) if tolerances.per_value else None,
            a[e].tolist(), b[e].tolist()))
    return rows


def stage_diff(name: str, theirs: np.ndarray, ours: np.ndarray,
               tolerances: Tolerances | None = None, worst: int = 5) -> StageDiff:
    """The comparison of one array (module docstring), its verdict against
    ``tolerances`` and its ``worst`` elements."""
    tolerances = tolerances or Tolerances()
    kind = element_kind(name, ours)
    if np.shape(theirs) != np.shape(ours):
        return _not_compared(name, kind, theirs, f"shape {tuple(np.shape(theirs))}, ours "
                                                 f"{tuple(np.shape(ours))}", tolerances)
    a, shape = _elements(kind, theirs)
    b, _ = _elements(kind, ours)
    for side, rows in (("theirs", a), ("ours", b)):
        bad = ~np.all(np.isfinite(rows), axis=1)
        if np.any(bad):
            first, count = int(np.flatnonzero(bad)[0]), int(np.count_nonzero(bad))
            return _not_compared(name, kind, theirs,
                                 f"{side} not finite at {count} {kind}{'s' * (count != 1)}, "
                                 f"the first{_at(kind, _where(kind, first, shape))}",
                                 tolerances)
    error = np.linalg.norm(a - b, axis=1)
    size = np.linalg.norm(b, axis=1)
    top = int(np.argmax(error)) if error.size else 0
    max_error = float(error[top]) if error.size else 0.0
    relative = relative_at = None
    counted = size >= RELATIVE_FLOOR * (float(size.max()) if size.size else 0.0)
    counted &= size > 0
    if np.any(counted):
        ratios = np.where(counted, error / np.where(counted, size, 1.0), -1.0)
        best = int(np.argmax(ratios))
        relative, relative_at = float(ratios[best]), _where(kind, best, shape)
    total = float(np.linalg.norm(b))
    relative_l2 = float(np.linalg.norm(a - b)) / total if total > 0 else None
    failing = (int(np.count_nonzero(np.any(outside(a, b, tolerances), axis=1)))
               if tolerances.per_value else None)
    failures = stage_failures(tolerances, failing=failing, element=kind,
                              relative_l2=relative_l2, theirs_nonzero=bool(np.any(a)),
                              max_relative=relative)
    return StageDiff(
        name, kind, int(error.size), list(np.shape(ours)), int(np.count_nonzero(error)),
        max_error, _where(kind, top, shape) if error.size else None,
        a[top].tolist() if error.size else None, b[top].tolist() if error.size else None,
        relative, relative_at, relative_l2, failing=failing,
        passed=not failures if tolerances.any else None, failures=failures,
        worst=_worst(kind, a, b, shape, tolerances, worst))


def _not_compared(name: str, kind: str, theirs: np.ndarray, problem: str,
                  tolerances: Tolerances) -> StageDiff:
    return StageDiff(name, kind, 0, list(np.shape(theirs)), 0, None, None, None, None, None,
                     None, None, problem=problem,
                     passed=False if tolerances.any else None,
                     failures=[f"not compared: {problem}"] if tolerances.any else [])


def diff_arrays(theirs: dict[str, np.ndarray], ours: dict[str, np.ndarray],
                tolerances: Tolerances | None = None, worst: int = 5
                ) -> tuple[list[StageDiff], list[str], list[str]]:
    """Every array both hold compared (in our order), and the names only theirs and only
    ours hold."""
    diffs = [stage_diff(name, theirs[name], ours[name], tolerances, worst)
             for name in ours if name in theirs]
    only_theirs = [name for name in theirs if name not in ours]
    only_ours = [name for name in ours if name not in theirs]
    return diffs, only_theirs, only_ours


def _at(kind: str, index: list[int] | None) -> str:
    if index is None:
        return ""
    return f" at {kind} ({', '.join(map(str, index))})"


def format_table(diffs: list[StageDiff]) -> str:
    """One line per stage: its elements, the largest error and where, the largest relative
    error per element and where, the relative L2 error of the stage; with tolerances the
    elements outside atol + rtol·|ours| and the stage's verdict too."""
    judged = any(d.passed is not None for d in diffs)
    per_value = any(d.failing is not None for d in diffs)
    extra = (" outside | verdict |" if per_value else " verdict |") if judged else ""
    rule = ("---:|---|" if per_value else "---|") if judged else ""
    lines = ["| stage | elements | differing | largest error | largest relative error | "
             "rel. L2 |" + extra, "|---|---:|---:|---|---|---:|" + rule]
    for d in diffs:
        verdict = ""
        if judged:
            verdict = (f" {'–' if d.failing is None else d.failing} |" if per_value else "")
            verdict += " pass |" if d.passed else f" FAIL: {'; '.join(d.failures)} |"
        if d.problem is not None:
            lines.append(f"| {d.stage} | – | – | not compared: {d.problem} | – | – |"
                         + verdict)
            continue
        relative = "–" if d.max_relative is None else f"{d.max_relative:.3g}" + (
            _at(d.element, d.max_relative_at) if d.max_relative else "")
        l2 = "–" if d.relative_l2 is None else f"{d.relative_l2:.3g}"
        largest = f"{d.max_error:.3g}" + (_at(d.element, d.max_error_at) if d.max_error else "")
        plural = "" if d.elements == 1 else "s"
        lines.append(f"| {d.stage} | {d.elements} {d.element}{plural} | {d.differing} | "
                     f"{largest} | {relative} | {l2} |" + verdict)
    return "\n".join(lines)


def _values(values: list[float], kind: str) -> str:
    """An element's values, a cell's grouped per colour."""
    def row(part: list[float]) -> str:
        return "[" + ", ".join(f"{v:.9g}" for v in part) + "]"     # float32 exactly

    if kind == "cell" and len(values) % 3 == 0:
        n = len(values) // 3
        return " ".join(f"{c} {row(values[i * n:(i + 1) * n])}" for i, c in enumerate("rgb"))
    return row(values)


def format_worst(diffs: list[StageDiff]) -> str:
    """The worst elements of each stage that failed (with no tolerances: that differs),
    each with its worst value and every value of the element on both sides."""
    judged = any(d.passed is not None for d in diffs)
    blocks = []
    for d in diffs:
        if not d.worst or (judged and d.passed):
            continue
        how = ("|Δ| against atol + rtol·|ours|" if d.worst[0].allowed is not None
               else "largest |Δ| first")
        lines = [f"worst {d.element}s of {d.stage} ({how}):"]
        for w in d.worst:
            allowed = "" if w.allowed is None else f", allowed {w.allowed:.3g}"
            lines.append(f"  {d.element} ({', '.join(map(str, w.at))}) {w.component}: "
                         f"theirs {w.theirs:.9g}, ours {w.ours:.9g} (|Δ| {w.error:.3g}"
                         f"{allowed})")
            if len(w.theirs_element) > 1:
                lines.append(f"    theirs {_values(w.theirs_element, d.element)}")
                lines.append(f"    ours   {_values(w.ours_element, d.element)}")
        blocks.append("\n".join(lines))
    return "\n".join(blocks)
