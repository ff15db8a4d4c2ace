"""The course's glossary: recurring terms (VPL, flux in flight, clamp gain, geometry
volume, ...) and what they mean, shown when the reader hovers the term in a lesson.

Data, like the lessons: ``lessons/glossary.toml`` holds one ``[[terms]]`` table per term::

    [[terms]]
    term = "flux in flight"          # lower case unless it is an acronym
    also = ["light in flight"]       # other spellings and plurals that mean it (optional)
    meaning = "The flux a propagation step moves: ..."   # one paragraph, plain words

:func:`load_glossary` validates the file; :func:`matches` finds the terms in a run of
words (longest spelling first, case-insensitive, punctuation around a word ignored).
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

GLOSSARY_FILE = "glossary.toml"
"""The glossary's file in the lessons folder (not a lesson: ``load_all`` skips it)."""
MAX_MEANING = 400
KEYS = ("term", "also", "meaning")
PUNCTUATION = ".,;:!?()[]\"'*_`"
"""What may stand around a term's words (a term matches without it)."""


class GlossaryError(ValueError):
    pass


@dataclass(frozen=True)
class Term:
    term: str
    meaning: str
    also: tuple[str, ...] = ()

    @property
    def spellings(self) -> tuple[str, ...]:
        return (self.term, *self.also)


def load_glossary(directory: Path | str | None = None) -> tuple[Term, ...]:
    """The glossary of the lessons in ``directory`` (default: the shipped lessons); ()
    when there is none. GlossaryError names the file and the entry otherwise."""
    from explorer.resources import lesson_dir
    from explorer.safe_files import UserFileError, parse_toml, read_text

    path = (lesson_dir() if directory is None else Path(directory)) / GLOSSARY_FILE
    if not path.exists():
        return ()
    try:        # a FIFO or a huge file is refused, never waited on or read whole
        data = parse_toml(read_text(path, "lesson"), path)
    except UserFileError as exc:
        raise GlossaryError(str(exc)) from None
    except tomllib.TOMLDecodeError as exc:
        raise GlossaryError(f"{path}: {exc}") from None
    if set(data) != {"terms"} or not isinstance(data["terms"], list):
        raise GlossaryError(f"{path}: expected only a list of [[terms]] tables")
    terms: list[Term] = []
    seen: dict[str, str] = {}
    for index, table in enumerate(data["terms"]):
        where = f"{path}: terms[{index}]"
        if not isinstance(table, dict):
            raise GlossaryError(f"{where}: must be a table")
        unknown = set(table) - set(KEYS)
        if unknown:
            raise GlossaryError(f"{where}: unknown field {sorted(unknown)[0]!r}; expected "
                                f"{list(KEYS)}")
        term, meaning, also = table.get("term"), table.get("meaning"), table.get("also", [])
        if not isinstance(term, str) or not term.strip():
            raise GlossaryError(f"{where}.term: must be a word or a few words")
        if not isinstance(meaning, str) or not meaning.strip() or len(meaning) > MAX_MEANING \
                or "\n\n" in meaning.strip():
            raise GlossaryError(f"{where}.meaning: must be one paragraph of at most "
                                f"{MAX_MEANING} characters")
        if "$" in meaning or "\\" in meaning:
            raise GlossaryError(f"{where}.meaning: plain words, no math (a tooltip shows it)")
        if not isinstance(also, list) or not all(isinstance(a, str) and a.strip()
                                                 for a in also):
            raise GlossaryError(f"{where}.also: must be a list of spellings")
        entry = Term(term.strip(), " ".join(meaning.split()), tuple(a.strip() for a in also))
        for spelling in entry.spellings:
            key = spelling.lower()
            if key in seen:
                raise GlossaryError(f"{where}: {spelling!r} is already a spelling of "
                                    f"{seen[key]!r}")
            seen[key] = entry.term
        terms.append(entry)
    return tuple(terms)


def _bare(word: str) -> str:
    return word.strip(PUNCTUATION).lower()


_by_first_word: tuple[tuple[Term, ...], dict[str, list]] | None = None
"""The last glossary :func:`matches` indexed, and its index (the article matches every
paragraph of the text on screen each frame, always against the same glossary)."""


def _spellings_by_first_word(terms: tuple[Term, ...]) -> dict[str, list]:
    """First word -> [(a spelling's words, its term)], the longest spellings first (of
    equal length, in the glossary's order)."""
    global _by_first_word
    if _by_first_word is None or _by_first_word[0] is not terms:
        index: dict[str, list] = {}
        for parts, term in sorted(((tuple(s.lower().split()), t) for t in terms
                                   for s in t.spellings), key=lambda item: -len(item[0])):
            if parts:
                index.setdefault(parts[0], []).append((parts, term))
        _by_first_word = (terms, index)
    return _by_first_word[1]


def matches(words: list[str], terms: tuple[Term, ...]) -> list[tuple[int, int, Term]]:
    """(first word, word count, term) for each glossary term in ``words`` (a run of text
    split at spaces), left to right, the longest spelling winning where two overlap."""
    spellings = _spellings_by_first_word(terms)
    bare = [_bare(w) for w in words]
    found, index = [], 0
    while index < len(words):
        for parts, term in spellings.get(bare[index], ()):
            if tuple(bare[index:index + len(parts)]) == parts:
                found.append((index, len(parts), term))
                index += len(parts)
                break
        else:
            index += 1
    return found


def defined_in(text: str, terms: tuple[Term, ...]) -> set[str]:
    """The terms that occur in ``text`` (words split at white space)."""
    return {term.term for _, _, term in matches(re.split(r"\s+", text), terms)}
