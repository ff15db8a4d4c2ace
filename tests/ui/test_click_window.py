"""The whole window clicked through its controls with Dear ImGui Test Engine
(explorer/ui/test_engine.py), on glfw's null platform (Xvfb where glfw has none): each
session of tests/click_sessions.py runs in a child process (a window's context cannot
become current in a process that made the tests' EGL context current; an imgui assert
aborts the child, not pytest) and reports every control it clicked and every check that
failed."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from window_cases import display_problem, run_child

_PROBLEM = display_problem()
pytestmark = pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))


def _lessons():
    from explorer.lessons import load_all

    lessons, errors = load_all(check_formula=None)
    assert not errors
    return lessons


def _least_clicks(session: str) -> int:
    """The clicks a session cannot pass with fewer (every lesson, step, try-this...)."""
    lessons = _lessons()
    steps = sum(len(lesson.steps) for lesson in lessons)
    tries = sum(len(step.try_this) for lesson in lessons for step in lesson.steps)
    from explorer.lpv.corrections import CORRECTIONS
    from explorer.ui.layout import PANELS

    return {"lessons": 2 * len(lessons) + (steps - len(lessons)) + (len(lessons) - 1),
            "return": 12,
            "try-this": 2 * tries,
            "figures": 40,
            "window": 2 * len(CORRECTIONS) + 2 * len(PANELS) + 3 + 4,
            }[session]


def _run_session(name: str, tmp_path: Path) -> dict:
    done = run_child(["tests/click_app.py", name], tmp_path, timeout=1500)
    # the engine's own log shares stdout and may leave a colour escape before the report
    lines = [line[line.index('{"session"'):] for line in done.stdout.splitlines()
             if '{"session"' in line]
    assert lines, (f"the click session {name} ended without a report (exit {done.returncode})"
                   f":\n{done.stderr[-4000:]}")
    return json.loads(lines[-1])


@pytest.mark.parametrize("session", ["lessons", "return", "try-this", "figures", "window"])
def test_click_session(session: str, tmp_path: Path) -> None:
    report = _run_session(session, tmp_path)
    problems = "\n".join(report["problems"])
    assert report["passed"], f"{session}: {report['status']}\n{problems}"
    assert report["clicks"] >= _least_clicks(session), report["clicks"]
