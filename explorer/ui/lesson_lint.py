"""What a lesson's figures and marks are held to, measured in a real window: every
inline figure fits the article column at the window sizes the course is read at, and
every labelled mark is in view of its step's camera. The shipped course's tests
(tests/ui/test_figures_fit.py, tests/lessons/test_lesson_checks.py) and ``lpv-explorer
lessons --lint`` run these same functions."""

from __future__ import annotations

from collections.abc import Iterable
from types import SimpleNamespace
from typing import Any

WINDOWS = ((1280, 720), (1600, 900))
"""Window sizes a figure must fit the column of (the smallest the layout is made for, and
the default)."""
SLACK_PX = 1.0
"""Rounding of imgui's layout (item rectangles are floats)."""
MARK_VIEW = 96
"""Pixels of the tiny frame the marks are placed in (only the camera matters)."""


def column_width(window_width: int) -> float:
    """The article's text column in a window this wide: the article dock of the default
    layout, less the window's padding on both sides and the scroll bar, laid out by
    explorer/ui/article.py's column_width (imgui's style must be set: a window is open)."""
    from imgui_bundle import imgui

    from explorer.ui import article
    from explorer.ui.layout import column_widths

    style = imgui.get_style()
    dock = column_widths(float(window_width))[0]
    return article.column_width(dock - 2.0 * style.window_padding.x - style.scrollbar_size)


def lesson_figures(lessons: Iterable[Any]) -> list[tuple[str, Any]]:
    """(``lesson/step/figure``, spec) of every inline figure of ``lessons``."""
    return [(f"{lesson.id}/{step.number}/{spec.instance_id}", spec)
            for lesson in lessons for step in lesson.steps for spec in step.figures]


def twin_result(corrections: str, iterations: int = 6) -> Any:
    """A FrameResult stand-in (settings and an EnergyAudit) from the numpy twin: what the
    audit figures plot when no window runs the pipeline."""
    from explorer.lpv.audit import EnergyAudit
    from explorer.lpv.settings import PRESETS, Settings
    from explorer.ui.figures import make_figure, propagation_stepper

    params = make_figure("propagation-stepper", iterations=iterations,
                         corrections=corrections).params
    audit = propagation_stepper.run(params).audit
    full = EnergyAudit.from_grid_audit(audit, rsm=audit.injected,
                                       gathered=0.4 * audit.injected)
    return SimpleNamespace(settings=Settings(corrections=PRESETS[corrections]), audit=full)


def figure_window(width: int, height: int, headless: bool = False) -> Any:
    """A hidden one-figure window (explorer/ui/figures/harness.py) whose audit figures
    plot the corrected and the original preset's twin frames; the caller closes it."""
    from explorer.ui.figures.harness import FigureWindow

    window = FigureWindow(width, height, visible=False, headless=headless)
    window.context.results = (twin_result("corrected"), twin_result("original"))
    return window


def figure_overflows(window: Any, figures: list[tuple[str, Any]],
                     sizes: tuple[tuple[int, int], ...] = WINDOWS) -> list[str]:
    """Each figure drawn at the article column's width of every window size: one line per
    figure that reaches past the column's right edge, with by how much."""
    too_wide = []
    for size in sizes:
        width = column_width(size[0])
        for where, spec in figures:
            window.render(spec, frames=3, figure_width=width)
            (left, _), _ = window.rect
            over = window.drawn_right - (left + width)
            if over > SLACK_PX:
                too_wide.append(f"{where} ({spec.kind}) at {size[0]}×{size[1]}: "
                                f"{over:.0f} px past a {width:.0f} px column")
    return too_wide


def hidden_marks(pipeline: Any, lessons: Iterable[Any]) -> list[str]:
    """One line per labelled mark its step's camera does not show (outside the image, or
    behind a surface), each step rendered tiny by ``pipeline``."""
    from explorer.lessons import preview_settings
    from explorer.ui.overlays.marks import placements

    problems = []
    for lesson in lessons:
        for step in lesson.steps:
            labelled = [m for m in step.marks if m.label]
            if not labelled:
                continue
            result = pipeline.run(preview_settings(step, size=MARK_VIEW, max_iterations=1))
            view = (float(MARK_VIEW), float(MARK_VIEW))
            placed = {p.label: p for p in placements(result, labelled, (0.0, 0.0), view,
                                                     lambda t: (5.0, 8.0))}
            for mark in labelled:
                if mark.label not in placed or not placed[mark.label].visible:
                    problems.append(f"{lesson.path.name} step {step.number}: mark "
                                    f"{mark.label!r} is not in view of the step's camera")
    return problems
