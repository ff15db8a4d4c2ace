"""What a learner reads is words and typeset math: no raw TeX outside math, no settings
field names or live-quantity names, no file names of the plain-text sources, and no
formula statement (the caption under a typeset formula) with TeX in it."""

from __future__ import annotations

import re

import pytest

from explorer.lessons import load_all
from explorer.lpv.settings import Corrections, Settings

_PLACEHOLDER = re.compile(r"\{\{[^}]*\}\}")
_MATH = re.compile(r"\$\$.*?\$\$|\$[^$]*\$", re.S)
_RAW_TEX = re.compile(r"\\[A-Za-z]+|[_^]\{")
_SOURCE_FILES = re.compile(r"lpv-[a-z0-9-]+\.md|seeds/")
_QUANTITY = re.compile(r"\b(?:audit|frame|settings|corrections|error|derived|mark)\.[a-z_]+")
_COMMAND = re.compile(r"`lpv-explorer [^`]*`"
                      r"|lpv-explorer [a-z]+(?: --?[a-z0-9-]+(?: [^ ,.;:)]+)?)*")


def _field_names() -> set[str]:
    """Names a learner should never have to read: the settings fields and switches
    spelled with an underscore (single words like "fog" are also plain English)."""
    names = {f for f in Settings.__dataclass_fields__ if "_" in f}
    return names | {name for name in Corrections.names() if "_" in name}


FIELDS = _field_names()


def _learner_texts():
    lessons, errors = load_all()
    assert not errors
    for lesson in lessons:
        yield lesson.path.name, "summary", lesson.summary
        for step in lesson.steps:
            where = f"step {step.number}"
            yield lesson.path.name, f"{where} title", step.title
            yield lesson.path.name, f"{where} text", step.text
            for index, item in enumerate(step.try_this, start=1):
                yield lesson.path.name, f"{where} try-this {index}", item.prompt
                yield lesson.path.name, f"{where} try-this {index} label", item.label
                if item.predict is not None:
                    yield lesson.path.name, f"{where} try-this {index} predict", \
                        " ".join((item.predict.question, *item.predict.choices))
            for spec in step.figures:
                yield lesson.path.name, f"{where} figure {spec.instance_id}", spec.caption
            for mark in step.marks:
                yield lesson.path.name, f"{where} mark {mark.id}", mark.label


def _prose(text: str) -> str:
    """``text`` without its live numbers, its math and its command lines."""
    text = _PLACEHOLDER.sub(" ", text)
    text = _MATH.sub(" ", text)
    return _COMMAND.sub(" ", text)


TEXTS = list(_learner_texts())


@pytest.mark.parametrize("name, where, text", TEXTS,
                         ids=[f"{n}:{w}" for n, w, _ in TEXTS])
def test_learner_text_is_words(name, where, text):
    prose = _prose(text)
    assert not _RAW_TEX.search(prose), f"raw TeX outside math: {_RAW_TEX.search(prose)[0]!r}"
    assert not _SOURCE_FILES.search(text), "a source cited by its file name"
    quantity = _QUANTITY.search(prose)
    assert quantity is None, f"a live-quantity name shown as text: {quantity[0]!r}"
    words = set(re.findall(r"[a-z][a-z0-9]*(?:_[a-z0-9]+)+", prose))
    assert not words & FIELDS, f"settings field names shown to the learner: {words & FIELDS}"


def test_the_rules_catch_what_they_are_for():
    """Each rule finds the slip it is written against (so the test above asserts
    something)."""
    assert _RAW_TEX.search(_prose("the integral ∫_{S²} dω"))
    assert not _RAW_TEX.search(_prose(r"the integral $\int_{S^2} d\omega$"))
    assert _QUANTITY.search(_prose("it keeps audit.last_over_first of it"))
    assert not _QUANTITY.search(_prose("it keeps {{audit.last_over_first:.2f}} of it"))
    assert "indirect_only" in FIELDS and "injection_pi" in FIELDS
    assert _SOURCE_FILES.search("as printed in lpv-annotations.md")
    assert "injection_offset" not in _prose(
        "run `lpv-explorer compare --scene room --injection-offset 0` to see it")


def test_formula_captions_have_no_raw_tex():
    """The statement under a typeset formula (explorer.derived) is plain text, and names
    its sources in full."""
    from explorer.derived_table import RESULTS

    lessons, _ = load_all()
    shown = {name for lesson in lessons for step in lesson.steps for name in step.formulas}
    shown |= {m.group(1) for lesson in lessons for step in lesson.steps
              for m in re.finditer(r"\{\{formula:([^}]+)\}\}", step.text)}
    bad = {name: RESULTS[name][1] for name in RESULTS
           if _RAW_TEX.search(RESULTS[name][1]) or _SOURCE_FILES.search(RESULTS[name][1])}
    assert not bad, bad
    assert shown <= set(RESULTS)


def test_the_printed_lessons_use_words(capsys):
    """``lpv-explorer lessons ID`` prints what a learner reads in a terminal: the same
    rules hold for it (but for its closing command line)."""
    from explorer.cli import main

    lessons, _ = load_all()
    for lesson in lessons:
        assert main(["lessons", lesson.id]) == 0
        out = capsys.readouterr().out
        prose = "\n".join(line for line in out.splitlines()
                          if not line.startswith("render a step:"))
        prose = _COMMAND.sub(" ", prose)
        words = set(re.findall(r"[a-z][a-z0-9]*(?:_[a-z0-9]+)+", prose))
        assert not words & FIELDS, (lesson.id, words & FIELDS)
        assert not _QUANTITY.search(prose), (lesson.id, _QUANTITY.search(prose)[0])


def test_the_glossary_explains_terms_the_lessons_use(tmp_path):
    """Every glossary term occurs in the lessons (the four the course leans on among
    them), its meaning is plain words, and a broken glossary is reported."""
    from explorer.lessons.glossary import GlossaryError, defined_in, load_glossary, matches

    terms = load_glossary()
    assert {"VPL", "flux in flight", "clamp gain", "geometry volume"} <= \
        {t.term for t in terms}
    lessons, _ = load_all()
    used: set[str] = set()
    for lesson in lessons:
        for step in lesson.steps:
            used |= defined_in(_prose(step.text), terms)
            for item in step.try_this:
                used |= defined_in(_prose(item.prompt), terms)
    assert used == {t.term for t in terms}, {t.term for t in terms} - used
    for term in terms:
        assert not _RAW_TEX.search(term.meaning) and not _QUANTITY.search(term.meaning)
    found = matches("Its VPLs, and the flux in flight: clamp gain.".split(), terms)
    assert [(first, count, term.term) for first, count, term in found] == [
        (1, 1, "VPL"), (4, 3, "flux in flight"), (7, 2, "clamp gain")]
    (tmp_path / "glossary.toml").write_text('[[terms]]\nterm = "VPL"\nmeaning = "$x$"\n')
    with pytest.raises(GlossaryError, match="no math"):
        load_glossary(tmp_path)
    (tmp_path / "glossary.toml").write_text('[[terms]]\nterm = "VPL"\nmeaning = "a"\n'
                                            '[[terms]]\nterm = "vpl"\nmeaning = "b"\n')
    with pytest.raises(GlossaryError, match="already a spelling"):
        load_glossary(tmp_path)
