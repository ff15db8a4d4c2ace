"""A drawn frame by phase (explorer/ui/frame_profile.py): each phase's wall and CPU time
from the previous mark, and the optional finish before each phase ends."""

from __future__ import annotations

import time

from explorer.ui.frame_profile import PHASES, FrameProfile


def test_each_phase_holds_the_time_since_the_last_mark_and_finishes_first():
    finished: list[str] = []
    profile = FrameProfile(finish=lambda: finished.append("finish"))
    profile.start()
    time.sleep(0.1)
    profile.mark("update")
    deadline = time.process_time() + 0.02
    while time.process_time() < deadline:     # CPU spent in this phase alone
        pass
    profile.mark("panels")
    assert list(profile.wall_ms) == ["update", "panels"] == list(PHASES[:2])
    # a sleep spends wall time, hardly any CPU (the process's other threads may run a
    # little on a loaded machine: half the wall time is the bound)
    assert profile.wall_ms["update"] >= 99.0
    assert profile.cpu_ms["update"] < 0.5 * profile.wall_ms["update"]
    assert profile.cpu_ms["panels"] >= 19.0
    assert finished == ["finish", "finish"]
    assert profile.summary().startswith("update ") and " · panels " in profile.summary()
    profile.start()                           # a new frame forgets the last one's phases
    assert profile.wall_ms == {} and profile.cpu_ms == {}
