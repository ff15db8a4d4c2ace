"""The lessons' inline figures as 2× PNG, drawn by the window's own figure code in a
hidden one-figure window (explorer/ui/figures/harness.py) at twice the size.

A GLX window cannot become current in a process that made an EGL context current, and
the site's frames are rendered through EGL, so the figures are drawn in a child process:
``python -m explorer.site.figure_shots JOBS.json`` reads the jobs, writes each PNG (a
propagation stepper one PNG per step t, the frames of its Play) and a JSON file of what
each figure reads out (``figure.<id>.<readout>`` numbers the prose may quote).
:func:`run_jobs` starts that child under ``xvfb-run`` when there is one, else on the
display the build has.
"""

from __future__ import annotations

import dataclasses
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

SCALE = 2
FONT_SIZE = 15.0
"""The one-figure window's font size before scaling (explorer/ui/figures/harness.py)."""
PADDING = 16
WINDOW_HEIGHT = 1900
XVFB_SCREEN = "-screen 0 2800x2000x24"


class FigureShotError(RuntimeError):
    """The child could not draw the figures (no display, a figure failed)."""


def run_jobs(jobs: list[dict[str, Any]], work: Path, timeout_s: float = 1800.0
             ) -> dict[str, Any]:
    """Draw ``jobs`` in a child process; returns {job key: {"files": [...],
    "readouts": {...}}}. Each job: ``key``, ``lesson`` (id), ``step`` (number),
    ``figure`` (instance id), ``out`` (PNG path; a sequence adds ``-<t>``), ``width``
    (CSS pixels), ``sequence`` (bool: every step t of a stepper), ``size`` ([w, h] of the
    frames the results-figures plot), ``lessons_dir`` (or None)."""
    if not jobs:
        return {}
    work.mkdir(parents=True, exist_ok=True)
    request, answer = work / "figure-jobs.json", work / "figure-results.json"
    request.write_text(json.dumps(jobs))
    command = [sys.executable, "-m", "explorer.site.figure_shots", str(request), str(answer)]
    xvfb = shutil.which("xvfb-run")
    if xvfb:
        command = [xvfb, "-a", "-s", XVFB_SCREEN, *command]
    elif not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
        raise FigureShotError("the figures are drawn in a hidden window: install xvfb "
                              "(xvfb-run) or run with a display")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(Path(__file__).resolve().parents[2]), os.environ.get("PYTHONPATH", "")]))
    done = subprocess.run(command, capture_output=True, text=True, timeout=timeout_s, env=env)
    if done.returncode != 0 or not answer.is_file():
        tail = (done.stderr or done.stdout).strip().splitlines()[-6:]
        raise FigureShotError("drawing the figures failed: " + " | ".join(tail))
    return json.loads(answer.read_text())


def _results(job: dict[str, Any], step, ctx) -> tuple:
    """The FrameResults an audit figure plots: the step's frame (and its comparison)."""
    from explorer.ui.figures.harness import pipeline_results

    width, height = job["size"]
    settings = [step.settings().with_changes(width=width, height=height)]
    compare = step.compare_settings()
    if compare is not None:
        settings.append(compare.with_changes(width=width, height=height))
    return pipeline_results(ctx, settings)


def _control_rows() -> int:
    """Pixel rows of the stepper's own controls above its picture (Play and the step
    slider, the glyph and axis choices: two rows of frames): the page plays the frames
    with its own slider, so the picture leaves them out."""
    from imgui_bundle import imgui

    style = imgui.get_style()         # sizes already scaled by SCALE (theme.apply_style)
    row = FONT_SIZE * SCALE + 2 * style.frame_padding.y + style.item_spacing.y
    return int(round(2 * row))


def draw(jobs: list[dict[str, Any]]) -> dict[str, Any]:
    from explorer.lessons import find_lesson, load_all
    from explorer.ui.figures.harness import FigureWindow
    from explorer.ui.figures.host import FigureContext
    from explorer.ui.figures.registry import FIGURES, USES_RESULTS
    from explorer.ui.images import write_png

    lesson_sets: dict[Any, list] = {}
    answers: dict[str, Any] = {}
    widest = max(int(job["width"]) for job in jobs)
    with FigureWindow(widest * SCALE + 2 * PADDING * SCALE, WINDOW_HEIGHT, visible=False,
                      scale=SCALE) as window:
        for job in jobs:
            where = job.get("lessons_dir")
            if where not in lesson_sets:
                lesson_sets[where] = load_all(where)[0]
            step = find_lesson(job["lesson"], lesson_sets[where]).step(int(job["step"]))
            spec = next(s for s in step.figures if s.instance_id == job["figure"])
            spec = dataclasses.replace(spec, caption="")      # the page sets the caption
            kind = FIGURES[spec.kind]
            window.context = FigureContext()
            if spec.kind in USES_RESULTS:
                window.context.results = _results(job, step, window.ctx)
            state = window.context.state_for(spec.instance_id, spec.kind, spec.params,
                                             kind.make_state)
            if hasattr(state, "playing"):
                state.playing = False          # a still picture; the page plays the frames
            steps = [None]
            if job.get("sequence"):
                steps = list(range(int(spec.params.iterations) + 1))
            files = []
            out = Path(job["out"])
            for t in steps:
                if t is not None:
                    state.step = t
                pixels = window.render(spec, frames=4, figure_width=job["width"] * SCALE)
                if job.get("sequence"):
                    pixels = pixels[_control_rows():]
                path = out if t is None else out.with_name(f"{out.stem}-{t}{out.suffix}")
                write_png(pixels, path)
                files.append(str(path))
            if job.get("sequence"):
                state.step = spec.params.step
            readouts = {k: float(v) for k, v in
                        kind.readouts(spec.params, state, window.context).items()}
            answers[job["key"]] = {"files": files, "readouts": readouts}
    return answers


def main(argv: list[str]) -> int:
    request, answer = Path(argv[0]), Path(argv[1])
    answers = draw(json.loads(request.read_text()))
    answer.write_text(json.dumps(answers))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
