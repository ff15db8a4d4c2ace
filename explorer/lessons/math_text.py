"""Inline math as plain text: the ``$...$`` of a lesson's words turned into readable
Unicode (Φ, π, <n, ω>, √3, x², ...), using only glyphs the window's font has, for where no
typeset formula can be shown (``lpv-explorer lessons`` prints a step this way)."""

from __future__ import annotations

import re

_LATEX_SYMBOLS = {
    r"\Phi": "Φ", r"\phi": "φ", r"\pi": "π", r"\omega": "ω", r"\Delta": "Δ", r"\theta": "θ",
    r"\rho": "ρ", r"\langle": "<", r"\rangle": ">", r"\lfloor": "floor[", r"\rfloor": "]",
    r"\cdot": "·", r"\times": "×", r"\approx": "≈", r"\int": "∫", r"\sum": "Σ",
    r"\dots": "…", r"\infty": "∞", r"\le": "≤", r"\ge": "≥", r"\in": "in", r"\pm": "±",
    r"\perp": "perp", r"\propto": "~", r"\max": "max", r"\arctan": "arctan",
    r"\cos": "cos", r"\sin": "sin", r"\log": "log",
    r"\alpha": "α", r"\delta": "δ", r"\sigma": "σ", r"\ell": "l",
    r"\tilde": "", r"\mathrm": "", r"\text": "", r"\mathrel": "",
    r"\left": "", r"\right": "", r"\Big": "",
}
_PUNCTUATION = {r"\,": " ", r"\;": " ", r"\ ": " ", r"\%": "%", r"\{": "⦃", r"\}": "⦄"}
# Only glyphs the window's font (Roboto) has: digits 1-3 as superscripts, no subscripts.
_SUPERSCRIPTS = {"1": "¹", "2": "²", "3": "³"}
_ATOM = r"[A-Za-z]|[0-9.]+|π"
MATH_COMMANDS = frozenset(_LATEX_SYMBOLS) | {r"\sqrt", r"\frac"}
"""The LaTeX commands :func:`math_to_text` turns into text (any other loses only its
backslash)."""


def math_to_text(text: str) -> str:
    """``text`` with its ``$...$`` inline math turned into readable text (Φ, π, <n, ω>,
    √3, Δω/(4π), x², c_0, ...) using only glyphs the window's font has. Covers what the
    lessons use; an unknown command just loses its backslash."""
    def convert(match: re.Match) -> str:
        math = match.group(1)
        math = re.sub(r"\\langle\s*", "<", math)
        math = re.sub(r"\s*\\rangle", ">", math)
        for command, symbol in _PUNCTUATION.items():
            math = math.replace(command, symbol)
        while True:         # innermost first: \frac{\sqrt{\pi}}{2} -> (√(\pi))/(2)
            before = math
            math = re.sub(r"\\sqrt\{([^{}]*)\}", r"√(\1)", math)
            math = re.sub(r"\\frac\{([^{}]*)\}\{([^{}]*)\}", r"(\1)/(\2)", math)
            if math == before:
                break
        for command in sorted(_LATEX_SYMBOLS, key=len, reverse=True):
            math = re.sub(re.escape(command) + r"(?![A-Za-z])", _LATEX_SYMBOLS[command], math)
        math = re.sub(r"\^\{?([123])\}?(?![0-9])", lambda m: _SUPERSCRIPTS[m.group(1)], math)
        math = re.sub(r"\^\{([^{}]*)\}", r"^(\1)", math)
        math = re.sub(r"_\{([^{}]*)\}", r"_(\1)", math)
        math = re.sub(r"\\([A-Za-z]+)", r"\1", math)
        math = math.replace("{", "").replace("}", "").replace("⦃", "{").replace("⦄", "}")
        math = re.sub(rf"\(({_ATOM})\)", r"\1", math)     # (x) -> x for a single atom
        return re.sub(r"  +", " ", math).strip()

    return re.sub(r"\$([^$]+)\$", convert, text)
