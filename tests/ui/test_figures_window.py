"""Every figure kind drawn in a real glfw window under Xvfb (pytest-xvfb starts it).

Screenshots are compared loosely: the figure's rectangle is not empty, and its pixels
change when a parameter changes."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from figure_cases import figure_window
from window_cases import display_problem

from explorer.ui.figures import FIGURES, make_figure

ROOT = Path(__file__).resolve().parents[2]


_PROBLEM = display_problem()
pytestmark = pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))

# Each kind with its defaults, and with its declared demo change (a visible change).
CHANGES = {name: dict(kind.demo) for name, kind in FIGURES.items()}
MIN_HEIGHT = {"pipeline": 100}
"""Figures drawn as a compact strip (pixels); the others are at least 150 tall."""
BACKGROUND = np.array([28, 29, 33])    # widgets.window_bg (0.11, 0.115, 0.13) in 8 bits


@pytest.fixture(scope="module")
def window():
    win = figure_window(1000, 760)
    yield win
    win.close()


def _not_empty(pixels: np.ndarray) -> float:
    """Share of the pixels that differ from the window background."""
    return float(np.mean(np.abs(pixels.astype(int) - BACKGROUND).sum(axis=-1) > 24))


def test_every_kind_is_covered():
    assert set(CHANGES) == set(FIGURES) and all(CHANGES.values())


@pytest.mark.parametrize("kind", sorted(CHANGES))
def test_figure_renders_and_changes_with_its_parameter(window, kind):
    before = window.render(make_figure(kind), frames=3)
    assert window.ctx.error == "GL_NO_ERROR"
    (x0, y0), (x1, y1) = window.rect
    assert x1 - x0 > 500 and y1 - y0 > MIN_HEIGHT.get(kind, 150), \
        f"{kind} drew into {window.rect}"
    assert _not_empty(before) > 0.2, f"{kind}: the figure's area is (nearly) empty"
    assert before.std() > 15
    after = window.render(make_figure(kind, **CHANGES[kind]), frames=3)
    shape = tuple(min(a, b) for a, b in zip(before.shape, after.shape))
    a = before[:shape[0], :shape[1]].astype(int)
    b = after[:shape[0], :shape[1]].astype(int)
    changed = float(np.mean(np.abs(a - b).sum(axis=-1) > 30))
    assert changed > 0.01, f"{kind}: {CHANGES[kind]} changed {changed:.2%} of the pixels"


def test_narrow_figures_stack_their_views(window):
    window.render(make_figure("clamped-cosine"), frames=3, figure_width=400.0)
    (x0, y0), (x1, y1) = window.rect
    assert x1 - x0 <= 401.0
    assert y1 - y0 > 700.0, "the polar and 3D views should stack in a narrow column"


def test_audit_figures_say_so_when_there_is_no_frame_yet(window):
    from explorer.ui.figures import FigureContext

    saved, window.context = window.context, FigureContext()
    try:
        pixels = window.render(make_figure("energy-audit"), frames=2)
        (x0, y0), (x1, y1) = window.rect
        assert y1 - y0 < 40, "only a one-line note"
        assert _not_empty(pixels) > 0.005
    finally:
        window.context = saved


def test_plots_panel_draws_both_scales_with_labelled_legends(window):
    """The Plots panel's flux and audit plots are the figures' own; drawn here through
    the same functions with the panel's linear/log choices."""
    from explorer.ui.figures.energy_audit import audit_series
    from explorer.ui.figures.flux_per_step import flux_series

    results = window.context.results
    assert [s.label for s in flux_series(results)] == ["A: corrected preset",
                                                       "B: original preset"]
    shots = [window.render(make_figure("flux-per-step", scale=scale), frames=2)
             for scale in ("linear", "log")]
    h = min(s.shape[0] for s in shots)
    assert np.mean(np.abs(shots[0][:h].astype(int) - shots[1][:h]).sum(-1) > 30) > 0.01
    assert len(audit_series(results)) == 2


def test_cli_writes_a_screenshot_and_refuses_bad_parameters(tmp_path):
    out = tmp_path / "texel.png"
    env = dict(os.environ)
    run = subprocess.run([sys.executable, "-m", "explorer.ui.figures", "rsm-texel",
                          "--theta-deg", "45", "--width", "700", "--height", "520",
                          "--frames", "3", "--screenshot", str(out)],
                         cwd=ROOT, env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    from PIL import Image

    image = np.asarray(Image.open(out).convert("RGB"))
    assert image.shape == (520, 700, 3) and image.std() > 15
    bad = subprocess.run([sys.executable, "-m", "explorer.ui.figures", "rsm-texel",
                          "--theta-deg", "95"], cwd=ROOT, env=env, capture_output=True,
                         text=True, timeout=60)
    assert bad.returncode == 2
    assert "theta_deg must be a finite number in [0, 85], got 95" in bad.stderr
    unknown = subprocess.run([sys.executable, "-m", "explorer.ui.figures", "cosine"],
                             cwd=ROOT, env=env, capture_output=True, text=True, timeout=60)
    assert unknown.returncode == 2 and "unknown figure kind 'cosine'" in unknown.stderr
    not_png = subprocess.run([sys.executable, "-m", "explorer.ui.figures", "rsm-texel",
                              "--screenshot", str(tmp_path / "shot")], cwd=ROOT, env=env,
                             capture_output=True, text=True, timeout=60)
    assert not_png.returncode == 2 and "must name a .png file" in not_png.stderr
    listing = subprocess.run([sys.executable, "-m", "explorer.ui.figures", "--list"],
                             cwd=ROOT, env=env, capture_output=True, text=True, timeout=60)
    assert listing.returncode == 0
    assert all(kind in listing.stdout for kind in FIGURES)


def test_the_drawing_follows_each_instance_state(window):
    """Dragging changes the instance's state, not its parameters: the next frame shows
    the new state, and another instance with the same parameters is untouched."""
    spec = make_figure("clamped-cosine", normal_deg=30)
    first = window.render(spec, frames=3)
    state = window.context.state_for(spec.instance_id, spec.kind, spec.params,
                                     FIGURES[spec.kind].make_state)
    state.normal_deg = -100.0                      # what a drag of the handle does
    dragged = window.render(spec, frames=2)
    h = min(first.shape[0], dragged.shape[0])
    assert np.mean(np.abs(first[:h].astype(int) - dragged[:h]).sum(-1) > 30) > 0.01
    from dataclasses import replace

    other = replace(spec, id="second")
    fresh = window.render(other, frames=3)
    h = min(first.shape[0], fresh.shape[0])
    assert np.mean(np.abs(first[:h].astype(int) - fresh[:h]).sum(-1) > 30) < 0.005
