"""``lpv-explorer lessons --export`` needs no display: glfw's null platform with an EGL
context, and it waits for the converged frame and says so."""

from __future__ import annotations

import os

import numpy as np
import pytest
from window_cases import run_child


def test_lessons_export_runs_without_a_display(tmp_path):
    from explorer.gl.window import headless_available

    if not headless_available():
        pytest.skip("this glfw has no null platform (glfw 3.4 needed)")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    out = tmp_path / "step.png"
    done = run_child(["-m", "explorer", "lessons", "--export", "overview", "--step", "2",
                      "--out", str(out), "--size", "640x400"], tmp_path, env=env)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "waiting for the converged frame" in done.stdout
    assert "(the converged frame)" in done.stdout
    from PIL import Image

    pixels = np.asarray(Image.open(out).convert("RGB"))
    assert pixels.shape == (400, 640, 3)
    assert pixels.std() > 10          # panels and a picture, not a cleared framebuffer
