"""Mitsuba 3 as the independent ground truth: the exported scene (mitsuba_scene.py) rendered
at the frame's pixels, split into the light an LPV frame is compared with.

With Mitsuba's ``path`` integrator (``volpath`` for a scene with one-sided surfaces, the
same without media), ``max_depth`` d keeps paths of at most d − 1 bounces
off surfaces (point-like and directional lights are never seen directly), so

* direct light                 = render(max_depth 2),
* one-bounce indirect light    = render(max_depth 3) − render(max_depth 2),
* multi-bounce indirect light  = render(max_depth ∞) − render(max_depth 2).

Both renders of a difference use the same seed: the path tracer draws the same samples
for the first bounce whatever its depth limit, so the direct part cancels exactly and the
difference holds only the noise of the added bounces (never negative). Each image is the
mean of two seeds; half the relative L2 distance between the two seeds' images is the
noise of that mean (two estimates with noise σ each differ by √2·σ; their mean has
σ/√2), reported beside every error as Mitsuba's own noise level.

Mitsuba is an optional extra (``pip install 'lpv-explorer[truth]'``);
:func:`load_mitsuba` raises :class:`MitsubaUnavailable` with that line when it is missing.
The ``scalar_rgb`` variant runs everywhere; ``llvm_ad_rgb`` (several times faster) needs an
LLVM that Dr.Jit can drive (``DRJIT_LIBLLVM_PATH`` naming LLVM 16 or newer; Debian 12's
LLVM 15 aborts it), so ``auto`` picks it only when that variable is set.
"""

from __future__ import annotations

import os
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from explorer.truth import mitsuba_one_sided
from explorer.truth.metrics import relative_l2
from explorer.truth.mitsuba_scene import export_scene

VARIANTS = ("auto", "scalar_rgb", "llvm_ad_rgb")
INSTALL_HINT = "pip install 'lpv-explorer[truth]'"
MULTI_BOUNCE_DEPTH = 64
"""The path length limit of the "all bounces" render: with Russian roulette from depth 5
the paths that reach it carry a negligible share (a white room of albedo 0.75 keeps
0.75⁶³ ≈ 1e-8 of the light there)."""
TRUTH_PARTS = ("direct", "one-bounce", "multi-bounce")
SEEDS = (0, 1)
SCENE_FILE = "scene.xml"


class MitsubaUnavailable(RuntimeError):
    """Mitsuba 3 cannot be imported or its variant cannot be set (one line: what to do)."""


def pick_variant(variant: str = "auto") -> str:
    """``auto``: ``llvm_ad_rgb`` when ``DRJIT_LIBLLVM_PATH`` names an LLVM for Dr.Jit, else
    ``scalar_rgb``; another name is returned as it is (checked against :data:`VARIANTS`)."""
    if variant not in VARIANTS:
        raise ValueError(f"Mitsuba variant must be one of {', '.join(VARIANTS)}, got "
                         f"{variant!r}")
    if variant != "auto":
        return variant
    return "llvm_ad_rgb" if os.environ.get("DRJIT_LIBLLVM_PATH") else "scalar_rgb"


_PROBE = ("import mitsuba as mi; mi.set_variant({name!r}); "
          "mi.render(mi.load_dict({{'type': 'scene', 'shape': {{'type': 'sphere'}}, "
          "'light': {{'type': 'constant'}}, 'integrator': {{'type': 'path'}}, "
          "'camera': {{'type': 'perspective', "
          "'film': {{'type': 'hdrfilm', 'width': 4, 'height': 4}}}}}}), spp=1)")
_PROBED: dict[str, str | None] = {}


def probe_variant(name: str) -> str | None:
    """None when a JIT variant renders a 4×4 test image in a child process, else why
    not: Dr.Jit aborts the whole process on an LLVM it cannot drive (Debian 12's LLVM 15),
    so the first render of an ``llvm_*`` variant is tried where an abort costs nothing."""
    if name not in _PROBED:
        import subprocess
        import sys

        try:
            run = subprocess.run([sys.executable, "-c", _PROBE.format(name=name)],
                                 capture_output=True, text=True, timeout=300)
            lines = (run.stderr or "").strip().splitlines()
            _PROBED[name] = None if run.returncode == 0 else (
                f"a test render ended with exit status {run.returncode}"
                + (f": {lines[-1]}" if lines else ""))
        except (OSError, subprocess.TimeoutExpired) as exc:
            _PROBED[name] = f"a test render failed: {exc}"
    return _PROBED[name]


def load_mitsuba(variant: str = "auto", probe: bool = True):
    """The ``mitsuba`` module with ``variant`` set (:func:`pick_variant`); a JIT variant
    is first tried in a child process (:func:`probe_variant`) unless ``probe`` is False
    (a worker whose parent tried it)."""
    try:
        import mitsuba as mi
    except ImportError:
        raise MitsubaUnavailable(f"Mitsuba 3 is not installed: {INSTALL_HINT}") from None
    name = pick_variant(variant)
    problem = probe_variant(name) if probe and name != "scalar_rgb" else None
    if problem is not None:
        raise MitsubaUnavailable(f"Mitsuba variant {name!r} does not run here ({problem}); "
                                 f"use --mitsuba-variant scalar_rgb, or point "
                                 f"DRJIT_LIBLLVM_PATH at LLVM 16 or newer")
    try:
        mi.set_variant(name)
    except (ImportError, AttributeError, RuntimeError, ValueError) as exc:
        raise MitsubaUnavailable(f"Mitsuba variant {name!r} is not available ({exc}); try "
                                 f"--mitsuba-variant scalar_rgb") from None
    return mi


def mitsuba_available() -> str | None:
    """None when Mitsuba 3 can be imported, else the reason (tests print it)."""
    try:
        import mitsuba  # noqa: F401
    except ImportError:
        return f"Mitsuba 3 is not installed ({INSTALL_HINT})"
    return None


@dataclass
class TruthPart:
    """One kind of light (direct, one-bounce or multi-bounce indirect) as Mitsuba renders
    it: the mean of the seeds and its noise."""

    image: np.ndarray
    """(H, W, 3) float64 linear radiance, row 0 at the top (the frame's order)."""
    noise_l2: float
    """Half the relative L2 distance between the seeds' images: the relative L2 noise of
    :attr:`image`."""
    noise_flux: float
    """Half the relative difference of the seeds' total flux: the flux noise of
    :attr:`image`."""
    seeds: tuple[np.ndarray, np.ndarray]


@dataclass
class TruthImages:
    """Mitsuba's direct, one-bounce and multi-bounce images of one scene and camera."""

    parts: dict[str, TruthPart]
    spp: int
    variant: str
    seconds: float

    def __getitem__(self, name: str) -> TruthPart:
        return self.parts[name]


def depths_for(parts: tuple[str, ...]) -> list[int]:
    """The ``max_depth`` of each render the parts need (2 always: the direct light)."""
    unknown = [name for name in parts if name not in TRUTH_PARTS]
    if unknown or not parts:
        raise ValueError(f"truth parts must be among {TRUTH_PARTS}, got {parts}")
    return [2] + ([3] if "one-bounce" in parts else []) + (
        [MULTI_BOUNCE_DEPTH] if "multi-bounce" in parts else [])


def scene_integrator(path: Path) -> str:
    """The integrator an exported XML scene names (``path``, or ``volpath`` for one with
    one-sided surfaces: explorer/truth/mitsuba_one_sided.py)."""
    import xml.etree.ElementTree as ElementTree

    node = ElementTree.parse(path).getroot().find("integrator")
    return "path" if node is None else node.get("type", "path")


def render_file(mi, path: Path, spp: int, depths: list[int], progress=None
                ) -> dict[tuple[int, int], np.ndarray]:
    """Render the exported scene file ``path`` once per depth and seed, with the
    integrator it names: ``(depth, seed)`` -> (H, W, 3) float64. ``progress(done,
    total)`` after each render."""
    mitsuba_one_sided.register(mi)
    kind = scene_integrator(path)
    scene = mi.load_file(str(path))
    renders = {}
    total = len(depths) * len(SEEDS)
    for seed in SEEDS:
        for depth in depths:
            integrator = mi.load_dict({"type": kind, "max_depth": int(depth)})
            image = mi.render(scene, integrator=integrator, spp=int(spp), seed=int(seed))
            renders[depth, seed] = np.asarray(image, np.float64)[..., :3]
            if progress is not None:
                progress(len(renders), total)
    return renders


def _part(seeds: list[np.ndarray]) -> TruthPart:
    a, b = seeds
    mean = 0.5 * (a + b)
    total = float(a.sum() + b.sum())
    flux = abs(float(a.sum() - b.sum())) / total if total > 0 else 0.0
    return TruthPart(mean, 0.5 * relative_l2(a, b), flux, (a, b))


def truth_images(renders: dict[tuple[int, int], np.ndarray], parts: tuple[str, ...],
                 spp: int, variant: str, seconds: float) -> TruthImages:
    """The parts from the renders of :func:`render_file`: a difference of two depths of
    the same seed is the light of the bounces between them (never negative but for
    rounding, which is clamped)."""
    found = {}
    for name in parts:
        depth = {"direct": None, "one-bounce": 3, "multi-bounce": MULTI_BOUNCE_DEPTH}[name]
        seeds = [renders[2, seed] if depth is None
                 else np.maximum(renders[depth, seed] - renders[2, seed], 0.0)
                 for seed in SEEDS]
        found[name] = _part(seeds)
    return TruthImages(found, int(spp), variant, seconds)


def render_truth(scene, width: int, height: int, spp: int = 256, variant: str = "auto",
                 parts: tuple[str, ...] = TRUTH_PARTS, progress=None) -> TruthImages:
    """Mitsuba's images of ``scene`` (overrides applied) at ``width × height`` with
    ``spp`` samples per pixel per seed, in this process. ``progress(done, total)`` after
    each render."""
    if spp < 1:
        raise ValueError(f"spp must be >= 1, got {spp}")
    depths = depths_for(parts)
    mi = load_mitsuba(variant)
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="lpv-mitsuba-") as folder:
        path = Path(folder) / SCENE_FILE
        export_scene(scene, width, height).write(path)
        renders = render_file(mi, path, spp, depths, progress)
    return truth_images(renders, parts, spp, pick_variant(variant),
                        time.perf_counter() - started)


def main(argv: list[str] | None = None) -> int:
    """The worker of explorer/truth/mitsuba_job.py: ``python -m
    explorer.truth.mitsuba_render FOLDER SPP VARIANT PARTS`` renders FOLDER/scene.xml and
    writes FOLDER/renders.npz (one array per depth and seed), counting the renders done
    in FOLDER/progress."""
    import sys

    folder, spp, variant, parts = (argv if argv is not None else sys.argv[1:])
    folder = Path(folder)

    def progress(done: int, total: int) -> None:
        (folder / "progress").write_text(f"{done} {total}")

    try:      # an abort here ends this child only: the parent reads its exit status
        mi = load_mitsuba(variant, probe=False)
    except MitsubaUnavailable as exc:
        (folder / "problem").write_text(str(exc))
        return 1
    renders = render_file(mi, folder / SCENE_FILE, int(spp),
                          depths_for(tuple(parts.split(","))), progress)
    np.savez(folder / "renders.partial.npz",
             **{f"d{depth}_s{seed}": image for (depth, seed), image in renders.items()})
    (folder / "renders.partial.npz").replace(folder / "renders.npz")
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
