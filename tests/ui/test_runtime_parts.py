"""The window's panels read the per-frame runtime by its parts: every
``runtime.X`` / ``rt.X`` in explorer/ names a part of :class:`explorer.ui.state.Runtime`
or one of its own members, so a panel that reads a field the runtime no longer forwards
fails here, not only in the click suite that happens to draw it."""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

from explorer.ui.state import RUNTIME_PARTS, Runtime

ROOT = Path(__file__).resolve().parents[2]
NAMES = ("runtime", "rt")


def _members() -> set[str]:
    fields = {entry.name for entry in dataclasses.fields(Runtime)}
    return fields | {name for name in vars(Runtime) if not name.startswith("_")}


def test_every_runtime_read_names_a_part_or_a_member():
    members, wrong = _members(), []
    for path in sorted((ROOT / "explorer").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Attribute) \
                    and node.value.attr == "runtime" and node.attr not in members:
                wrong.append(f"{path.relative_to(ROOT)}:{node.lineno}: runtime.{node.attr}")
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
                    and node.value.id in NAMES and node.attr not in members:
                wrong.append(f"{path.relative_to(ROOT)}:{node.lineno}: "
                             f"{node.value.id}.{node.attr}")
    assert not wrong, "reads of the runtime past its parts:\n" + "\n".join(wrong)


def test_the_parts_are_the_runtime_fields():
    assert set(RUNTIME_PARTS) <= _members()
    for part, cls in RUNTIME_PARTS.items():
        assert dataclasses.fields(Runtime)[list(RUNTIME_PARTS).index(part)].name == part
        assert not hasattr(Runtime(), dataclasses.fields(cls)[0].name), (
            f"{cls.__name__}'s fields are read through runtime.{part}, not forwarded")
