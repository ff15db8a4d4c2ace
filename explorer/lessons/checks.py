"""Lesson checks: a step's claims about its own live numbers, written as data and verified
on the converged frame of that step (tests/lessons/test_lesson_checks.py runs every one in
CI, through :mod:`explorer.lessons.verify`).

A check is one ``[[steps.checks]]`` table::

    [[steps.checks]]
    claim = "the front-face clamp adds light"    # the prose's claim, in plain words
    value = "audit.clamp_gain"                   # a live quantity (live_values.py)
    op = ">"                                     # one of OPERATORS
    than = 0                                     # a number; [low, high] for "between";
                                                 # a number, word or true/false for "=="
    over = "audit.injected"        # optional: the check reads value / over
    after_try = 1                  # optional: read after pressing try-this 1 of the step
    over_before_try = true         # optional: read ``over`` on the step before the press
    side = "compare"               # optional: read on the compare preset's side

Nothing is evaluated as code: the operator is one of a fixed set, the operands are
quantity names the live-value table resolves and literal numbers. Every quantity a step
can quote is a property of the step, so a check may read it:

* ``figure.<id>.<readout>`` is read on the figure as the step declares it (its
  parameters, nothing dragged; a figure that plots frames plots the check's frame), not
  as a reader has dragged it; a figure shows both sides while its step compares, so a
  figure check reads the step's side (``side = "compare"`` is refused);
* ``error.*`` is the Error panel's measurement of the check's settings against the
  one-bounce reference, made at a small size (``explorer.lessons.verify.ERROR_SIZE``)
  and only for the frames whose checks name it; ``error.mitsuba_*`` and
  ``error.reference_mitsuba_*`` are refused (:data:`REFUSED_PREFIXES`): Mitsuba is an
  optional extra and its render takes minutes.

:func:`parse_check` validates a table, :func:`evaluate` reads the numbers (a ``read``
function :mod:`explorer.lessons.verify` makes from the step's frames) and says whether
the claim holds.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

OPERATORS: dict[str, Callable[[Any, Any], bool]] = {
    ">": operator.gt, ">=": operator.ge, "<": operator.lt, "<=": operator.le,
    "==": operator.eq,
    "between": lambda value, bounds: bounds[0] <= value <= bounds[1],
}
"""The comparisons a check may make (``between`` includes both bounds)."""
REFUSED_PREFIXES = ("error.mitsuba_", "error.reference_mitsuba_")
"""Quantities a check may not read: measured against Mitsuba, an optional extra whose
render takes minutes (module docstring)."""
SIDES = ("step", "compare")
KEYS = ("claim", "value", "op", "than", "over", "after_try", "over_before_try", "side")


class CheckError(ValueError):
    """A check table that cannot be used; ``field`` names the key."""

    def __init__(self, field: str, message: str) -> None:
        super().__init__(message)
        self.field = field


@dataclass(frozen=True)
class Check:
    """One claim of a step about its live numbers."""

    claim: str
    value: str
    op: str
    than: Any
    over: str | None = None
    after_try: int | None = None
    """1-based try-this whose press the value is read after (None: the step as it opens)."""
    over_before_try: bool = False
    side: str = "step"

    def describe(self) -> str:
        """The check in words and symbols, e.g. ``audit.clamp_gain > 0``."""
        left = self.value if self.over is None else f"{self.value} / {self.over}"
        where = []
        if self.after_try is not None:
            where.append(f"after try-this {self.after_try}")
        if self.over_before_try:
            where.append(f"{self.over} before it")
        if self.side != "step":
            where.append("on the compare side")
        suffix = f" ({', '.join(where)})" if where else ""
        return f"{left} {self.op} {self.than!r}{suffix}"


@dataclass(frozen=True)
class Outcome:
    check: Check
    measured: Any
    """The number (or word) the check compared; None when it could not be read."""
    holds: bool
    reason: str = ""

    def __str__(self) -> str:
        verdict = "holds" if self.holds else "FAILS"
        shown = f"{self.measured:.4g}" if isinstance(self.measured, float) else \
            repr(self.measured)
        extra = f" ({self.reason})" if self.reason else ""
        return f"{verdict}: {self.check.claim} [{self.check.describe()}; measured {shown}]" \
               f"{extra}"


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


# complexity: one branch per check kind and key, each its own one-line error
def parse_check(table: Any, lookup: Callable[[str], Any], try_count: int,  # noqa: C901
                has_compare: bool, prefix: str = "") -> Check:
    """The check ``table`` (a parsed TOML table) validated: ``lookup(name)`` resolves a
    quantity name (KeyError otherwise), ``try_count`` is the step's number of try-this
    entries, ``has_compare`` whether the step has a compare side. CheckError otherwise."""
    if not isinstance(table, Mapping):
        raise CheckError(prefix.rstrip("."), "must be a table {claim, value, op, than}")
    for key in table:
        if key not in KEYS:
            raise CheckError(prefix + str(key), f"unknown field; expected one of {list(KEYS)}")
    for key in ("claim", "value", "op", "than"):
        if key not in table:
            raise CheckError(prefix + key, "missing (required)")
    claim = table["claim"]
    if not isinstance(claim, str) or not claim.strip():
        raise CheckError(prefix + "claim", "must be the claim in words (a non-empty string)")
    names = {"value": table["value"]}
    if "over" in table:
        names["over"] = table["over"]
    for key, name in names.items():
        if not isinstance(name, str):
            raise CheckError(prefix + key, f"must be a live quantity name, got {name!r}")
        if name.startswith(REFUSED_PREFIXES):
            raise CheckError(prefix + key, f"{name}: a check cannot read numbers measured "
                                           f"against Mitsuba (an optional extra whose "
                                           f"render takes minutes)")
        try:
            lookup(name)
        except KeyError as exc:
            raise CheckError(prefix + key, str(exc.args[0] if exc.args else exc)) from None
    op = table["op"]
    if op not in OPERATORS:
        raise CheckError(prefix + "op", f"{op!r} is not one of {list(OPERATORS)}")
    than = table["than"]
    if op == "between":
        if (not isinstance(than, list) or len(than) != 2 or not all(map(_is_number, than))
                or not than[0] < than[1]):
            raise CheckError(prefix + "than", f"'between' needs [low, high] with low < high, "
                                              f"got {than!r}")
        than = (float(than[0]), float(than[1]))
    elif op == "==":
        if not (_is_number(than) or isinstance(than, (str, bool))):
            raise CheckError(prefix + "than", f"'==' compares with a number, a word or "
                                              f"true/false, got {than!r}")
    elif not _is_number(than) or not math.isfinite(than):
        raise CheckError(prefix + "than", f"{op!r} compares with a finite number, got "
                                          f"{than!r}")
    after_try = table.get("after_try")
    if after_try is not None and (not isinstance(after_try, int) or isinstance(after_try, bool)
                                  or not 1 <= after_try <= try_count):
        raise CheckError(prefix + "after_try", f"must name one of the step's {try_count} "
                                               f"try-this entries (1..{try_count}), got "
                                               f"{after_try!r}")
    before = table.get("over_before_try", False)
    if not isinstance(before, bool):
        raise CheckError(prefix + "over_before_try", f"must be true or false, got {before!r}")
    if before and (after_try is None or "over" not in table):
        raise CheckError(prefix + "over_before_try", "needs both 'over' and 'after_try'")
    side = table.get("side", "step")
    if side not in SIDES:
        raise CheckError(prefix + "side", f"{side!r} is not one of {list(SIDES)}")
    if side == "compare" and not has_compare:
        raise CheckError(prefix + "side", "the step has no compare preset")
    if side == "compare" and any(n.startswith("figure.") for n in names.values()):
        raise CheckError(prefix + "side", "a figure shows both sides of a comparison: read "
                                          "its b_* readouts on the step's side")
    return Check(claim=claim.strip(), value=table["value"], op=op, than=than,
                 over=table.get("over"), after_try=after_try, over_before_try=before,
                 side=side)


def needs(check: Check) -> tuple[str, ...]:
    """The quantity names the check reads."""
    return (check.value,) if check.over is None else (check.value, check.over)


def evaluate(check: Check, read: Callable[[str, bool], Any]) -> Outcome:
    """Whether ``check`` holds. ``read(name, after)`` gives the value of quantity ``name``
    on the check's frame (``after``: after its try-this; False: the step as it opens), or
    raises LookupError when it has none (the Outcome then fails with the reason)."""
    after = check.after_try is not None
    try:
        measured = read(check.value, after)
        if check.over is not None:
            bottom = read(check.over, after and not check.over_before_try)
            if not (_is_number(measured) and _is_number(bottom)):
                return Outcome(check, None, False, f"{check.value} / {check.over} of "
                                                   f"non-numbers {measured!r}, {bottom!r}")
            if bottom == 0:
                return Outcome(check, None, False, f"{check.over} is 0")
            measured = float(measured) / float(bottom)
    except LookupError as exc:
        return Outcome(check, None, False, f"no value: {exc}")
    if check.op != "==" and not _is_number(measured):
        return Outcome(check, measured, False, "not a number")
    if _is_number(measured) and not math.isfinite(measured):
        return Outcome(check, float(measured), False, "not finite")
    return Outcome(check, measured, bool(OPERATORS[check.op](measured, check.than)))
