"""Module size: no module of the window (``explorer/ui/``) is over 600 lines, and any module
over 600 lines anywhere opens with a docstring that indexes it (names its own parts), so a
reader finds their way in a long file from its top."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MAX_LINES = 600
FOLDERS = ("explorer", "derivations", "tests", "scripts")
INDEX_NAMES = 2
"""How many of its own top-level definitions a long module's docstring names at least."""


def _lines(path: Path) -> int:
    return len(path.read_text(encoding="utf-8").splitlines())


def _python_files() -> list[Path]:
    return sorted(path for folder in FOLDERS for path in (ROOT / folder).rglob("*.py"))


def _generated(docstring: str) -> bool:
    """A file ``python -m derivations.codegen`` writes: its docstring says so."""
    return "GENERATED FILE" in docstring


def _top_level_names(tree: ast.Module) -> set[str]:
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names.update(t.id for t in targets if isinstance(t, ast.Name))
    return names


def _named_in(docstring: str, names: set[str]) -> set[str]:
    """The names the docstring quotes as code (``name``, `name` or :role:`name`)."""
    quoted = set(re.findall(r"`+(?:~?[\w.]+\.)?(\w+)(?:\(\))?`+", docstring))
    return quoted & names


def index_problem(path: Path) -> str | None:
    """Why a long module's opening docstring is not an index of it; None when it is."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docstring = ast.get_docstring(tree) or ""
    if _generated(docstring):
        return None
    if not docstring:
        return "no module docstring"
    named = _named_in(docstring, _top_level_names(tree))
    if len(named) < INDEX_NAMES:
        return (f"its docstring names {len(named)} of its own definitions "
                f"({', '.join(sorted(named)) or 'none'}); an index names {INDEX_NAMES} or more")
    return None


def test_no_window_module_is_over_600_lines():
    long = {str(path.relative_to(ROOT)): _lines(path)
            for path in (ROOT / "explorer" / "ui").rglob("*.py") if _lines(path) > MAX_LINES}
    assert not long, f"split by responsibility (a module with one job each): {long}"


def test_every_long_module_opens_with_an_index():
    problems = {str(path.relative_to(ROOT)): problem for path in _python_files()
                if _lines(path) > MAX_LINES and (problem := index_problem(path))}
    assert not problems, problems


def test_an_index_names_the_module_s_own_definitions(tmp_path):
    path = tmp_path / "long.py"
    body = "\n".join(f"def part_{k}():\n    return {k}\n" for k in range(3))
    path.write_text('"""A long module that says nothing of its parts."""\n' + body)
    assert "names 0" in index_problem(path)
    path.write_text('"""Its parts: :func:`part_0` reads, ``part_2()`` writes."""\n' + body)
    assert index_problem(path) is None
    path.write_text(body)
    assert index_problem(path) == "no module docstring"
