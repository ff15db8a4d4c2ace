"""Mitsuba's truth rendered in the background: a worker process a window can poll and
cancel.

``mi.render`` is one long call that a window cannot split into frames, so the Error
panel runs it in a child process (``python -m explorer.truth.mitsuba_render``): the
scene is exported to a temporary folder, the child renders it there and writes its
images, and :meth:`MitsubaJob.poll` (no waiting) reads them once they are complete.
:meth:`MitsubaJob.release` ends the child and removes the folder at any time, which is
how a change of the settings cancels a render still running.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from explorer.truth.mitsuba_render import (
    SCENE_FILE,
    SEEDS,
    TRUTH_PARTS,
    TruthImages,
    depths_for,
    pick_variant,
    truth_images,
)
from explorer.truth.mitsuba_scene import export_scene


class MitsubaJob:
    """Renders ``scene`` at ``width × height`` with Mitsuba in a child process."""

    def __init__(self, scene, width: int, height: int, spp: int = 64,
                 variant: str = "auto", parts: tuple[str, ...] = TRUTH_PARTS) -> None:
        self.parts = tuple(parts)
        self.spp = int(spp)
        self.variant = pick_variant(variant)
        self.depths = depths_for(self.parts)
        self.result: TruthImages | None = None
        self.problem: str | None = None
        self._started = time.perf_counter()
        self._folder = Path(tempfile.mkdtemp(prefix="lpv-mitsuba-job-"))
        export_scene(scene, width, height).write(self._folder / SCENE_FILE)
        # the child imports this very explorer package, wherever it was imported from
        root = str(Path(__file__).resolve().parents[2])
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(
            [root, *filter(None, [os.environ.get("PYTHONPATH")])])}
        with open(self._folder / "stderr", "wb") as stderr:
            self._process = subprocess.Popen(
                [sys.executable, "-m", "explorer.truth.mitsuba_render", str(self._folder),
                 str(self.spp), self.variant, ",".join(self.parts)],
                stdout=subprocess.DEVNULL, stderr=stderr, env=env)

    @property
    def fraction(self) -> float:
        """Renders finished / renders to do (0 before the first)."""
        if self.result is not None:
            return 1.0
        try:
            done, total = (int(v) for v in (self._folder / "progress").read_text().split())
        except (OSError, ValueError):
            return 0.0
        return done / max(total, 1)

    @property
    def done(self) -> bool:
        return self.result is not None or self.problem is not None

    def poll(self) -> bool:
        """Look, without waiting, whether the child has finished: True once
        :attr:`result` (or :attr:`problem`) is set."""
        if self.done:
            return True
        code = self._process.poll()
        if code is None:
            return False
        if code != 0:
            problem = self._folder / "problem"
            stderr = (self._folder / "stderr").read_text(errors="replace").strip()
            self.problem = (problem.read_text() if problem.exists()
                            else (stderr.splitlines() or [f"exit status {code}"])[-1])
            self.release()
            return True
        with np.load(self._folder / "renders.npz") as arrays:
            renders = {(depth, seed): arrays[f"d{depth}_s{seed}"]
                       for depth in self.depths for seed in SEEDS}
        self.result = truth_images(renders, self.parts, self.spp, self.variant,
                                   time.perf_counter() - self._started)
        self.release()
        return True

    def release(self) -> None:
        """End the child (when still running) and remove the folder."""
        if self._process.poll() is None:
            self._process.kill()
            self._process.wait()
        shutil.rmtree(self._folder, ignore_errors=True)


class TruthStats:
    """An Error panel measurement held against Mitsuba: the LPV against the one bounce
    and all bounces, and the project's reference against the one bounce, with Mitsuba's
    noise (explorer/truth/mitsuba_render.py)."""

    def __init__(self, lpv: np.ndarray, reference: np.ndarray, valid: np.ndarray,
                 truth: TruthImages) -> None:
        from explorer.truth.metrics import error_stats

        one, multi = truth["one-bounce"], truth["multi-bounce"]
        self.one_bounce = error_stats(lpv, one.image, valid)
        self.multi_bounce = error_stats(lpv, multi.image, valid)
        self.reference = error_stats(reference, one.image, valid)
        self.noise = (one.noise_l2, one.noise_flux)
        self.truth = truth


class ErrorReadout:
    """What ``{{error.*}}`` reads: the ErrorStats of configuration A against the
    reference (``relative_l2``, ``flux_ratio``, ...) and, once Mitsuba has measured it,
    ``mitsuba_*`` (the LPV against Mitsuba's one bounce), ``mitsuba_multi_*`` (all
    bounces) and ``reference_mitsuba_*`` (the reference against the one bounce); None
    until then."""

    PREFIXES = (("reference_mitsuba_", "reference"), ("mitsuba_multi_", "multi_bounce"),
                ("mitsuba_", "one_bounce"))

    def __init__(self, stats, truth=None) -> None:
        self.stats, self.truth = stats, truth

    def __getattr__(self, name: str):
        for prefix, field in self.PREFIXES:
            if name.startswith(prefix):
                truth = self.__dict__["truth"]
                return None if truth is None else getattr(getattr(truth, field),
                                                          name[len(prefix):])
        return getattr(self.__dict__["stats"], name)
