"""``lpv-explorer compare``: LPV against the one-bounce reference, as a table and PNGs.

Both images come from the same frame: the reference gathers the very VPLs the LPV
injected, at the pixels the camera sees, so the error measures what the grid (injection,
propagation, gather and the formulas the preset selects) does to that light. With several
lights (``--lights spot,bulb``) the frame's VPLs are every light's, and the reference sums
them all (docs/MODEL.md "Several lights").

Every option is checked, the reference's cost bounded and the output folder made before
any rendering; Ctrl-C removes what was written (see :class:`~explorer.commands.options.
options.Outputs`).
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from explorer.commands import compare_folder, compare_truth, options
from explorer.commands.compare_report import (  # noqa: F401  (tables.py reads them here)
    METRIC_ALIGN,
    METRIC_HEADERS,
    metric_cells,
    region_metrics,
    save_error_png,
    save_png,
)
from explorer.lpv.settings import PRESETS, Settings
from explorer.schema import Spec, specs

REFERENCE_CHOICES = ("visible", "unoccluded")
LOG2_DEFAULT_SCALE = 3.0  # error images saturate at 8× too bright / too dark
MAX_REFERENCE_PAIRS = 2**34
"""Pixel × VPL pairs one reference may gather (1.7·10¹⁰, 64× the default 256² pixels ×
64² VPLs): each pair costs a 1/r² term and, with visibility, a shadow ray through the
BVH, so a larger request would run for hours. Smaller images or RSMs fit."""
DEFAULTS = {"size": (256, 256), "rsm_size": 64}
"""Sizes that keep the reference (pixels × VPLs) to seconds on a GPU."""
MIN_DISTANCE = Spec(kind="float", low=0.0, high=1e6, optional=True,
                    doc="The reference's 1/r² clamp distance in world units; default half a "
                        "grid cell (with --cascades above 1, of the single scene-enclosing "
                        "grid).")
ERROR_SCALE = Spec(kind="float", low=0.0, low_open=True, high=1e6, optional=True,
                   doc="Error value at full colour; default 3 stops for log2-ratio, the "
                       "reference's 99th percentile for difference.")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--preset", default="all", choices=("all", *PRESETS),
                        help="corrections preset(s) to render (default: all)")
    parser.add_argument("--reference", default="visible", choices=REFERENCE_CHOICES,
                        help="visible: shadow rays between VPLs and pixels; unoccluded: no "
                             "visibility, what LPV without a geometry volume approximates "
                             "(default: visible)")
    parser.add_argument("--out", type=Path, default=None, metavar="FOLDER",
                        help="folder for the PNGs and table (default: ./compare-<scene>); "
                             "made before the rendering starts. It replaces only files "
                             "it wrote there itself (listed in its .lpv-explorer-compare): "
                             "a file of a name it writes that it did not write, such as your "
                             "own table.md or one of an older compare's, is refused, "
                             "never overwritten")
    parser.add_argument("--min-distance", metavar="X",
                        type=options.value_type("min_distance", MIN_DISTANCE),
                        default=None, help=options.spec_help(MIN_DISTANCE))
    parser.add_argument("--error-mode", default="log2-ratio",
                        choices=("log2-ratio", "difference"),
                        help="what the error image shows (default: log2-ratio)")
    parser.add_argument("--error-scale", metavar="X",
                        type=options.value_type("error_scale", ERROR_SCALE),
                        default=None, help=options.spec_help(ERROR_SCALE))
    parser.add_argument("--exposure", metavar="X", type=options.setting_type("exposure"),
                        default=None,
                        help="exposure of the LPV/reference PNGs (default: the reference's "
                             "99th percentile maps to white)")
    parser.add_argument("--region", action="append", default=[], metavar="X0,Y0,X1,Y1",
                        type=parse_region,
                        help="also report the metrics over this pixel rectangle (rows from "
                             "the top of the PNG, X1 and Y1 excluded); repeatable")
    parser.add_argument("--region-mask", action="append", default=[], metavar="NAME",
                        help="also report the metrics over the pixels that see the scene's "
                             "surface NAME (a part such as 'tall block' or 'north curtains', "
                             "else a movable object; explorer/scene/parts.py); an unknown "
                             "name lists the scene's surfaces; repeatable")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    parser.add_argument("--json", action="store_true",
                        help="print the rows as JSON on stdout (every metric at full "
                             "precision) instead of the markdown table; table.json is also "
                             "written")
    parser.add_argument("--dump", type=Path, default=None, metavar="FILE.npz",
                        help="also write the last frame's stages as float arrays and the "
                             "reference image (`reference`), with FILE.json (as `render "
                             "--dump`)")
    compare_truth.add_arguments(parser)
    options.add_setting_options(parser, exclude=("corrections", "exposure", "indirect_only"),
                        sweep=("iterations", "cascades", "sh_order"), defaults=DEFAULTS,
                        aliases={"grid_size": ("--grid-size",)})
    for name in ("width", "height"):     # compare's own spelling of --size, kept
        spec = specs(Settings)[name]
        parser.add_argument(f"--{name}", dest=name, type=options.setting_type(name), default=None,
                            metavar="N", help=f"image {name} in pixels (or --size WxH); "
                            f"{spec.allowed()}; default {DEFAULTS['size'][0]}")


def parse_region(text: str) -> tuple[int, int, int, int]:
    """``X0,Y0,X1,Y1`` with 0 <= X0 < X1 and 0 <= Y0 < Y1 (argparse ``type=``)."""
    parts = text.split(",")
    try:
        if len(parts) != 4:
            raise ValueError
        x0, y0, x1, y1 = (int(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected four integers X0,Y0,X1,Y1, got "
                                         f"{text!r}") from None
    if not (0 <= x0 < x1 and 0 <= y0 < y1):
        raise argparse.ArgumentTypeError(f"{text!r}: need 0 <= X0 < X1 and 0 <= Y0 < Y1")
    return x0, y0, x1, y1


@dataclass(frozen=True)
class Run:
    """One LPV frame of the comparison and how its files are named."""

    settings: Settings
    label: str        # file names: lpv-<label>.png, error-<label>.png
    preset: str       # the preset's name (the table adds the SH order when swept)


@dataclass
class CompareRow:
    """One line of the table: a frame's metrics over the whole image or one region
    (``stats`` None: the region held no visible pixel)."""

    preset: str
    iterations: int
    cascades: int
    sh_order: int
    region: str                     # "image", "x0,y0,x1,y1" or a --region-mask name
    stats: object | None            # explorer.truth.metrics.ErrorStats
    means: tuple[float, float] | None = None    # LPV and reference mean radiance


@dataclass
class Comparison:
    rows: list[CompareRow]
    images: dict[str, object]       # PNG label -> the LPV's indirect image (H, W, 3)
    reference: object               # the reference image of the last frame (H, W, 3)
    valid: object                   # (H, W) pixels that see a surface
    frame: object                   # the last FrameResult (its settings head the table)
    regions: dict = field(default_factory=dict)  # region name -> (H, W) mask, "image" first


class ReferenceCache:
    """Reference images already rendered in this process, reused for a frame with the same
    scene, image size, visibility, ``r_min`` and VPLs (the reference depends on nothing
    else): the presets, iteration counts and options of one scene share one reference."""

    def __init__(self) -> None:
        self._entries: list[tuple[tuple, object, tuple]] = []

    def get(self, key: tuple, vpls) -> tuple | None:
        for entry_key, entry_vpls, value in self._entries:
            if entry_key == key and _same_vpls(vpls, entry_vpls):
                return value
        return None

    def put(self, key: tuple, vpls, value: tuple) -> None:
        self._entries.append((key, vpls, value))


def plan_runs(args: argparse.Namespace, base: Settings) -> list[Run]:
    """Every frame the command renders, each Settings made (so checked) before any work."""
    iterations = options.sweep_values(args, "iterations", base)
    cascades = options.sweep_values(args, "cascades", base)
    orders = options.sweep_values(args, "sh_order", base)
    names = list(PRESETS) if args.preset == "all" else [args.preset]
    runs = []
    for name in names:
        for steps in iterations:
            for count in cascades:
                for order in orders:
                    try:
                        settings = base.with_changes(corrections=PRESETS[name],
                                                     iterations=steps, cascades=count,
                                                     sh_order=order)
                    except ValueError as exc:
                        raise options.CommandError(exc) from None
                    label = name if len(iterations) == 1 else f"{name}-it{steps}"
                    if args.cascades is not None:
                        label += f"-c{count}"
                    if args.sh_order is not None:
                        label += f"-L{order}"
                    runs.append(Run(settings, label, name))
    return runs


def check_cost(settings: Settings, regions: list[tuple[int, int, int, int]],
               views: int = 1) -> None:
    """The reference's pixel × VPL pairs within :data:`MAX_REFERENCE_PAIRS` (``views`` RSM
    views: several lights, a point light's six faces), and every region inside the
    image."""
    texels = settings.rsm_size // (settings.downsample_factor
                                   if settings.downsample != "none" else 1)
    vpls = views * max(texels, 1) ** 2
    pairs = settings.width * settings.height * vpls
    if pairs > MAX_REFERENCE_PAIRS:
        raise options.CommandError(f"the reference would gather {settings.width}×{settings.height} "
                           f"pixels × up to {vpls} VPLs = {pairs:.3g} pairs, "
                           f"more than {MAX_REFERENCE_PAIRS:.3g}: use a smaller --size or "
                           f"--rsm-size")
    for x0, y0, x1, y1 in regions:
        if x1 > settings.width or y1 > settings.height:
            raise options.CommandError(f"--region {x0},{y0},{x1},{y1} leaves the {settings.width}×"
                               f"{settings.height} image")


def check_masks(scene, names: list[str]) -> None:
    """Every ``--region-mask`` name a surface of ``scene`` (explorer/scene/parts.py)."""
    from explorer.truth.surface_masks import check_surface_names

    try:
        check_surface_names(scene, names)
    except ValueError as exc:
        raise options.CommandError(f"--region-mask: {exc}") from None


def main(args: argparse.Namespace) -> int:
    from explorer.gl.context import GLUnavailableError, given_or_headless

    base = options.settings_from_args(args)
    options.check_scene(base.scene)
    runs = plan_runs(args, base)
    scene = load_scene(base)
    check_cost(base, args.region, _view_count(scene))
    check_masks(scene, args.region_mask)
    compare_truth.check_available(args)
    out = args.out if args.out is not None else Path(f"compare-{Path(base.scene).stem}")
    with options.Outputs() as outputs:
        outputs.folder(out)
        earlier = compare_folder.earlier_names(out)
        compare_folder.check_names(out, compare_folder.planned_names(
            [run.label for run in runs]), earlier)
        if args.dump is not None:
            args.dump = outputs.file(args.dump, (".npz",), option="--dump")
            outputs.file(args.dump.with_suffix(".json"), (".json",), option="--dump")
        with options.Progress("compare", enabled=False if args.quiet else None) as progress:
            try:
                with given_or_headless(None) as ctx:
                    comparison = run_comparison(args, runs, ctx, scene, progress=progress)
            except GLUnavailableError as exc:
                raise options.CommandError(exc, 1) from None
            except options.render_failures() as exc:
                raise options.CommandError(exc, 1) from None
        table = format_table(comparison.rows, args, comparison.frame)
        report = json_report(comparison, args)
        print(report if args.json else table)
        reference, valid = comparison.reference, comparison.valid
        exposure = args.exposure or _auto_exposure(reference, valid)
        written = _write(outputs, out, args, comparison.images, reference, valid, exposure)
        if args.truth == "mitsuba":
            truth_table, truth_files = compare_truth.run(args, comparison, scene,
                                                         comparison.regions, outputs, out,
                                                         exposure)
            print("\n" + truth_table)
            table += "\n\n" + truth_table
            written += truth_files
        names = [*written, "table.md", "table.json"]
        compare_folder.check_names(out, names, earlier)     # the Mitsuba images' names too
        listing = compare_folder.listing_text(names, earlier, out)
        outputs.write(out / compare_folder.LISTING_FILE, lambda p: p.write_text(listing))
        outputs.write(out / "table.md", lambda p: p.write_text(table + "\n"))
        outputs.write(out / "table.json", lambda p: p.write_text(report + "\n"))
        if args.dump is not None:
            from explorer.commands.render import write_dump

            write_dump(outputs, args.dump, comparison.frame, reference,
                       extra={"reference_options": {"visibility": args.reference,
                                                    "min_distance": args.min_distance}},
                       stream=sys.stderr if args.json else sys.stdout)
    print(f"wrote {', '.join(written)}, table.md, table.json to {out}/ (PNG exposure "
          f"{exposure:.4g})", file=sys.stderr if args.json else sys.stdout)
    return 0


def json_report(comparison: Comparison, args: argparse.Namespace) -> str:
    """The rows as JSON (``--json``, table.json): what was compared and, per row, every
    metric at full precision (None for an empty region)."""
    import json

    rows = []
    for row in comparison.rows:
        stats = row.stats
        rows.append({
            "preset": row.preset, "iterations": row.iterations, "cascades": row.cascades,
            "sh_order": row.sh_order, "region": row.region,
            "relative_l2": None if stats is None else stats.relative_l2,
            "rmse": None if stats is None else stats.rmse,
            "flux_ratio": None if stats is None else stats.flux_ratio,
            "flux_ratio_rgb": None if stats is None else list(stats.flux_ratio_rgb),
            "pixels": 0 if stats is None else stats.pixels,
            "lpv_mean": None if row.means is None else row.means[0],
            "reference_mean": None if row.means is None else row.means[1]})
    frame = comparison.frame
    return json.dumps({"compared": settings_line(args, frame), "reference": args.reference,
                       "settings": frame.settings.to_dict(), "vpls": frame.vpls.count,
                       "rows": rows}, indent=2, ensure_ascii=False)


def load_scene(base: Settings):
    from explorer.scene import SceneError
    from explorer.truth.gbuffer import scene_for

    try:
        return scene_for(base)
    except (SceneError, FileNotFoundError, KeyError, ValueError) as exc:
        raise options.CommandError(f"cannot load scene {base.scene!r}: {exc}") from None


def _view_count(scene) -> int:
    """RSM views of the lights that shine: one per spot or directional light, six per point
    light."""
    return sum(6 if light.kind == "point" else 1 for light in scene.lights)


def reference_distance(args: argparse.Namespace, runs: list[Run], scene) -> float | None:
    """The reference's ``r_min``: ``--min-distance``, or None (half a cell of the frame's
    grid) unless cascades are compared: then half a cell of the single grid, for every
    cascade count (cascade 0's cells shrink with more cascades, the reference must not)."""
    if args.min_distance is not None or max(r.settings.cascades for r in runs) == 1:
        return args.min_distance
    from explorer.lpv.cascades import single_spec

    return 0.5 * single_spec(runs[0].settings, scene).cell_size


def run_comparison(args: argparse.Namespace, runs: list[Run], ctx, scene,
                   references: ReferenceCache | None = None,
                   progress: options.Progress | None = None) -> Comparison:
    """Render every run's LPV frame and its metrics against the one-bounce reference
    (rendered once per distinct VPL set, or taken from ``references``)."""
    import numpy as np

    from explorer.lpv.pipeline import Pipeline
    from explorer.truth.metrics import rect_mask
    from explorer.truth.render import reference_for_frame
    from explorer.truth.surface_masks import render_triangle_ids, surface_masks

    references = references if references is not None else ReferenceCache()
    visibility = args.reference == "visible"
    min_distance = reference_distance(args, runs, scene)
    rows, images = [], {}
    reference = gbuffer = frame = None
    names = getattr(args, "region_mask", [])
    masks = {}
    if names:   # the runs differ in the LPV's settings only: one scene, one image size
        first = runs[0].settings
        masks = surface_masks(scene, render_triangle_ids(ctx, scene, first.width,
                                                         first.height), names)
    keep_steps = getattr(args, "dump", None) is not None     # --dump writes grid_0 … grid_N
    with Pipeline(runs[0].settings, ctx) as pipeline:
        for run in runs:
            frame = options.run_pipeline(pipeline, run.settings, progress,
                                         keep_steps=keep_steps)
            settings = frame.settings
            key = (settings.scene, settings.width, settings.height, visibility,
                   min_distance if min_distance is not None
                   else 0.5 * frame.grid_spec.cell_size)
            cached = references.get(key, frame.vpls)
            if cached is None:
                started = time.perf_counter()
                cached = reference_for_frame(
                    frame, visibility, min_distance, ctx=ctx, scene=scene,
                    progress=None if progress is None else progress.fraction("reference"))
                references.put(key, frame.vpls, cached)
                if progress is not None:
                    progress.close()
                if not getattr(args, "quiet", True):
                    print(f"reference ({args.reference}, {frame.vpls.count} VPLs): "
                          f"{time.perf_counter() - started:.1f} s", file=sys.stderr)
            reference, gbuffer = cached
            valid = gbuffer.valid
            lpv = np.asarray(frame.indirect, np.float64)[..., :3]
            images[run.label] = lpv
            cells = (run.preset, settings.iterations, settings.cascades, settings.sh_order)
            regions = {"image": valid}
            for rect in args.region:           # rows from the top
                regions[",".join(map(str, rect))] = rect_mask(valid.shape, [rect]) & valid
            for name, mask in masks.items():
                regions[name] = mask & valid
            for region, mask in regions.items():
                rows.append(CompareRow(*cells, region, *region_metrics(lpv, reference, mask)))
    return Comparison(rows, images, reference, gbuffer.valid, frame, regions)


def _write(outputs: options.Outputs, out: Path, args, images: dict, reference, valid,
           exposure: float) -> list[str]:
    """The reference, LPV and error PNGs; returns their names."""
    from explorer.truth.metrics import error_image

    outputs.write(out / "reference.png", lambda p: save_png(p, reference * exposure))
    written = ["reference.png"]
    scale = args.error_scale
    if scale is None:
        # One scale for every error image so that they compare: three stops for the log
        # ratio; for the difference, the reference's bright end (99th percentile).
        scale = LOG2_DEFAULT_SCALE if args.error_mode == "log2-ratio" else 1.0 / exposure
    for label, lpv in images.items():
        outputs.write(out / f"lpv-{label}.png", lambda p, lpv=lpv: save_png(p, lpv * exposure))
        error = error_image(lpv, reference, valid, args.error_mode, scale)
        outputs.write(out / f"error-{label}.png", lambda p, e=error: save_error_png(p, e))
        written += [f"lpv-{label}.png", f"error-{label}.png"]
    return written


def _same_vpls(a, b) -> bool:
    import numpy as np

    return (b is not None and a.count == b.count
            and np.array_equal(np.asarray(a.positions), np.asarray(b.positions))
            and np.array_equal(np.asarray(a.flux), np.asarray(b.flux)))


MEAN_HEADERS = ("pixels", "LPV mean", "ref. mean")


def mean_cells(row: CompareRow) -> list[str]:
    """The pixel count and the two mean radiances of a row (:data:`MEAN_HEADERS`)."""
    if row.stats is None or row.means is None:
        return ["0", "–", "–"]
    return [str(row.stats.pixels), *(f"{value:.4g}" for value in row.means)]


def _cells_text(cells: tuple[int, int, int]) -> str:
    return f"{cells[0]}³" if len(set(cells)) == 1 else "×".join(map(str, cells))


def settings_line(args: argparse.Namespace, frame) -> str:
    """The line above the table: what was compared."""
    settings = frame.settings
    scene = f"scene `{settings.scene}`"
    rsm = f"RSM {settings.rsm_size}² ({frame.vpls.count} VPLs)"
    if len(frame.vpl_sets) > 1:      # several lights, or a point light's six faces
        scene += f" (lights {', '.join(frame.light_names)}: {len(frame.vpl_sets)} RSM views)"
        rsm = f"RSM {settings.rsm_size}² per view ({frame.vpls.count} VPLs)"
    return (f"{scene}, reference `{args.reference}`, {settings.width}×{settings.height} px, "
            f"{rsm}, grid {_cells_text(frame.grid_spec.cells)}, geometry volume "
            f"`{settings.geometry_volume}`, injection offset "
            f"{settings.injection_offset_cells:g} cells, gather damping "
            f"{'on' if settings.gather_damping else 'off'}, bounces {settings.bounces}")


def format_table(rows: list[CompareRow], args: argparse.Namespace, frame) -> str:
    """Markdown table: one row per preset, iteration count (and cascade count, SH order
    when those options were given) and region."""
    lines = [
        settings_line(args, frame),
        "",
        "| preset | iterations | region | " + " | ".join(METRIC_HEADERS + MEAN_HEADERS)
        + " |",
        "|---|---:|---|" + "|".join(METRIC_ALIGN + ("---:",) * len(MEAN_HEADERS)) + "|",
    ]
    for row in rows:
        name = row.preset if args.sh_order is None else f"{row.preset} L{row.sh_order}"
        steps = str(row.iterations)
        if args.cascades is not None:   # the iterations cell: "8, 2 cascades"
            steps += f", {row.cascades} cascade{'s' if row.cascades > 1 else ''}"
        lines.append(f"| {name} | {steps} | {row.region} | "
                     + " | ".join(metric_cells(row.stats) + mean_cells(row)) + " |")
    return "\n".join(lines)


def _auto_exposure(reference, valid) -> float:
    import numpy as np

    values = np.asarray(reference)[valid]
    top = float(np.percentile(values, 99.0)) if values.size else 0.0
    return 1.0 / top if top > 0 else 1.0
