"""No module in explorer/ probes a declared field: a ``getattr``/``hasattr`` whose name (a
string literal) is a field of FrameResult, LevelResult, the Runtime or one of its parts
reads an attribute the type always has, or, asked of the wrong object, never finds it
(as ``hasattr(runtime, "gl_renderer")`` did once the field moved to ``runtime.services``)."""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

from explorer.lpv.frame import FrameResult, LevelResult
from explorer.ui.state import RUNTIME_PARTS, Runtime

ROOT = Path(__file__).resolve().parents[2]
TYPES = (FrameResult, LevelResult, Runtime, *RUNTIME_PARTS.values())

ALLOWED = {
    ("explorer/ui/scene_reload.py", "warnings"):
        "a Scene's own warnings (explorer.scene.model), not FrameResult.warnings",
    ("explorer/ui/figures/pipeline_overview.py", "vpls"):
        "also reads explorer.ui.lesson_lint.twin_result's stand-in (settings and audit "
        "only), which lesson checks run without a GL context",
}
"""(path, name) -> why the probe there is not of the declared field."""


def _declared() -> dict[str, list[str]]:
    owners: dict[str, list[str]] = {}
    for cls in TYPES:
        for entry in dataclasses.fields(cls):
            owners.setdefault(entry.name, []).append(cls.__name__)
    return owners


def probes(source: str, names: dict[str, list[str]]) -> list[tuple[int, str, str]]:
    """(line, call, name) of each getattr/hasattr in ``source`` that names one of ``names``."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) \
                and node.func.id in ("getattr", "hasattr") and len(node.args) >= 2 \
                and isinstance(node.args[1], ast.Constant) and node.args[1].value in names:
            found.append((node.lineno, ast.unparse(node), node.args[1].value))
    return found


def test_no_module_probes_a_declared_field():
    names, wrong = _declared(), []
    for path in sorted((ROOT / "explorer").rglob("*.py")):
        relative = path.relative_to(ROOT).as_posix()
        for line, call, name in probes(path.read_text(encoding="utf-8"), names):
            if (relative, name) not in ALLOWED:
                wrong.append(f"{relative}:{line}: {call} ({'/'.join(names[name])}.{name})")
    assert not wrong, "probes of declared fields (read the field):\n" + "\n".join(wrong)


def test_every_allowance_still_matches_a_probe():
    names = _declared()
    for (relative, name), reason in ALLOWED.items():
        assert reason
        found = probes((ROOT / relative).read_text(encoding="utf-8"), names)
        assert any(hit == name for _, _, hit in found), f"{relative}: no {name} probe left"


def test_the_scan_sees_the_renderer_probe_of_the_old_interaction_driver():
    old = ('figures["renderer"] = app.state.runtime.services.gl_renderer if hasattr(\n'
           '    app.state.runtime, "gl_renderer") else ""\n')
    assert [name for _, _, name in probes(old, _declared())] == ["gl_renderer"]
