r"""The derivation results as the window and the lessons show them, without sympy.

``explorer/derived_table.py`` is generated from ``derivations/registry.py`` by
``python -m derivations.codegen`` (LaTeX typeset with the constants at codegen time; the
test suite fails when it is stale). This module looks results up in it, so showing a
formula never imports sympy or re-derives the registry.

Examples
--------
>>> from explorer.derived import get
>>> get("corrections.reprojection_pi.corrected").latex
'\\Phi_{\\mathrm{lobe}} = \\Phi_{f}'
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from derivations.names import unknown_name


def _results() -> dict[str, tuple[str, str, float | None]]:
    # Imported on first use, not with this module: the codegen must run even when the
    # table is missing.
    from explorer.derived_table import RESULTS

    return RESULTS


@dataclass(frozen=True)
class Derived:
    """One derivation result: ``latex`` (a formula keeps its left-hand side), its
    ``statement``, and ``value``, the number it is or a formula equals (None otherwise)."""

    name: str
    latex: str
    statement: str
    value: float | None

    @property
    def tooltip(self) -> str:
        """What the window shows on hover: the statement, in words (the result's dotted
        name is the code's)."""
        return self.statement


def names() -> list[str]:
    """Every result name, in registry order."""
    return list(_results())


def get(name: str) -> Derived:
    """The result called ``name``; ``KeyError`` names the closest matches otherwise."""
    results = _results()
    try:
        latex, statement, value = results[name]
    except KeyError:
        raise unknown_name(name, list(results)) from None
    return Derived(name, latex, statement, value)


_FIELD = re.compile(r"\{([\w.]+)(?::([^}]*))?\}")


def fill(text: str) -> str:
    """``text`` with each ``{<result name>:<format>}`` replaced by the result's value
    (e.g. ``{corrections.side_faces.step_flux_original:.3f}``); KeyError for an unknown
    name, ValueError for a result without a value."""
    def value(match: re.Match) -> str:
        found = get(match.group(1))
        if found.value is None:
            raise ValueError(f"{found.name} has no numeric value to put in {text!r}")
        return format(found.value, match.group(2) or "")

    return _FIELD.sub(value, text)
