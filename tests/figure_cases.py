"""Data the figure tests share: FrameResult stand-ins built from the numpy twin, and the
one-figure window that plots them (both from explorer/ui/lesson_lint.py, which
``lpv-explorer lessons --lint`` uses too)."""

from __future__ import annotations

from explorer.ui.lesson_lint import figure_window
from explorer.ui.lesson_lint import twin_result as synthetic_result

__all__ = ["figure_window", "synthetic_result"]
