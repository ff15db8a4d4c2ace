"""``run --screenshot`` waits for the converged frame by default and says so; with
``--no-wait`` it writes the frame after ``--frames`` as it is and says whether that one
had converged."""

from __future__ import annotations

import re

import pytest
from window_cases import display_problem, run_child


@pytest.mark.skipif(display_problem() is not None, reason=str(display_problem()))
def test_run_screenshot_waits_for_the_converged_frame_and_says_so(tmp_path):
    out = tmp_path / "shot.png"
    base = ["-m", "explorer", "run", "--no-persist", "--hidden", "--size", "640x400",
            "--lesson", "overview", "--step", "1", "--frames", "2", "--screenshot", str(out)]
    done = run_child(base, tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "waiting for the converged frame" in done.stdout
    # the lesson step is applied by the panel in the first frames: its own frame is
    # what converged (more than the 2 frames asked for)
    waited = re.search(r"converged after 2 \+ (\d+) frames", done.stdout)
    assert waited and int(waited.group(1)) > 1, done.stdout
    assert out.stat().st_size > 0
    done = run_child(base + ["--no-wait"], tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "waiting" not in done.stdout
    assert re.search(r"after 2 frames \((not converged: [^)]+|converged)\)",
                     done.stdout), done.stdout
