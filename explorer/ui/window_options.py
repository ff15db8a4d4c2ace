"""How a window is opened (:class:`~explorer.ui.app.App`'s options): its size, whether it
is shown, persisted, paced by events, and which pipeline it runs."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from explorer.ui.frame_pacing import IDLE_TIMEOUT_S


@dataclass(frozen=True)
class WindowOptions:
    """The options of one window; the defaults are the interactive explorer's."""

    width: int | None = None
    """Window width in pixels; None: the size saved last time (fitted to the monitor)."""
    height: int | None = None
    visible: bool = True
    vsync: bool = True
    persist_settings: bool = True
    """Read the saved settings and layout at start and write them at close."""
    pipeline_class: Callable | None | object = ...
    """The Pipeline class (``...``: explorer.lpv.pipeline's), or None for a window without
    a pipeline (panels only: the window tests)."""
    wait_when_idle: bool | None = None
    """Wait for events instead of drawing when nothing changed (None: for a visible window;
    a hidden one is scripted and draws every :meth:`App.frame`)."""
    idle_timeout_s: float = IDLE_TIMEOUT_S
    """The longest such wait."""
    test_engine: bool = False
    """Start Dear ImGui Test Engine in the window (explorer/ui/test_engine.py)."""
    headless: bool = False
    """No display needed (glfw's null platform with EGL): exports and scripts."""
    partial_paint: bool = True
    """Paint imgui's lists only where they changed (explorer/ui/partial_paint.py); False:
    the whole window every frame (``--repaint-all``, a check of the partial painting)."""

    @property
    def waits_when_idle(self) -> bool:
        return self.visible if self.wait_when_idle is None else bool(self.wait_when_idle)
