"""Numbers from the two forms of a lesson's math: its LaTeX and the plain text the
terminal prints (explorer/lessons/math_text.py), each read by a small grammar into sympy,
for tests/lessons/test_formula_text.py. A side of an equation that names a quantity
(a letter other than π or a function) is not a number and reads as None."""

from __future__ import annotations

import re

import sympy
from sympy.parsing.sympy_parser import (
    convert_xor,
    implicit_multiplication,
    parse_expr,
    standard_transformations,
)

_TRANSFORMS = standard_transformations + (implicit_multiplication, convert_xor)
_NAMES = {"pi": sympy.pi, "sqrt": sympy.sqrt, "atan": sympy.atan, "cos": sympy.cos,
          "sin": sympy.sin, "log": sympy.log}
_ALLOWED = re.compile(r"^[0-9.+\-*/() ]*$")


def _parse(text: str) -> sympy.Expr | None:
    """``text`` (Python syntax with the function names of :data:`_NAMES`, implicit
    products) as an exact number, or None when it names anything else."""
    if not text.strip() or not _ALLOWED.match(re.sub(r"pi|sqrt|atan|cos|sin|log", "", text)):
        return None
    # decimals as exact rationals: a printed 0.3652176138 is that decimal, not a float
    text = re.sub(r"(?<![0-9.])([0-9]+\.[0-9]+|[0-9]+)(?![0-9.])",
                  lambda m: f"Rational('{m.group(1)}')", text)
    try:
        value = parse_expr(text, local_dict={**_NAMES, "Rational": sympy.Rational},
                           transformations=_TRANSFORMS, evaluate=True)
    except (SyntaxError, TypeError, ValueError, sympy.SympifyError):
        return None
    return value if getattr(value, "is_number", False) else None


def _latex_group(math: str, start: int) -> tuple[str, int]:
    """The ``{...}`` group (or single character) at ``start``, nested braces matched."""
    if math[start] != "{":
        return math[start], start + 1
    depth = 0
    for end in range(start, len(math)):
        depth += {"{": 1, "}": -1}.get(math[end], 0)
        if depth == 0:
            return math[start + 1:end], end + 1
    raise ValueError(f"unbalanced braces in {math!r}")


def latex_python(math: str) -> str:
    """LaTeX (the lessons' subset: \\frac, \\sqrt, ^, \\pi, \\arctan, \\cdot, \\times) as
    Python syntax."""
    out, index = [], 0
    while index < len(math):
        command = re.match(r"\\(frac|sqrt)(?![A-Za-z])\s*", math[index:])
        if command:
            index += command.end()
            first, index = _latex_group(math, index)
            if command.group(1) == "sqrt":
                out.append(f"sqrt({latex_python(first)})")
                continue
            second, index = _latex_group(math, index)
            out.append(f"(({latex_python(first)})/({latex_python(second)}))")
            continue
        out.append(math[index])
        index += 1
    text = "".join(out)
    for command, python in ((r"\pi", " pi "), (r"\arctan", " atan "), (r"\cos", " cos "),
                            (r"\sin", " sin "), (r"\log", " log "), (r"\cdot", "*"),
                            (r"\times", "*"), (r"\left", ""), (r"\right", ""),
                            (r"\,", " "), (r"\;", " "), (r"\ ", " "), (r"\Big", "")):
        text = text.replace(command, python)
    text = re.sub(r"\^\{([^{}]*)\}", r"**(\1)", text).replace("^", "**")
    return text.replace("{", "(").replace("}", ")")


def plain_python(text: str) -> str:
    """The plain-text math (π, √, ², ·, ×, arctan) as Python syntax: √ takes the atom or
    bracket after it."""
    text = text.replace("−", "-").replace("·", "*").replace("×", "*")
    text = text.replace("²", "**2").replace("³", "**3").replace("¹", "**1").replace("^", "**")
    text = text.replace("π", " pi ").replace("arctan", " atan ")
    out, index = [], 0
    while index < len(text):
        if text[index] != "√":
            out.append(text[index])
            index += 1
            continue
        index += 1
        if index < len(text) and text[index] == "(":
            depth = 0
            for end in range(index, len(text)):
                depth += {"(": 1, ")": -1}.get(text[end], 0)
                if depth == 0:
                    break
            out.append(f" sqrt{text[index:end + 1]}")
            index = end + 1
        else:
            atom = re.match(r"[0-9.]+| pi |[A-Za-z]", text[index:])
            if atom is None:
                raise ValueError(f"√ with no argument in {text!r}")
            out.append(f" sqrt({atom.group(0)})")
            index += atom.end()
    return "".join(out)


def split_sides(math: str) -> list[str]:
    """The sides of an equation chain (``a = b = c``; ``≈`` and ``\\approx`` too), split
    outside every bracket."""
    sides, depth, start = [], 0, 0
    text = math.replace(r"\approx", "≈")
    for index, char in enumerate(text):
        depth += {"(": 1, "{": 1, "[": 1, ")": -1, "}": -1, "]": -1}.get(char, 0)
        if depth == 0 and char in "=≈":
            sides.append(text[start:index])
            start = index + 1
    return sides + [text[start:]]


def latex_value(side: str) -> sympy.Expr | None:
    return _parse(latex_python(side))


def plain_value(side: str) -> sympy.Expr | None:
    try:
        return _parse(plain_python(side))
    except ValueError:
        return None
