"""What a learner reads is words and typeset math: no raw TeX outside math, no settings
field names or live-quantity names, no file names of the plain-text sources. The rules
the shipped course is held to (tests/lessons/test_lesson_words.py) and ``lpv-explorer
lessons --lint`` applies to a folder's lessons."""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator
from functools import lru_cache

from explorer.lessons.model import Lesson
from explorer.lpv.settings import Corrections, Settings

PLACEHOLDER = re.compile(r"\{\{[^}]*\}\}")
MATH = re.compile(r"\$\$.*?\$\$|\$[^$]*\$", re.S)
RAW_TEX = re.compile(r"\\[A-Za-z]+|[_^]\{")
"""A TeX command or a sub/superscript group: math written outside ``$...$``."""
SOURCE_FILES = re.compile(r"lpv-[a-z0-9-]+\.md|seeds/")
"""The plain-text sources' file names: a source is cited by its title, not its file."""
QUANTITY = re.compile(r"\b(?:audit|frame|settings|corrections|error|derived|mark)\.[a-z_]+")
"""A live-quantity name shown as text (outside ``{{...}}``)."""
COMMAND = re.compile(r"`lpv-explorer [^`]*`"
                     r"|lpv-explorer [a-z]+(?: --?[a-z0-9-]+(?: [^ ,.;:)]+)?)*")
"""A command line quoted for the reader (its option names are no prose)."""
_SNAKE = re.compile(r"[a-z][a-z0-9]*(?:_[a-z0-9]+)+")
INTERNAL = re.compile(r"\bacc_N\b|\bgrid_(?:\d+|t)\b|\bc0\b|\bY_?00\b|\bSettings\.|"
                      r"\bexplorer\.[a-z]|\bdocs/|\b[a-z]+\.[a-z_]+\.[a-z_]+\b|"
                      r"\b[a-z][a-z0-9]+(?:_[a-z0-9]+)+\b")
"""What the window must not draw for a learner: the model's array names (acc_N, grid_t,
c0, Y00), module, class and file paths, dotted derivation names and any snake_case
identifier (a settings field, a quantity, a function; a one-letter symbol with a subscript,
k_s, is math)."""
_CITATION = re.compile(r"\s*\((?:see )?docs/[A-Z_]+\.md[^)]*\)"
                       r"|[;,]\s*docs/[A-Z_]+\.md(?: \"[^\"]*\")?"
                       r"|\s*\((?:[A-Za-z_]+\.)+[A-Za-z_]+\)")


def field_names() -> set[str]:
    """Names a learner should never have to read: the settings fields and switches
    spelled with an underscore (single words like "fog" are also plain English)."""
    names = {f for f in Settings.__dataclass_fields__ if "_" in f}
    return names | {name for name in Corrections.names() if "_" in name}


FIELDS = field_names()


def learner_texts(lessons: Iterable[Lesson]) -> Iterator[tuple[str, str, str]]:
    """(file name, where, text) of everything a learner reads: summaries, step titles
    and texts, try-this prompts, labels and predictions, figure captions, mark labels."""
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


def prose(text: str) -> str:
    """``text`` without its live numbers, its math and its command lines."""
    text = PLACEHOLDER.sub(" ", text)
    text = MATH.sub(" ", text)
    return COMMAND.sub(" ", text)


def word_problems(text: str) -> list[str]:
    """What in ``text`` is not words for a learner, one phrase each (empty: none)."""
    plain = prose(text)
    problems = []
    tex = RAW_TEX.search(plain)
    if tex:
        problems.append(f"raw TeX outside math: {tex[0]!r} (write it inside $...$)")
    if SOURCE_FILES.search(text):
        problems.append(f"a source cited by its file name: {SOURCE_FILES.search(text)[0]!r}")
    quantity = QUANTITY.search(plain)
    if quantity:
        problems.append(f"a live-quantity name shown as text: {quantity[0]!r} (quote its "
                        f"value as {{{{{quantity[0]}}}}})")
    names = sorted(set(_SNAKE.findall(plain)) & FIELDS)
    if names:
        problems.append(f"settings field names shown to the learner: {', '.join(names)} "
                        "(say what they are in words)")
    return problems


def window_word_problems(text: str) -> list[str]:
    """What in ``text``, a string the window draws for a lesson (a label, a caption, a
    tooltip, a hover), is an internal identifier: :func:`word_problems` and
    :data:`INTERNAL`."""
    problems = word_problems(text)
    found = sorted(set(m[0] for m in INTERNAL.finditer(prose(text))))
    if found:
        problems.append(f"internal identifiers shown to the learner: {', '.join(found)}")
    return problems


@lru_cache(maxsize=4096)
def for_reader(text: str) -> str:
    """``text`` (a setting's or a quantity's documentation) without the citations that
    point a developer at a file or a function (``(docs/MODEL.md "Injection")``,
    ``(rsm.surfel_area)``): the window's tooltips show the rest (kept by text: the
    window asks for each live number's every frame)."""
    return _CITATION.sub("", text)


_WORD = re.compile(r"[\w./]+")


def _word_at(text: str, index: int) -> str:
    """The whole word (path, dotted or snake_case name) of ``text`` around ``index``,
    without the sentence's punctuation after it: ``explorer.lpv.rsm``, not ``explorer.l``."""
    start = index
    while start > 0 and _WORD.fullmatch(text[start - 1]):
        start -= 1
    return _WORD.match(text, start)[0].rstrip("./")


def learner_word_problems(text: str) -> list[str]:
    """What the window's rule (:func:`window_word_problems`) finds in ``text``, a lesson's
    prose, each name once: a settings field or a quantity :func:`word_problems` names is
    not named again as an internal identifier."""
    problems = word_problems(text)
    plain = prose(text)
    quantities = QUANTITY.findall(plain)
    found = sorted({_word_at(plain, m.start()) for m in INTERNAL.finditer(plain)} - FIELDS)
    found = [name for name in found if not any(name in quantity for quantity in quantities)]
    if found:
        problems.append(f"internal identifiers shown to the learner: {', '.join(found)} "
                        "(say what they are in words)")
    return problems


def lesson_word_problems(lessons: Iterable[Lesson]) -> list[str]:
    """Every :func:`learner_word_problems` finding of ``lessons`` (what the window walk
    holds the shipped course to): ``file where: problem``."""
    return [f"{name} {where}: {problem}" for name, where, text in learner_texts(lessons)
            for problem in learner_word_problems(text)]
