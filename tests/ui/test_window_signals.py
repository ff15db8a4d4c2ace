"""SIGTERM and SIGHUP end the window as its Quit item does (the settings and the layout
saved, each whole), and a second signal ends it at once. A real window under Xvfb: the
explorer runs as a child process, the signal is sent to it like ``kill`` would."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from window_cases import display_problem

ROOT = Path(__file__).resolve().parents[2]
_PROBLEM = display_problem() or (None if shutil.which("xwininfo") else
                                 "xwininfo (x11-utils) is needed to see the window open")
pytestmark = pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))


def _start(tmp_path: Path) -> subprocess.Popen:
    """The explorer's window with its settings in ``tmp_path``, once it has drawn (its
    title is set after the first frame)."""
    env = dict(os.environ, XDG_CONFIG_HOME=str(tmp_path / "config"),
               XDG_CACHE_HOME=str(tmp_path / "cache"), PYTHONPATH=str(ROOT))
    child = subprocess.Popen(
        [sys.executable, "-m", "explorer", "run", "--size", "640x400", "--scene",
         "single-source"],
        cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and child.poll() is None:
        tree = subprocess.run(["xwininfo", "-root", "-tree"], capture_output=True,
                              text=True).stdout
        if "lpv-explorer —" in tree:
            time.sleep(0.5)
            return child
        time.sleep(0.2)
    child.kill()
    out, err = child.communicate()
    raise AssertionError(f"the window did not open: {err[-2000:]}")


def test_sigterm_quits_the_window_and_saves_settings_and_layout(tmp_path):
    """(SIGHUP has the same handler, explorer/stop_signals.py ``calling``.)"""
    child = _start(tmp_path)
    child.send_signal(signal.SIGTERM)
    _, err = child.communicate(timeout=60)
    assert child.returncode == 0, err[-2000:]
    folder = tmp_path / "config" / "lpv-explorer"
    settings = json.loads((folder / "settings.json").read_text())
    assert settings["settings"]["scene"] == "single-source"
    assert "[Docking][Data]" in (folder / "imgui.ini").read_text()
    assert sorted(p.name for p in folder.iterdir()) == ["imgui.ini", "settings.json"], \
        "a temporary was left in the settings folder"


def test_a_second_signal_ends_the_window_at_once(tmp_path):
    """Two different signals sent together are both handled (two of one kind pending at
    once are one for Python; it takes them in the order of their numbers): the second
    ends the process by that signal, unsaved."""
    child = _start(tmp_path)
    child.send_signal(signal.SIGTERM)
    child.send_signal(signal.SIGHUP)
    child.communicate(timeout=60)
    assert child.returncode in (-signal.SIGHUP, -signal.SIGTERM)
    assert not (tmp_path / "config" / "lpv-explorer" / "settings.json").exists()
