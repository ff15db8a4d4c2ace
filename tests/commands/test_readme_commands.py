"""Every ``lpv-explorer`` command line the README shows is one the program accepts: its
options exist and their values parse (argparse), and for the commands that render, the
options make valid Settings (the schema's checks and the rules between fields, e.g.
``--bounces 2`` needs a geometry volume). Nothing is rendered: a reader's first paste
must not end in "unrecognized arguments" or a refused setting."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SETTINGS_COMMANDS = ("render", "compare", "bench", "stability", "export-mitsuba")
"""Commands whose options are the Settings (explorer/commands/options.py)."""


def _readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    lines = []
    for block in re.findall(r"^```bash\n(.*?)^```", text, re.M | re.S):
        for line in block.splitlines():
            line = line.split("   #", 1)[0].split(" # ", 1)[0].strip()
            if line.startswith("lpv-explorer "):
                # what follows a redirect or a second command is the shell's, not ours
                lines.append(re.split(r"\s(?:>|&&|\|)\s", line)[0].strip())
    return lines


COMMANDS = _readme_commands()


def test_the_readme_shows_commands():
    assert len(COMMANDS) >= 30, COMMANDS


@pytest.mark.parametrize("line", COMMANDS)
def test_a_readme_command_line_is_accepted(line: str, capsys):
    from explorer.cli import _parse, build_parser
    from explorer.commands import options

    argv = shlex.split(line)[1:]
    try:
        args = _parse(build_parser(), argv)
    except SystemExit:
        pytest.fail(f"{line}\n{capsys.readouterr().err}")
    if args.command in SETTINGS_COMMANDS and not getattr(args, "lesson", None):
        options.settings_from_args(args)
