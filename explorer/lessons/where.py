"""Where in a lesson file a :class:`~explorer.lessons.model.LessonError` points: the line
of the key it names, found in the file's text, so that an author's editor can jump to it
(``01-light.toml:14, step 2 ('Turn it', field 'try_this[0].value'): ...``).

The reader checks parsed TOML, which keeps no line numbers; this module finds the key
again by the TOML layout the lessons use: ``[[steps]]`` headers, ``[[steps.try_this]]``
and ``[steps.settings]`` tables below them, ``key = value`` lines. A key written some
other way (an inline table) falls back to the line of its table or of its step. An error
about a ``{{...}}`` in a text (a live value's name, a marker) points at the line of the
text that holds it.
"""

from __future__ import annotations

import re

from explorer.lessons.model import LessonError

_HEADER = re.compile(r"^\s*\[\[?\s*([A-Za-z0-9_.]+)\s*\]\]?\s*(?:#.*)?$")
_FIELD_PART = re.compile(r"([A-Za-z0-9_]+)(?:\[(\d+)\])?")


def _headers(lines: list[str]) -> list[tuple[int, str]]:
    """(line index, table name) of every table header, outside multi-line strings."""
    found, quote = [], None
    for index, line in enumerate(lines):
        if quote is None:
            match = _HEADER.match(line)
            if match:
                found.append((index, match.group(1)))
        for mark in ("'''", '"""'):
            if line.count(mark) % 2 and quote in (None, mark):
                quote = mark if quote is None else None
    return found


def _key_line(lines: list[str], start: int, end: int, key: str) -> int | None:
    pattern = re.compile(rf"^\s*{re.escape(key)}\s*=")
    for index in range(start, end):
        if pattern.match(lines[index]):
            return index
    return None


def _table(headers: list[tuple[int, str]], name: str, start: int, end: int,
           nth: int = 0) -> tuple[int, int] | None:
    """(header line, end) of the ``nth`` table ``name`` between lines start and end."""
    inside = [(i, n) for i, n in headers if start <= i < end]
    hits = [k for k, (_, n) in enumerate(inside) if n == name]
    if nth >= len(hits):
        return None
    k = hits[nth]
    stop = inside[k + 1][0] if k + 1 < len(inside) else end
    return inside[k][0], stop


def line_of(text: str, step: int | None, field: str | None) -> int | None:
    """The 1-based line of ``field`` (a reader's field path, ``try_this[0].value``) in
    step ``step`` (1-based; None: the lesson's own keys) of the lesson ``text``."""
    lines = text.splitlines()
    headers = _headers(lines)
    steps = [i for i, name in headers if name == "steps"]
    if step is None:
        start, end, prefix = 0, steps[0] if steps else len(lines), ""
    elif step <= len(steps):
        start = steps[step - 1]
        end = steps[step] if step < len(steps) else len(lines)
        prefix = "steps."
    else:
        return None
    parts = [] if not field else [_FIELD_PART.fullmatch(p) for p in field.split(".")]
    if not parts or any(p is None for p in parts):
        return start + 1 if step is not None else None
    head, nth = parts[0].group(1), parts[0].group(2)
    rest = [p.group(1) for p in parts[1:]]
    table = _table(headers, prefix + head, start + (step is not None), end,
                   int(nth) if nth is not None else 0)
    if table is not None:
        found = _key_line(lines, table[0] + 1, table[1], rest[0]) if rest else None
        return (found if found is not None else table[0]) + 1
    own_end = next((i for i, _ in headers if start < i < end), end)
    found = _key_line(lines, start + (step is not None), own_end, head)
    if found is None:
        return start + 1 if step is not None else None
    return found + 1


def _marker_line(lines: list[str], key_line: int, reason: str) -> int | None:
    """The 1-based line, from the key's line on, of the ``{{...}}`` a reason starts with
    (``{{frame.cellsize}}: no live quantity ...``), before the next table; None when the
    reason quotes none or the text spells it otherwise."""
    match = re.match(r"\{\{([^{}]+)\}\}", reason)
    if match is None:
        return None
    # the reason quotes the name (and format) as the text wrote it, without spaces
    pattern = re.compile(r"\{\{\s*" + re.escape(match.group(1).strip()))
    for index in range(key_line - 1, len(lines)):
        if index >= key_line and _HEADER.match(lines[index]):
            return None
        if pattern.search(lines[index]):
            return index + 1
    return None


def located(error: LessonError, text: str) -> LessonError:
    """``error`` with the line of its key in ``text`` (the same error when it has a line
    already or the key cannot be found)."""
    if error.line is not None:
        return error
    line = line_of(text, error.step, error.field)
    if line is None:
        return error
    line = _marker_line(text.splitlines(), line, error.reason) or line
    return LessonError(error.path, error.reason, step=error.step, step_title=error.step_title,
                       field=error.field, line=line)
