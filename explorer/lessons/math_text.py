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


_FRACTION_OPEN, _FRACTION_CLOSE = "\u27ea", "\u27eb"
"""Brackets around a converted fraction until its surroundings are text (⟪a/b⟫)."""
_FUNCTIONS = ("arctan", "cos", "sin", "log", "max", "√")
_FACTOR_END = r"[A-Za-z0-9.πΦφωΔθρασδ)²³¹]"
_FACTOR_START = r"[A-Za-z0-9.πΦφωΔθρασδ(√]"


def _group(math: str, start: int) -> tuple[str, int]:
    """The argument of a command at ``start``: a ``{...}`` group (nested braces matched)
    or a single character or command; returns it and the index after it."""
    while start < len(math) and math[start] == " ":
        start += 1
    if start >= len(math):
        return "", start
    if math[start] == "{":
        depth = 0
        for end in range(start, len(math)):
            depth += {"{": 1, "}": -1}.get(math[end], 0)
            if depth == 0:
                return math[start + 1:end], end + 1
        return math[start + 1:], len(math)
    command = re.match(r"\\[A-Za-z]+", math[start:])
    if command:
        return command.group(0), start + command.end()
    return math[start], start + 1


def _is_atom(text: str) -> bool:
    """One number, or one letter or command with its subscript, and a power (``11``,
    ``n``, ``\\pi``, ``\\Phi_t``, ``h^2``): needs no brackets."""
    script = r"(?:[A-Za-z0-9]|\{[^{}]*\})"
    symbol = rf"(?:[A-Za-z]|\\[A-Za-z]+|π)(?:_{script})?"
    return re.fullmatch(rf"(?:[0-9.]+|{symbol})(?:\^{script})?", text.strip()) is not None


def _top_level(text: str, characters: str) -> bool:
    """Whether ``text`` has one of ``characters`` outside every bracket (its first
    character, a sign, does not count)."""
    depth = 0
    for index, char in enumerate(text):
        depth += {"(": 1, "{": 1, "[": 1, ")": -1, "}": -1, "]": -1}.get(char, 0)
        if depth == 0 and char in characters and index > 0:
            return True
    return False


def _expand(math: str) -> str:
    """``\\frac`` and ``\\sqrt`` as text with the brackets their meaning needs: a
    numerator bracketed only around a sum, a denominator unless it is one atom (a/(bc),
    since a/bc reads as (a/b)·c), a root unless it is one atom; the fraction itself in
    ⟪ ⟫ until :func:`_place_fractions` sees what stands beside it."""
    out, index = [], 0
    while index < len(math):
        command = re.match(r"\\(frac|sqrt)(?![A-Za-z])", math[index:])
        if not command:
            out.append(math[index])
            index += 1
            continue
        index += command.end()
        if command.group(1) == "sqrt":
            body, index = _group(math, index)
            body = _expand(body)
            out.append("√" + (body if _is_atom(body) else f"({body})"))
            continue
        top, index = _group(math, index)
        bottom, index = _group(math, index)
        top, bottom = _expand(top), _expand(bottom)
        top = f"({top})" if _top_level(top, "+-=") else top
        bottom = bottom if _is_atom(bottom) else f"({bottom})"
        out.append(f"{_FRACTION_OPEN}{top}/{bottom}{_FRACTION_CLOSE}")
    return "".join(out)


def _place_fractions(text: str) -> str:
    """Resolve ⟪a/b⟫: bracketed as a function's argument (``arctan(3√11/11)``), joined by
    ``·`` to a factor beside it (``2/π·arctan``: never ``2/πarctan``), else bare."""
    pattern = re.compile(f"{_FRACTION_OPEN}([^{_FRACTION_OPEN}{_FRACTION_CLOSE}]*)"
                         f"{_FRACTION_CLOSE}")
    while True:
        match = pattern.search(text)
        if match is None:
            return text
        before, body, after = text[:match.start()], match.group(1), text[match.end():]
        if before.rstrip().endswith(_FUNCTIONS):
            body = f"({body})"
            before = before.rstrip()
        else:
            if re.search(_FACTOR_END + r"\s*$", before):
                body = "·" + body
                before = before.rstrip()
            if re.match(r"\s*" + _FACTOR_START, after) and not after.startswith("_"):
                body = body + "·"
                after = after.lstrip()
        text = before + body + after


def math_to_text(text: str) -> str:
    """``text`` with its ``$...$`` inline math turned into readable text (Φ, π, <n, ω>,
    √3, Δω/(4π), x², c_0, ...) using only glyphs the window's font has, with the
    brackets that keep a formula's meaning (``2/π·arctan(3√11/11)``). Covers what the
    lessons use; an unknown command just loses its backslash."""
    def convert(match: re.Match) -> str:
        math = match.group(1)
        math = re.sub(r"\\langle\s*", "<", math)
        math = re.sub(r"\s*\\rangle", ">", math)
        for command, symbol in _PUNCTUATION.items():
            math = math.replace(command, symbol)
        math = _expand(math)
        for command in sorted(_LATEX_SYMBOLS, key=len, reverse=True):
            math = re.sub(re.escape(command) + r"(?![A-Za-z])", _LATEX_SYMBOLS[command], math)
        math = re.sub(r"\^\{?([123])\}?(?![0-9])", lambda m: _SUPERSCRIPTS[m.group(1)], math)
        math = re.sub(r"\^\{([^{}]*)\}", r"^(\1)", math)
        math = re.sub(r"_\{([^{}]*)\}", r"_(\1)", math)
        math = re.sub(r"\\([A-Za-z]+)", r"\1", math)
        math = math.replace("{", "").replace("}", "").replace("⦃", "{").replace("⦄", "}")
        # (x) -> x for a single atom, but not a function's argument: lobe(n) stays
        math = re.sub(rf"(?<![A-Za-z])\(({_ATOM})\)", r"\1", math)
        math = _place_fractions(math)
        # √3π reads as √(3π): the root of one atom is joined to the next factor by a dot
        math = re.sub(r"(√(?:[0-9.]+|π|[A-Za-z]))(?=[A-Za-zπ√(])", r"\1·", math)
        return re.sub(r"  +", " ", math).strip()

    return re.sub(r"\$([^$]+)\$", convert, text)
