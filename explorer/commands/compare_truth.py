"""``lpv-explorer compare --truth mitsuba``: the comparison's frames against physics.

Beside the project's own one-bounce reference (which gathers the very VPLs the LPV
injected), Mitsuba 3 renders the exported scene (explorer/truth/mitsuba_scene.py) at the
frame's pixels: the direct light, the one-bounce and the multi-bounce indirect light
(explorer/truth/mitsuba_render.py). The table then shows, per region:

* the explorer's direct light against Mitsuba's (the export's own check),
* the project's reference against Mitsuba's one bounce (what the RSM's sampling, the
  1/r² clamp and the shadow rays cost: the reference's error),
* every LPV frame against Mitsuba's one bounce and its multi-bounce light (the grid's
  error on top of the reference's),

each with Mitsuba's own noise (half the distance between two seeds' images). The PNGs
``mitsuba-direct.png``, ``mitsuba-one-bounce.png``, ``mitsuba-multi-bounce.png`` (the
comparison's exposure), ``error-mitsuba-<label>.png`` (the LPV against the one bounce) and
the linear images in ``mitsuba.npz`` go into the output folder.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from explorer.commands import options

TRUTH_CHOICES = ("project", "mitsuba")
DEFAULT_SPP = 256


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from explorer.truth.mitsuba_render import VARIANTS

    parser.add_argument("--truth", default="project", choices=TRUTH_CHOICES,
                        help="project: the one-bounce reference alone; mitsuba: also Mitsuba "
                             "3's direct, one-bounce and multi-bounce light (pip install "
                             "'lpv-explorer[truth]') (default: project)")
    parser.add_argument("--mitsuba-spp", type=_positive_int, default=DEFAULT_SPP,
                        metavar="N", help=f"Mitsuba samples per pixel per seed (two seeds; "
                                          f"default {DEFAULT_SPP})")
    parser.add_argument("--mitsuba-variant", default="auto", choices=VARIANTS,
                        help="auto: llvm_ad_rgb when DRJIT_LIBLLVM_PATH is set, else "
                             "scalar_rgb (default: auto)")


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}"
                                         ) from None
    if not 1 <= value <= 1 << 20:
        raise argparse.ArgumentTypeError(f"expected a whole number in [1, 1048576], got "
                                         f"{value}")
    return value


def check_available(args: argparse.Namespace) -> None:
    """Mitsuba importable with the variant asked for, before any rendering."""
    if args.truth != "mitsuba":
        return
    from explorer.truth.mitsuba_render import MitsubaUnavailable, load_mitsuba

    try:
        load_mitsuba(args.mitsuba_variant)
    except MitsubaUnavailable as exc:
        raise options.CommandError(exc, 1) from None


@dataclass
class TruthRow:
    """One line of the table against Mitsuba."""

    what: str           # "direct (explorer)", "reference (project)", an LPV label
    truth: str          # "direct", "one-bounce" or "multi-bounce"
    region: str
    stats: object | None
    noise: tuple[float, float]      # Mitsuba's relative L2 and flux noise of that image


def truth_rows(comparison, truth, regions: dict[str, np.ndarray]) -> list[TruthRow]:
    """Every row of the table: the explorer's direct light, the project's reference and
    each LPV image against the Mitsuba image it approximates, over each region."""
    from explorer.commands.compare_report import region_metrics

    frame = comparison.frame
    pairs = [("direct (explorer)", np.asarray(frame.direct, np.float64)[..., :3], "direct"),
             ("reference (project)", np.asarray(comparison.reference, np.float64),
              "one-bounce")]
    for label, image in comparison.images.items():
        pairs += [(label, image, "one-bounce"), (label, image, "multi-bounce")]
    rows = []
    for what, image, name in pairs:
        part = truth[name]
        for region, mask in regions.items():
            stats, _ = region_metrics(image, part.image, mask)
            rows.append(TruthRow(what, name, region, stats, (part.noise_l2, part.noise_flux)))
    return rows


def format_truth_table(rows: list[TruthRow], truth) -> str:
    from explorer.commands.compare_report import METRIC_ALIGN, METRIC_HEADERS, metric_cells

    headers = tuple(h.replace("LPV/ref", "image/Mitsuba") for h in METRIC_HEADERS)
    lines = [f"against Mitsuba 3 (`{truth.variant}`, {truth.spp} spp × 2 seeds, "
             f"{truth.seconds:.1f} s): noise = half the distance between the seeds' images",
             "",
             "| image | truth | region | " + " | ".join(headers)
             + " | noise rel. L2 | noise flux |",
             "|---|---|---|" + "|".join(METRIC_ALIGN) + "|---:|---:|"]
    for row in rows:
        lines.append(f"| {row.what} | {row.truth} | {row.region} | "
                     + " | ".join(metric_cells(row.stats))
                     + f" | {row.noise[0]:.3f} | {row.noise[1]:.4f} |")
    return "\n".join(lines)


def run(args: argparse.Namespace, comparison, scene, regions: dict[str, np.ndarray],
        outputs: options.Outputs, out: Path, exposure: float) -> tuple[str, list[str]]:
    """Render Mitsuba's images at the comparison's pixels, write them and return the
    table (printed by the caller) and the names of the files written."""
    from explorer.truth.mitsuba_render import MitsubaUnavailable, render_truth

    settings = comparison.frame.settings
    quiet = getattr(args, "quiet", False)

    def progress(done: int, total: int) -> None:
        if not quiet:
            print(f"mitsuba: render {done}/{total}",
                  file=sys.stderr, flush=True)

    try:
        truth = render_truth(scene, settings.width, settings.height, args.mitsuba_spp,
                             args.mitsuba_variant, progress=progress)
    except MitsubaUnavailable as exc:
        raise options.CommandError(exc, 1) from None
    rows = truth_rows(comparison, truth, regions)
    written = _write_images(outputs, out, comparison, truth, exposure)
    return format_truth_table(rows, truth), written


def _write_images(outputs: options.Outputs, out: Path, comparison, truth,
                  exposure: float) -> list[str]:
    from explorer.commands.compare_report import save_error_png, save_png
    from explorer.truth.metrics import error_image

    for name, part in truth.parts.items():
        outputs.write(out / f"mitsuba-{name}.png",
                      lambda p, image=part.image: save_png(p, image * exposure))
    one = truth["one-bounce"].image
    for label, image in comparison.images.items():
        error = error_image(image, one, comparison.valid, "log2-ratio", 3.0)
        outputs.write(out / f"error-mitsuba-{label}.png",
                      lambda p, e=error: save_error_png(p, e))
    arrays = {name.replace("-", "_"): part.image.astype(np.float32)
              for name, part in truth.parts.items()}
    outputs.write(out / "mitsuba.npz", lambda p: np.savez_compressed(p, **arrays))
    return [f"mitsuba-{name}.png" for name in truth.parts] + [
        f"error-mitsuba-{label}.png" for label in comparison.images] + ["mitsuba.npz"]
