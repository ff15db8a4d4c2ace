"""The panels' background GPU work (``runtime.services.tasks``, e.g. the Error panel's
reference), run in what a frame's budget leaves after the pipelines."""

from __future__ import annotations

import sys
import time
import traceback
from typing import TYPE_CHECKING

from explorer.gl.context import use_screen
from explorer.ui.controller_state import ControllerStatus, WorkUnit

if TYPE_CHECKING:
    import moderngl

    from explorer.ui.state import AppState

MIN_TASK_MS = 2.0
"""Background tasks run when at least this much of the budget is left."""


def run_tasks(ctx: moderngl.Context, state: AppState, left_ms: float,
              status: ControllerStatus) -> None:
    """Advance the tasks in ``left_ms``, shared by those that have work (an idle one is
    still called: it may start some, e.g. the Error panel's measurement of a new
    configuration); a task that fails is said in Messages and dropped."""
    tasks = state.runtime.services.tasks
    if not tasks or left_ms < MIN_TASK_MS:
        return
    share = left_ms / max(sum(bool(task.running) for task in tasks), 1)
    for task in list(tasks):
        began = time.perf_counter()
        try:
            task.advance(ctx, share / 1e3)
        except Exception as exc:  # noqa: BLE001 - shown in the window, the app goes on
            state.notify(f"{type(task).__name__} failed: {exc}", "error")
            traceback.print_exception(exc, file=sys.stderr)
            task.release()
            tasks.remove(task)
        finally:
            use_screen(ctx)
        if task.running:
            status.work.append(WorkUnit("task", type(task).__name__,
                                        (time.perf_counter() - began) * 1e3))
