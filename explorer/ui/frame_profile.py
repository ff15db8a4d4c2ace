"""One drawn frame of the window by phase (:class:`FrameProfile`): the pipelines' update,
the panels built, imgui's draw lists rendered, the swap; wall-clock and CPU
milliseconds each (``bench --interactive`` prints the slowest frames' profiles).

A software renderer (llvmpipe) rasterises what a phase queued when something later needs
it (a texture sampled, the swap), so a phase's wall time can hold an earlier phase's
GPU work. With ``finish`` each phase ends with ``glFinish``: its own GPU work lands in it
(a diagnosis: the waits cost a GPU its overlap)."""

from __future__ import annotations

import time
from collections.abc import Callable

PHASES = ("update", "panels", "render", "swap")
"""The phases of a drawn frame, in order (:meth:`App.frame <explorer.ui.app.App.frame>`):
events and the pipelines' work, the panels' imgui calls, imgui's draw lists rendered over
the cleared window, the buffers swapped."""


class FrameProfile:
    """The phases of the frame being drawn: :meth:`start`, then :meth:`mark` at the end
    of each phase."""

    def __init__(self, finish: Callable[[], None] | None = None) -> None:
        """``finish``: called before each phase's end is taken (``ctx.finish``: each
        phase's GPU work lands in it); None: no wait."""
        self.finish = finish
        self.wall_ms: dict[str, float] = {}
        """Phase -> wall-clock milliseconds of the last frame profiled."""
        self.cpu_ms: dict[str, float] = {}
        """Phase -> CPU milliseconds of the process (all threads: the software
        renderer's too) in the last frame profiled."""
        self._wall = self._cpu = 0.0

    def start(self) -> None:
        self.wall_ms, self.cpu_ms = {}, {}
        self._wall, self._cpu = time.perf_counter(), time.process_time()

    def mark(self, phase: str) -> None:
        """``phase`` ends now (after ``finish`` when set)."""
        if self.finish is not None:
            self.finish()
        wall, cpu = time.perf_counter(), time.process_time()
        self.wall_ms[phase] = (wall - self._wall) * 1e3
        self.cpu_ms[phase] = (cpu - self._cpu) * 1e3
        self._wall, self._cpu = wall, cpu

    def summary(self) -> str:
        """``update 12.0 (cpu 20.1) · panels …`` of the last frame profiled."""
        return " · ".join(f"{phase} {ms:.1f} (cpu {self.cpu_ms.get(phase, 0.0):.1f})"
                          for phase, ms in self.wall_ms.items())
