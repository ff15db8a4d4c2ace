"""``lpv-explorer lessons --export`` needs no display: glfw's null platform with an EGL
context (issue #25 item 6), and it waits for the converged frame and says so."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent


def test_lessons_export_runs_without_a_display(tmp_path):
    from explorer.gl.window import headless_available

    if not headless_available():
        pytest.skip("this glfw has no null platform (glfw 3.4 needed)")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env.update(XDG_CONFIG_HOME=str(tmp_path / "config"), XDG_CACHE_HOME=str(tmp_path / "c"))
    out = tmp_path / "step.png"
    done = subprocess.run([sys.executable, "-m", "explorer", "lessons", "--export",
                           "overview", "--step", "2", "--out", str(out), "--size", "640x400"],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "waiting for the converged frame" in done.stdout
    assert "(the converged frame)" in done.stdout
    from PIL import Image

    pixels = np.asarray(Image.open(out).convert("RGB"))
    assert pixels.shape == (400, 640, 3)
    assert pixels.std() > 10          # panels and a picture, not a cleared framebuffer
