"""The math of every step keeps its meaning in plain text, and its arithmetic is right.

* Every side of every formula that is a number (no quantity named) has the same value
  read from the LaTeX and read from the plain text ``lpv-explorer lessons ID`` prints
  (``5/6 − 2/π·arctan(3√11/11)``, never ``2/πarctan(3√11)/11``);
* every chain ``a = b = c`` whose sides are numbers agrees with itself: a printed sum,
  product or ratio equals what its own operands give, to the digits printed;
* a fraction in words beside its number ("3^(-3/2), about a fifth") fits it.

Both forms are read by small grammars (tests/lessons/formula_values.py)."""

from __future__ import annotations

import re

import pytest
import sympy

from explorer.lessons import live_values, load_all, math_to_text
from explorer.lessons import text as lesson_text
from explorer.lessons.words import learner_texts
from tests.lessons.formula_values import (
    latex_python,
    latex_value,
    plain_value,
    split_sides,
)

_MATH = re.compile(r"\$\$(.+?)\$\$|\$([^$]+)\$", re.S)
_UNIT_LATEX = re.compile(r"\\?\s*\\text\{(?:sr|W)\}\s*$")
_UNIT_PLAIN = re.compile(r"\s+(?:sr|W)\s*$")
_LITERAL = re.compile(r"(?<![0-9.])([0-9]+\.([0-9]+))(?![0-9.])")


def _derived(name: str, fmt: str) -> str:
    """A derived number as the step prints it; any live one as a quantity name."""
    if name.startswith(("derived.", "settings.", "corrections.")):
        return live_values.render(name, fmt, live_values.LiveContext())
    return r"\mathrm{live}"


def _formulas():
    """(where, LaTeX) of every math span a learner reads: summaries, step texts, try-this
    prompts, labels and predictions, figure captions, mark labels."""
    lessons, errors = load_all(check_formula=None)
    assert not errors
    for name, where, text in learner_texts(lessons):
        filled = lesson_text.substitute(text or "", _derived)
        for match in _MATH.finditer(filled):
            math = (match.group(1) or match.group(2)).strip()
            yield f"{name[:2]} {where}", math


FORMULAS = list(_formulas())


def _sides(math: str) -> tuple[list[str], list[str]]:
    plain = math_to_text(f"${' '.join(math.split())}$")
    return split_sides(math), split_sides(plain)


def test_every_numeric_side_prints_with_its_meaning():
    compared = []
    for where, math in FORMULAS:
        latex_sides, plain_sides = _sides(math)
        assert len(latex_sides) == len(plain_sides), (where, math)
        for latex, plain in zip(latex_sides, plain_sides):
            want = latex_value(_UNIT_LATEX.sub("", latex))
            if want is None:
                continue
            got = plain_value(_UNIT_PLAIN.sub("", plain))
            assert got is not None, f"{where}: {plain!r} does not read as {latex!r}"
            assert abs(float(got - want)) <= 1e-12 * max(1.0, abs(float(want))), \
                f"{where}: {plain!r} = {float(got)}, but {latex!r} = {float(want)}"
            compared.append((where, plain))
    assert len(compared) > 40
    # the DX11 step factor of lesson 11, the formula the printer once broke
    assert any("arctan(3√11/11)" in plain and where.startswith("11 ")
               for where, plain in compared)


def _tolerance(side: str) -> float:
    """How far a side may be from the exact value for the digits it prints: each decimal
    literal moved by half its last digit, the changes of the side added."""
    base = latex_value(side)
    total = 0.0
    for match in _LITERAL.finditer(side):
        half = sympy.Rational(5, 10 ** (len(match.group(2)) + 1))
        moved = f"{side[:match.start()]}({match.group(1)} + {half}){side[match.end():]}"
        value = latex_value(moved)
        if value is not None:
            total += abs(float(value - base))
    return total


def test_every_printed_arithmetic_agrees_with_its_operands():
    chains = 0
    for where, math in FORMULAS:
        sides = [_UNIT_LATEX.sub("", side) for side in split_sides(math)]
        numbers = [(side, latex_value(side)) for side in sides]
        numbers = [(side, value) for side, value in numbers if value is not None]
        if len(numbers) < 2:
            continue
        chains += 1
        first_side, first = numbers[0]
        for side, value in numbers[1:]:
            allowed = _tolerance(first_side) + _tolerance(side) + 1e-12
            assert abs(float(value - first)) <= allowed, \
                f"{where}: {first_side.strip()!r} = {float(first)} but {side.strip()!r} = " \
                f"{float(value)} ({latex_python(side).strip()})"
    assert chains > 10


@pytest.mark.parametrize("math, plain", [
    (r"\frac{5}{6} - \frac{2}{\pi}\arctan\frac{3\sqrt{11}}{11}",
     "5/6 - 2/π·arctan(3√11/11)"),
    (r"\frac{\Phi_{t+1}}{\Phi_t} = \frac{1}{4\pi}", "Φ_(t+1)/Φ_t = 1/(4π)"),
    (r"\mathrm{lobe}(n) + \mathrm{lobe}(-n)", "lobe(n) + lobe(-n)"),
    (r"\frac{1 + x}{2}", "(1 + x)/2"),
    (r"\sqrt{3}\pi/2", "√3·π/2"),
])
def test_the_printer_brackets_what_the_typesetting_groups(math, plain):
    assert math_to_text(f"${math}$") == plain


_ORDINALS = {word: number for number, word in enumerate(
    "first second third fourth fifth sixth seventh eighth ninth tenth eleventh twelfth"
    .split(), 1)}
_NUMBER = r"(\d+\.\d+)"


def _decimals(number: str) -> str:
    return number.split(".")[1]


def _plain_steps():
    from explorer.commands.lessons import _plain

    lessons, _ = load_all(check_formula=None)
    for lesson in lessons:
        for step in lesson.steps:
            yield f"{lesson.number:02d}/{step.number}", " ".join(_plain(step.text).split())


def test_every_digit_claim_counts_the_digits_it_names():
    """"correct to every printed digit", "its fifth decimal is 4 instead of 3, too large by
    one unit", "short in the eighth decimal", "wrong in its last digit (4 where the exact
    value has 6)": each recounted from the two numbers the sentence prints (the exact one
    for the last: the step's printed number that agrees longest with the quoted one)."""
    claims = 0
    for where, text in _plain_steps():
        numbers = re.findall(_NUMBER, text)
        for printed, exact in re.findall(rf"printed {_NUMBER}, exact [^=]*= {_NUMBER}: "
                                         r"correct to every printed digit", text):
            places = len(_decimals(printed))
            assert f"{float(exact):.{places}f}" == printed, (where, printed, exact)
            claims += 1
        for printed, exact, nth, digit, instead in re.findall(
                rf"printed {_NUMBER}, exact [^=]*= {_NUMBER}: its (\w+) decimal is (\d) "
                r"instead of (\d), too large by one unit in that place", text):
            place = _ORDINALS[nth]
            assert _decimals(printed)[:place - 1] == _decimals(exact)[:place - 1], where
            assert (_decimals(printed)[place - 1], _decimals(exact)[place - 1]) == \
                (digit, instead), (where, printed, exact)
            assert sympy.Rational(printed) - sympy.Rational(exact) == \
                sympy.Rational(1, 10 ** place), (where, printed, exact)
            claims += 1
        for printed, nth in re.findall(rf"π printed as {_NUMBER}: short in the (\w+) "
                                       r"decimal", text):
            place = _ORDINALS[nth]
            exact = f"{sympy.N(sympy.pi, 30)}"
            assert len(_decimals(printed)) == place - 1, (where, printed)
            assert exact.startswith(printed) and _decimals(exact)[place - 1] != "0", where
            claims += 1
        for quoted, digit, exact_digit in re.findall(
                rf"quoted as {_NUMBER}…, wrong in its last digit \((\d) where the exact "
                r"value has (\d)\)", text):
            places = len(_decimals(quoted))
            longer = [n for n in numbers if len(_decimals(n)) > places]
            exact = max(longer, key=lambda n: len(_common_prefix(n, quoted)))
            assert _decimals(quoted)[:places - 1] == _decimals(exact)[:places - 1], where
            assert (_decimals(quoted)[-1], _decimals(exact)[places - 1]) == \
                (digit, exact_digit), (where, quoted, exact)
            claims += 1
    assert claims >= 4


def _common_prefix(a: str, b: str) -> str:
    size = 0
    while size < min(len(a), len(b)) and a[size] == b[size]:
        size += 1
    return a[:size]


_FRACTION_WORDS = {"half": sympy.Rational(1, 2), "third": sympy.Rational(1, 3),
                   "quarter": sympy.Rational(1, 4), "fifth": sympy.Rational(1, 5),
                   "sixth": sympy.Rational(1, 6), "eighth": sympy.Rational(1, 8),
                   "tenth": sympy.Rational(1, 10)}
_ABOUT = re.compile(r"(\S+), (?:about|roughly|nearly) (?:a|an|one) (" +
                    "|".join(_FRACTION_WORDS) + r")\b")
_PER_AXIS = re.compile(r"\b(Half|A third|A quarter) as many cells per axis\b.*?\b(?:a|an) (" +
                       "|".join(_FRACTION_WORDS) + r") of the cells", re.I)


def _plain_texts():
    """(where, plain text) of everything a learner reads, as `lessons ID` prints it."""
    from explorer.commands.lessons import _plain

    lessons, _ = load_all(check_formula=None)
    for name, where, text in learner_texts(lessons):
        yield f"{name[:2]} {where}", " ".join(_plain(text or "").split())


def verbal_ratio_problems(text: str) -> list[str]:
    """Where ``text`` puts a fraction in words next to a number it does not approximate:
    "covers 3^(-3/2), about a fifth" (within 10 %), "half as many cells per axis ... an
    eighth of the cells" (the cube of the per-axis fraction, exactly)."""
    problems = []
    for operand, word in _ABOUT.findall(text):
        value = plain_value(operand.rstrip(",;:"))
        if value is None:
            continue
        claimed = _FRACTION_WORDS[word]
        if abs(float(value / claimed) - 1) > 0.1:
            problems.append(f"{operand} = {float(value):.4g} is not about a {word}")
    for per_axis, word in _PER_AXIS.findall(text):
        axis = _FRACTION_WORDS[per_axis.split()[-1].lower()]
        if axis ** 3 != _FRACTION_WORDS[word]:
            problems.append(f"{per_axis.lower()} per axis is {axis ** 3} of the cells, "
                            f"not a {word}")
    return problems


def test_every_fraction_in_words_fits_its_number():
    found = [(where, verbal_ratio_problems(text)) for where, text in _plain_texts()]
    assert not [item for item in found if item[1]]
    checked = sum(len(_ABOUT.findall(text)) + len(_PER_AXIS.findall(text))
                  for _, text in _plain_texts())
    assert checked >= 2


@pytest.mark.parametrize("text, bad", [
    ("and covers 3^(-3/2), about a fifth, of it", False),
    ("and covers 3^(-3/2), about a third, of it", True),
    ("Half as many cells per axis: the grid has an eighth of the cells", False),
    ("Half as many cells per axis: the grid has a quarter of the cells", True),
])
def test_the_fraction_rule_catches_a_wrong_fraction(text, bad):
    assert bool(verbal_ratio_problems(text)) == bad
