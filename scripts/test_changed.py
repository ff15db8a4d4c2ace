"""The unit tests of what changed: the test modules that import (or name) a module, shader
or test helper changed since ``--base`` (default ``main``), in the working tree too, run
in one process. The developer's quick target beside ``bash scripts/check.sh`` (lint, types,
structure, codegen); the whole suite stays the README's test command.

    python scripts/test_changed.py              # changed since main, then run them
    python scripts/test_changed.py --list       # only say which, and why
    python scripts/test_changed.py --base HEAD~3 -- -x --durations=5

The click sessions and the wheel install (minutes each) run only when they are changed
themselves or ``--heavy`` is given.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
HEAVY = ("tests/ui/test_click_window.py", "tests/test_wheel_install.py")
"""Modules of minutes each: run when changed themselves or with --heavy."""


def changed_files(base: str) -> list[str]:
    """Paths changed since ``base`` (committed or not) and new files git does not ignore."""
    def git(*args: str) -> list[str]:
        done = subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True,
                              check=True)
        return [line for line in done.stdout.splitlines() if line]

    merge_base = git("merge-base", base, "HEAD")[0]
    found = git("diff", "--name-only", merge_base) + git("ls-files", "--others",
                                                         "--exclude-standard")
    return sorted({path for path in found if (ROOT / path).exists()})


def patterns_for(path: str) -> list[re.Pattern]:
    """What a test module says when it uses ``path``: its dotted module name (``import
    a.b.c``, ``from a.b.c import``, ``from a.b import c``) or, for a shader, its file."""
    file = Path(path)
    if file.suffix == ".glsl":
        return [re.compile(re.escape(file.name))]
    if file.suffix != ".py":
        return []
    parts = list(file.with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    if parts and parts[0] == "tests":
        return [re.compile(rf"\b(import|from)\s+{re.escape(parts[-1])}\b")]
    dotted = ".".join(parts)
    parent, leaf = ".".join(parts[:-1]), parts[-1]
    found = [re.compile(rf"\b{re.escape(dotted)}\b")]
    if parent:
        found.append(re.compile(rf"from\s+{re.escape(parent)}\s+import\s+[^\n]*\b{leaf}\b"))
    return found


def tests_for(changed: list[str], heavy: bool) -> dict[str, list[str]]:
    """Test module -> the changed paths that select it."""
    modules = sorted(str(path.relative_to(ROOT)) for path in (ROOT / "tests").rglob("test_*.py"))
    texts = {module: (ROOT / module).read_text(encoding="utf-8") for module in modules}
    chosen: dict[str, list[str]] = {}
    for path in changed:
        if path in texts:
            chosen.setdefault(path, []).append(path)
            continue
        for pattern in patterns_for(path):
            for module, text in texts.items():
                if pattern.search(text) and (heavy or module not in HEAVY):
                    reasons = chosen.setdefault(module, [])
                    if path not in reasons:
                        reasons.append(path)
    return dict(sorted(chosen.items()))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default="main", help="compare with this revision (main)")
    parser.add_argument("--list", action="store_true", help="list the modules, run nothing")
    parser.add_argument("--heavy", action="store_true",
                        help="also the click sessions and the wheel install")
    parser.add_argument("pytest_args", nargs="*", help="after --: given to pytest")
    args = parser.parse_args(argv)
    changed = changed_files(args.base)
    chosen = tests_for(changed, args.heavy)
    for module, reasons in chosen.items():
        shown = ", ".join(reasons[:3]) + (f" and {len(reasons) - 3} more"
                                          if len(reasons) > 3 else "")
        print(f"{module}  <- {shown}")
    if not chosen:
        print(f"no test module uses what changed since {args.base} ({len(changed)} files)")
        return 0
    if args.list:
        return 0
    command = [sys.executable, "-m", "pytest", "-p", "no:xdist", "-q", *chosen,
               *args.pytest_args]
    began = time.monotonic()
    status = subprocess.call(command, cwd=ROOT)
    print(f"{len(chosen)} test modules in {time.monotonic() - began:.0f} s")
    return status


if __name__ == "__main__":
    sys.exit(main())
