"""The README's Python examples run as a reader pastes them: every ```python block, in
order, in one fresh interpreter (a later block reads what an earlier one made), and each
output the README writes down (a ``# ...`` line after a ``print``, or a ``print(...)  #
(...)`` / ``# [...]`` comment that starts with a tuple or list) is what it prints."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _blocks() -> list[str]:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    return re.findall(r"^```python\n(.*?)^```", text, re.M | re.S)


def _stated_outputs(code: str) -> list[str]:
    """The outputs the README states exactly: a comment line right after a ``print`` line,
    or a print's own comment that is a Python tuple of strings."""
    stated, lines = [], code.splitlines()
    for before, line in zip(lines, lines[1:]):
        if before.lstrip().startswith("print(") and re.match(r"\s*# \(", line):
            stated.append(line.split("# ", 1)[1].strip())
    for line in lines:
        found = re.match(r"\s*print\(.*\)\s+# (\('.*'\))\s*$", line)
        if found:
            stated.append(found.group(1))
    return stated


def test_the_readme_python_examples_run_and_print_what_they_say(tmp_path):
    blocks = _blocks()
    assert len(blocks) >= 2, "the README's scripting section lost its examples"
    code = "\n".join(blocks)
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                          text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    printed = done.stdout.splitlines()
    stated = _stated_outputs(code)
    assert stated, "no stated output found to hold the examples to"
    for line in stated:
        assert line in printed, f"the README says {line!r}; the example printed:\n{done.stdout}"
