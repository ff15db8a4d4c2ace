"""What a learner reads is words and typeset math: no raw TeX outside math, no settings
field names or live-quantity names, no file names of the plain-text sources, and no
formula statement (the caption under a typeset formula) with TeX in it."""

from __future__ import annotations

import re

import pytest

from explorer.lessons import load_all, words
from explorer.lessons.words import FIELDS, learner_texts, word_problems


def _learner_texts():
    lessons, errors = load_all()
    assert not errors
    yield from learner_texts(lessons)


TEXTS = list(_learner_texts())


@pytest.mark.parametrize("name, where, text", TEXTS,
                         ids=[f"{n}:{w}" for n, w, _ in TEXTS])
def test_learner_text_is_words(name, where, text):
    assert not word_problems(text)


def test_the_rules_catch_what_they_are_for():
    """Each rule finds the slip it is written against (so the test above asserts
    something)."""
    assert words.RAW_TEX.search(words.prose("the integral ∫_{S²} dω"))
    assert not words.RAW_TEX.search(words.prose(r"the integral $\int_{S^2} d\omega$"))
    assert words.QUANTITY.search(words.prose("it keeps audit.last_over_first of it"))
    assert not words.QUANTITY.search(words.prose("it keeps {{audit.last_over_first:.2f}} of it"))
    assert "indirect_only" in FIELDS and "injection_pi" in FIELDS
    assert words.SOURCE_FILES.search("as printed in lpv-annotations.md")
    assert "injection_offset" not in words.prose(
        "run `lpv-explorer compare --scene room --injection-offset 0` to see it")
    found = word_problems(r"the \omega of grid_size, audit.injected, in lpv-notes.md")
    assert [problem.split(":")[0] for problem in found] == [
        "raw TeX outside math", "a source cited by its file name",
        "a live-quantity name shown as text", "settings field names shown to the learner"]


def test_formula_captions_have_no_raw_tex():
    """The statement under a typeset formula (explorer.derived) is plain text, and names
    its sources in full."""
    from explorer.derived_table import RESULTS

    lessons, _ = load_all()
    shown = {name for lesson in lessons for step in lesson.steps for name in step.formulas}
    shown |= {m.group(1) for lesson in lessons for step in lesson.steps
              for m in re.finditer(r"\{\{formula:([^}]+)\}\}", step.text)}
    bad = {name: RESULTS[name][1] for name in RESULTS
           if words.RAW_TEX.search(RESULTS[name][1]) or words.SOURCE_FILES.search(RESULTS[name][1])}
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
        prose = words.COMMAND.sub(" ", prose)
        names = set(re.findall(r"[a-z][a-z0-9]*(?:_[a-z0-9]+)+", prose))
        assert not names & FIELDS, (lesson.id, names & FIELDS)
        assert not words.QUANTITY.search(prose), (lesson.id, words.QUANTITY.search(prose)[0])


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
            used |= defined_in(words.prose(step.text), terms)
            for item in step.try_this:
                used |= defined_in(words.prose(item.prompt), terms)
    assert used == {t.term for t in terms}, {t.term for t in terms} - used
    for term in terms:
        assert not words.RAW_TEX.search(term.meaning) and not words.QUANTITY.search(term.meaning)
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
