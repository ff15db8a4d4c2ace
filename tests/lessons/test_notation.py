"""One notation per quantity: every lesson's prose, math and captions, and every formula a
step typesets, write each quantity of explorer.lessons.notation.QUANTITIES one way."""

from __future__ import annotations

import re

import pytest

from explorer.lessons import load_all
from explorer.lessons.notation import QUANTITIES, normal, notation_problems
from explorer.lessons.words import learner_texts


def _texts():
    lessons, errors = load_all()
    assert not errors
    return list(learner_texts(lessons))


TEXTS = _texts()


@pytest.mark.parametrize("name, where, text", TEXTS, ids=[f"{n}:{w}" for n, w, _ in TEXTS])
def test_lesson_text_keeps_the_notation(name, where, text):
    assert not notation_problems(text)


def test_typeset_formulas_keep_the_notation():
    """The formulas a step shows (its list and its {{formula:...}} references) use the
    same symbols as the prose around them."""
    from explorer.derived_table import RESULTS

    lessons, _ = load_all()
    shown = {name for lesson in lessons for step in lesson.steps for name in step.formulas}
    shown |= {m.group(1) for lesson in lessons for step in lesson.steps
              for m in re.finditer(r"\{\{formula:([^}]+)\}\}", step.text)}
    assert shown
    bad = {name: notation_problems(f"${RESULTS[name][0]}$") for name in shown}
    assert not {name: found for name, found in bad.items() if found}


def test_every_derived_result_keeps_the_notation():
    """Every result the Formulas and Corrections panels typeset, and its statement, except
    a value quoted as a source printed it (its symbol marked "printed")."""
    from explorer.derived_table import RESULTS

    bad = {name: notation_problems(f"${tex}$") + notation_problems(statement)
           for name, (tex, statement, *_rest) in RESULTS.items()
           if r"\mathrm{printed}" not in tex}
    assert len(bad) > 100
    assert not {name: found for name, found in bad.items() if found}


def test_each_notation_belongs_to_one_quantity():
    written = [normal(q.notation) for q in QUANTITIES if q.notation]
    assert len(written) == len(set(written))


@pytest.mark.parametrize("text, kind", [
    ("each cell size $d$ of the grid", "cell size"),
    (r"the step $\Delta x$ between cells", "cell size"),
    ("a surface with albedo $a$ sends back", "diffuse albedo"),
    (r"radiance $L = a\,E/\pi$", "diffuse albedo"),
    (r"a room of reflectance $c_{diff}$", "diffuse albedo"),
    (r"a texel covers a solid angle $\rho$", "solid angle"),
    (r"a lobe carrying $\Phi_l$", "flux"),
    ("the irradiance $M$ on the wall", "irradiance"),
    ("the coefficient $c_{00}$", "SH coefficient"),
    ("the lateral faces of the cube", "face names"),
    ("the published Φ_l = Φ_f/π", "flux"),
])
def test_the_rules_catch_what_they_are_for(text, kind):
    found = notation_problems(text)
    assert found and all(problem.startswith(kind) for problem in found), found


def test_the_notation_itself_passes():
    text = (r"a cell size $h$, albedo $c_\text{diff}$ and $L = c_{\mathrm{diff}}\,E/\pi$, "
            r"a solid angle $\Delta\omega_\text{front}$, flux $\Phi_L$, the irradiance "
            r"$E$, intensity $I_n = \Phi/\pi$, radiance $L_o$, coefficients $c_0$ and "
            r"$c_1$, the front and side faces, Φ_L and Φ_lobe = Φ_f")
    assert notation_problems(text) == []
