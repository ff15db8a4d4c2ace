"""The window fixes glibc's mmap threshold, so a large block freed goes back to the system,
and hands the heaps' free pages back each time it falls idle."""

from __future__ import annotations

import ctypes
import ctypes.util

import numpy as np
import pytest

from explorer.ui import memory


def _resident_kib() -> int:
    with open("/proc/self/status", encoding="ascii") as status:
        return next(int(line.split()[1]) for line in status if line.startswith("VmRSS:"))


def test_a_freed_grid_sized_block_leaves_resident_memory():
    """After one 12 MiB block is freed glibc would serve the next from its heap (its
    dynamic threshold); with the threshold fixed each comes from mmap and goes back."""
    if ctypes.util.find_library("c") is None or not memory.return_large_blocks():
        pytest.skip("not glibc")
    size = 12 << 20
    np.ones(size // 8).sum()                     # freed once: the dynamic rule's trigger
    before = _resident_kib()
    for _ in range(8):
        block = np.ones(size // 8)
        block.sum()
        del block
    assert _resident_kib() - before < 4 << 10    # under 4 MiB stays resident


def test_the_heaps_free_pages_go_back_when_asked():
    """Blocks below the mmap threshold freed in the middle of the heap (a kept block
    after each few) stay resident until :func:`memory.give_back_free` hands them back."""
    if ctypes.util.find_library("c") is None or not memory.return_large_blocks():
        pytest.skip("not glibc")
    blocks = [bytes(100 << 10) for _ in range(600)]     # 60 MiB in 100 KiB blocks
    kept = blocks[::20]                                  # one in 20 pins the heap
    del blocks
    before = _resident_kib()
    assert memory.give_back_free()
    assert before - _resident_kib() > 30 << 10           # over 30 of the 57 MiB freed
    assert len(kept) == 30


def test_the_window_gives_the_free_pages_back_once_each_time_it_falls_idle(monkeypatch):
    """A frame with nothing to do after work trims the heaps; the idle frames after it
    do not, until work comes again."""
    from window_cases import display_problem

    from explorer.ui.app import App
    from explorer.ui.window_options import WindowOptions

    if display_problem() is not None:
        pytest.skip(str(display_problem()))
    calls = []
    monkeypatch.setattr(memory, "give_back_free", lambda: calls.append(1) or True)
    app = App(options=WindowOptions(width=320, height=200, visible=False, vsync=False,
                                    persist_settings=False, pipeline_class=None,
                                    wait_when_idle=True, idle_timeout_s=0.01))
    try:
        for _ in range(8):
            app.frame()
        assert len(calls) == 1
        app.state.update(exposure=app.state.settings.exposure + 0.5)   # work, then idle
        for _ in range(8):
            app.frame()
        assert len(calls) == 2
    finally:
        app.close()


def test_a_window_falling_idle_releases_what_only_a_job_uses(monkeypatch):
    """Once the frame converged and the window falls idle it releases its pipelines'
    ping and pong grids, injection layers and taken read-backs (Pipeline.
    release_between_runs) before trimming the heaps, once per fall; the next change makes
    them anew and its frame is the same as a window that kept them."""
    from window_cases import display_problem

    import explorer.lpv.passes.propagate as propagate_pass
    from explorer.lpv.settings import Settings
    from explorer.ui.app import App
    from explorer.ui.state import AppState
    from explorer.ui.window_options import WindowOptions

    if display_problem() is not None:
        pytest.skip(str(display_problem()))
    monkeypatch.setattr(propagate_pass, "SPARE_GRID_BYTES", 0)      # every grid is large
    released = []
    original = memory.release_between_runs

    def counted(sides) -> int:
        released.append(original(sides))
        return released[-1]

    monkeypatch.setattr(memory, "release_between_runs", counted)
    settings = Settings(grid_size=8, iterations=4, rsm_size=32, width=96, height=64)
    app = App(AppState(settings=settings),
              WindowOptions(width=640, height=480, visible=False, vsync=False,
                            persist_settings=False, wait_when_idle=True,
                            idle_timeout_s=0.01))
    try:
        for _ in range(400):
            app.frame()
            if app.idle_falls:
                break
        assert app.idle_falls == 1 and len(released) == 1 and released[0] > 0
        first = app.state.runtime.frame.result
        app.state.update(iterations=5)
        for _ in range(400):
            app.frame()
            if app.idle_falls == 2:
                break
        # the propagation ran again, not the injection: its ping, pong and read-back
        assert app.idle_falls == 2 and 0 < released[1] < released[0]
        again = app.state.runtime.frame.result
        assert again is not first and again.settings.iterations == 5
    finally:
        app.close()
