r"""The course's notation: one symbol per quantity, in lesson prose, math and captions alike.

:data:`QUANTITIES` lists the quantities the lessons name, the one notation each is written
with (the spelling the derivations typeset, derivations/symbols.py), the words that name
it in prose, and the spellings a slip produces. :func:`notation_problems` checks one
learner text against it (tests/lessons/test_notation.py runs it over every lesson).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from explorer.lessons.words import MATH, PLACEHOLDER


@dataclass(frozen=True)
class Quantity:
    """One quantity of the course and how it is written."""

    name: str
    notation: str
    """Its symbol in TeX, as written in a lesson's math (compared after :func:`normal`)."""
    words: tuple[str, ...]
    """Phrases naming it in prose: "<phrase> $X$" must write X as :attr:`notation`."""
    slips: tuple[str, ...] = ()
    """Regexes of other spellings, matched against normalised math: each one is a slip."""
    prose_slips: tuple[str, ...] = ()
    """Regexes of other names or plain-text spellings of it in prose (outside math)."""


QUANTITIES: tuple[Quantity, ...] = (
    Quantity("cell size", "h", ("cell size", "cell width", "cell edge", "cell spacing"),
             slips=(r"\\Deltax(?![a-z])",)),
    Quantity("diffuse albedo", r"c_{\mathrm{diff}}",
             ("albedo", "diffuse reflectance", "reflectance"),
             slips=(r"c_\{diff\}", r"(?<![A-Za-z\\])a(?:\\,)?E", r"(?<![A-Za-z\\_{])c\\,E",
                    r"\\frac{c\\,")),
    Quantity("solid angle", r"\Delta\omega", ("solid angle", "solid angles"),
             slips=(r"\\rho",)),
    Quantity("flux", r"\Phi", ("flux", "light's flux"),
             slips=(r"\\Phi_\{l\}",), prose_slips=(r"Φ_l\b",)),
    Quantity("irradiance", "E", ("irradiance",)),
    Quantity("intensity", "I", ("intensity", "peak intensity")),
    Quantity("radiance", "L", ("radiance",)),
    Quantity("SH coefficient", "c", ("coefficient", "sh coefficient"),
             slips=(r"c_\{00\}", r"c_\{1,-1\}", r"Y_\{00\}", r"Y_\{0\}\^")),
    Quantity("face names", "", (),
             prose_slips=(r"(?i)\b(?:lateral|frontal|forward) faces?\b",)),
)
"""The course's quantities and their one notation each."""

_SYMBOL = re.compile(r"^((?:\\[A-Za-z]+)+|[A-Za-z])(_(?:{[^}]*}|\\[A-Za-z]+|[A-Za-z0-9]))?")
_NAMED = re.compile(r"([A-Za-z' ]+?) \$([^$]+)\$")


def normal(tex: str) -> str:
    r"""``tex`` spelled one way: no spaces, ``\text`` as ``\mathrm``, a one-character
    subscript without braces kept in braces (``h_f`` and ``h_{f}`` read the same)."""
    tex = re.sub(r"\s+", "", tex).replace(r"\text{", r"\mathrm{")
    tex = re.sub(r"_(\\[A-Za-z]+\{[^}]*\})", r"_{\1}", tex)
    return re.sub(r"_([A-Za-z0-9])", r"_{\1}", tex)


def _bare_symbol(math: str) -> str | None:
    """The symbol ``math`` names when it is one symbol or ``symbol = ...`` (else None)."""
    left = normal(math).split("=")[0]
    found = _SYMBOL.match(left)
    return left if found and found.group(0) == left else None


def _fits(symbol: str, quantity: Quantity) -> bool:
    """Whether ``symbol`` writes ``quantity``: its notation, or that with a subscript."""
    notation = normal(quantity.notation)
    return symbol == notation or symbol.startswith(notation + "_") or (
        "_" in notation and symbol.startswith(notation))


def notation_problems(text: str) -> list[str]:
    """Where ``text`` writes a quantity other than by its one notation (empty: nowhere)."""
    text = PLACEHOLDER.sub(" ", text or "")
    problems = []
    for quantity in QUANTITIES:
        for math in MATH.findall(text):
            body = normal(math.strip("$"))
            for slip in quantity.slips:
                if re.search(slip, body):
                    problems.append(f"{quantity.name} written {math!r}, not "
                                    f"${quantity.notation}$")
        prose = MATH.sub(" ", text)
        for slip in quantity.prose_slips:
            found = re.search(slip, prose)
            if found:
                problems.append(f"{quantity.name} written {found[0]!r} in prose, not "
                                f"{quantity.notation or 'front/side'}")
    for found in _NAMED.finditer(text):
        phrase, symbol = found.group(1).lower().strip(), _bare_symbol(found.group(2))
        if symbol is None:
            continue
        for quantity in QUANTITIES:
            named = any(phrase == w or phrase.endswith(" " + w) for w in quantity.words)
            if named and not _fits(symbol, quantity):
                problems.append(f"{quantity.name} named {phrase!r} written ${found.group(2)}$,"
                                f" not ${quantity.notation}$")
    return problems
