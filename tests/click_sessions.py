"""The click sessions tests/click_app.py runs: each a window state to start from and a
test function that drives the window through its controls (explorer/ui/test_engine.py)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Session:
    state: Callable
    run: Callable


def _small_state(**changes):
    from explorer.lpv.settings import Settings
    from explorer.ui.state import AppState

    state = AppState(settings=Settings(grid_size=8, iterations=3, rsm_size=32),
                     render_scale=0.25)
    for name, value in changes.items():
        setattr(state, name, value)
    return state


def explore(c) -> None:
    import time
    t = time.monotonic()
    c.settle_input(5)
    print("lesson list exists", c.exists("//Lesson/**/01   What a light propagation volume does"))
    c.click("//Lesson/**/01   What a light propagation volume does", "open lesson 1")
    print("opened", c.state.lesson_session.lesson.id, time.monotonic() - t)
    print("scroll", c.scroll_y("//Lesson/article"))
    c.click("//Lesson/**/< All lessons")
    print("after all", c.state.lesson_session.lesson, time.monotonic() - t)
    c.screenshot("explore")


SESSIONS = {
    "explore": Session(_small_state, explore),
}
