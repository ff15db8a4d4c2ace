"""``lpv-explorer compare``: LPV against the one-bounce reference, as a table and PNGs.

Both images come from the same frame: the reference gathers the very VPLs the LPV
injected, at the pixels the camera sees, so the error measures what the grid (injection,
propagation, gather and the formulas the preset selects) does to that light.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from explorer.commands.render import (
    LIGHT_OPTIONS,
    add_leak_arguments,
    add_light_arguments,
    leak_changes,
    option_changes,
)
from explorer.lpv.settings import CASCADE_ITERATIONS, GEOMETRY_VOLUME_MODES

PRESET_CHOICES = ("all", "original", "corrected")
REFERENCE_CHOICES = ("visible", "unoccluded")
LOG2_DEFAULT_SCALE = 3.0  # error images saturate at 8× too bright / too dark


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--scene", default="cornell",
                        help="built-in scene name or mesh file (default: cornell)")
    parser.add_argument("--preset", default="all", choices=PRESET_CHOICES,
                        help="corrections preset(s) to render (default: all)")
    parser.add_argument("--reference", default="visible", choices=REFERENCE_CHOICES,
                        help="visible: shadow rays between VPLs and pixels; unoccluded: no "
                             "visibility, what LPV without a geometry volume approximates "
                             "(default: visible)")
    parser.add_argument("--out", type=Path, default=None,
                        help="folder for the PNGs and table (default: ./compare-<scene>)")
    parser.add_argument("--width", type=int, default=256, help="image width (default 256)")
    parser.add_argument("--height", type=int, default=256, help="image height (default 256)")
    parser.add_argument("--rsm-size", type=int, default=64,
                        help="RSM side = VPLs per side; the reference costs pixels × VPLs "
                             "(default 64)")
    parser.add_argument("--grid-size", type=int, default=None,
                        help="LPV resolution (default: the Settings default)")
    parser.add_argument("--iterations", default=None, metavar="N[,N...]",
                        help="propagation steps, or a comma list for a sweep (default: the "
                             "Settings default)")
    parser.add_argument("--cascades", default=None, metavar="K[,K...]",
                        help="LPV cascades (nested grids around the camera's focus), or a "
                             "comma list to compare several (default: 1, the single grid)")
    parser.add_argument("--cascade-iterations", default="same",
                        choices=CASCADE_ITERATIONS,
                        help="propagation steps per cascade: the same in every cascade "
                             "(default), or 2x more per finer level (same distance)")
    parser.add_argument("--geometry-volume", default="off",
                        choices=GEOMETRY_VOLUME_MODES,
                        help="LPV occlusion (default: off)")
    parser.add_argument("--sh-order", default=None, metavar="ORDER[,ORDER]",
                        help="spherical harmonics of the grid: 1 (L1, default), 2 (L2), or "
                             "1,2 to compare both; the table's preset cell then names it")
    add_leak_arguments(parser)
    add_light_arguments(parser)
    parser.add_argument("--min-distance", type=float, default=None,
                        help="reference 1/r² clamp distance in world units "
                             "(default: half a grid cell; with --cascades above 1, of the "
                             "single scene-enclosing grid)")
    parser.add_argument("--error-mode", default="log2-ratio",
                        choices=("log2-ratio", "difference"),
                        help="what the error image shows (default: log2-ratio)")
    parser.add_argument("--error-scale", type=float, default=None,
                        help="error value at full colour (default: 3 stops for log2-ratio, "
                             "the reference's 99th percentile for difference)")
    parser.add_argument("--exposure", type=float, default=None,
                        help="exposure of the LPV/reference PNGs (default: the reference's "
                             "99th percentile maps to white)")
    parser.add_argument("--region", action="append", default=[], metavar="X0,Y0,X1,Y1",
                        help="also report the metrics over this pixel rectangle (rows from "
                             "the top of the PNG); repeatable")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")


def _fail(message: str, code: int = 2) -> int:
    print(f"lpv-explorer compare: error: {message}", file=sys.stderr)
    return code


def _parse_region(text: str) -> tuple[int, int, int, int]:
    parts = text.split(",")
    if len(parts) != 4:
        raise ValueError(f"--region {text!r}: expected X0,Y0,X1,Y1")
    try:
        x0, y0, x1, y1 = (int(p) for p in parts)
    except ValueError:
        raise ValueError(f"--region {text!r}: expected four integers") from None
    return x0, y0, x1, y1


def main(args: argparse.Namespace) -> int:
    import numpy as np

    from explorer.lpv.settings import PRESETS, Settings

    try:
        regions = [_parse_region(text) for text in args.region]
        iterations = _parse_iterations(args.iterations)
        cascade_counts = _parse_cascades(args.cascades)
        sh_orders = _parse_sh_orders(args.sh_order)
        for name in ("width", "height", "rsm_size"):
            if getattr(args, name) < 1:
                raise ValueError(f"--{name.replace('_', '-')} must be at least 1")
        if args.min_distance is not None and not args.min_distance >= 0:
            raise ValueError("--min-distance must be >= 0")
        if args.error_scale is not None and not args.error_scale > 0:
            raise ValueError("--error-scale must be positive")
        changes = {"scene": args.scene, "width": args.width, "height": args.height,
                   "rsm_size": args.rsm_size, "geometry_volume": args.geometry_volume,
                   "cascade_iterations": args.cascade_iterations}
        if args.grid_size is not None:
            changes["grid_size"] = args.grid_size
        changes.update(leak_changes(args))
        changes.update(option_changes(args, LIGHT_OPTIONS))
        base = Settings(**changes, cascades=max(cascade_counts))   # validates the count
        for order in sh_orders:   # L2 refuses some combinations (e.g. cascades)
            for count in cascade_counts:
                base.with_changes(sh_order=order, cascades=count)
        if iterations is None:
            iterations = [base.iterations]
    except ValueError as exc:
        return _fail(str(exc))

    from explorer.gl.context import (GLUnavailableError, create_headless_context,
                                     release_headless_context)
    from explorer.lpv.pipeline import Pipeline
    from explorer.scene import SceneError
    from explorer.truth.gbuffer import scene_for
    from explorer.truth.metrics import EmptyRegionError, error_image, error_stats, rect_mask
    from explorer.truth.render import reference_for_frame

    try:
        scene = scene_for(base)
    except (SceneError, FileNotFoundError, KeyError, ValueError) as exc:
        return _fail(f"cannot load scene {args.scene!r}: {exc}")
    try:
        ctx = create_headless_context()
    except GLUnavailableError as exc:
        return _fail(str(exc), 1)

    min_distance = args.min_distance
    if min_distance is None and max(cascade_counts) > 1:
        # one reference for every cascade count: half a cell of the single grid (cascade
        # 0's cells shrink with more cascades, the reference must not)
        from explorer.lpv.grid import GridSpec

        single = GridSpec.enclosing(scene.bounds_min, scene.bounds_max, base.grid_size)
        min_distance = 0.5 * single.cell_size
    names = ["original", "corrected"] if args.preset == "all" else [args.preset]
    visibility = args.reference == "visible"
    out = args.out if args.out is not None else Path(f"compare-{Path(args.scene).stem}")
    pipeline = Pipeline(base, ctx)
    rows = []
    images = {}
    reference = gbuffer = reference_vpls = frame = None
    try:
        for name in names:
            for steps, count, order in [(i, k, o) for i in iterations for k in cascade_counts
                                        for o in sh_orders]:
                frame = pipeline.run(base.with_changes(corrections=PRESETS[name],
                                                       iterations=steps, cascades=count,
                                                       sh_order=order))
                if reference is None or not _same_vpls(frame.vpls, reference_vpls):
                    started = time.perf_counter()
                    reference, gbuffer = reference_for_frame(
                        frame, visibility, min_distance, ctx=ctx, scene=scene,
                        progress=None if args.quiet else _progress_printer())
                    reference_vpls = frame.vpls
                    if not args.quiet:
                        print(f"\rreference ({args.reference}, {frame.vpls.count} VPLs): "
                              f"{time.perf_counter() - started:.1f} s", file=sys.stderr)
                valid = gbuffer.valid
                lpv = np.asarray(frame.indirect, np.float64)[..., :3]
                label = name if len(iterations) == 1 else f"{name}-it{steps}"
                if args.cascades is not None:
                    label += f"-c{count}"
                    steps = (steps, count)   # the table's iterations cell: "8, 2 cascades"
                shown = name
                if args.sh_order is not None:
                    label += f"-L{order}"
                    shown = f"{name} L{order}"   # the table's preset cell: "corrected L2"
                images[label] = lpv
                rows.append((shown, steps, "image", error_stats(lpv, reference, valid)))
                for rect in regions:
                    mask = rect_mask(valid.shape, [rect]) & valid  # rows from the top
                    try:
                        stats = error_stats(lpv, reference, mask)
                    except EmptyRegionError:
                        stats = None
                    rows.append((shown, steps, ",".join(map(str, rect)), stats))
    finally:
        pipeline.release()
        release_headless_context(ctx)

    table = format_table(rows, args, frame)
    print(table)
    out.mkdir(parents=True, exist_ok=True)
    valid = gbuffer.valid
    exposure = args.exposure or _auto_exposure(reference, valid)
    _save(out / "reference.png", reference * exposure)
    written = ["reference.png"]
    scale = args.error_scale
    if scale is None:
        # One scale for every error image so that they compare: three stops for the log
        # ratio; for the difference, the reference's bright end (99th percentile).
        scale = LOG2_DEFAULT_SCALE if args.error_mode == "log2-ratio" else 1.0 / exposure
    for label, lpv in images.items():
        _save(out / f"lpv-{label}.png", lpv * exposure)
        error = error_image(lpv, reference, valid, args.error_mode, scale)
        _save_error(out / f"error-{label}.png", error)
        written += [f"lpv-{label}.png", f"error-{label}.png"]
    (out / "table.md").write_text(table + "\n")
    print(f"wrote {', '.join(written)}, table.md to {out}/ (PNG exposure {exposure:.4g})")
    return 0


def _int_list(text: str, flag: str, example: str, valid, rule: str) -> list[int]:
    """A comma list of integers from ``--flag``, each passing ``valid``; errors name the
    flag, the expected form (``example``) and the ``rule`` broken."""
    try:
        values = [int(part) for part in text.split(",")]
    except ValueError:
        raise ValueError(f"{flag} {text!r}: expected {example}") from None
    if not all(valid(v) for v in values):
        raise ValueError(f"{flag} {text!r}: {rule}")
    return values


def _parse_iterations(text: str | None) -> list[int] | None:
    if text is None:
        return None
    return _int_list(text, "--iterations", "integers like 16 or 0,4,16", lambda v: v >= 0,
                     "iterations must be >= 0")


def _parse_cascades(text: str | None) -> list[int]:
    from explorer.lpv.settings import MAX_CASCADES

    if text is None:
        return [1]
    return _int_list(text, "--cascades", "integers like 2 or 1,2,3",
                     lambda v: 1 <= v <= MAX_CASCADES, f"cascades must be 1..{MAX_CASCADES}")


def _parse_sh_orders(text: str | None) -> list[int]:
    from explorer.lpv.settings import SH_ORDERS

    if text is None:
        return [1]
    return _int_list(text, "--sh-order", "1, 2 or 1,2", lambda v: v in SH_ORDERS,
                     "the SH order must be 1 (L1) or 2 (L2)")


def _same_vpls(a, b) -> bool:
    import numpy as np

    return (b is not None and a.count == b.count
            and np.array_equal(np.asarray(a.positions), np.asarray(b.positions))
            and np.array_equal(np.asarray(a.flux), np.asarray(b.flux)))


def _progress_printer():
    last = [-1]

    def report(done: float) -> bool:
        percent = int(100 * done)
        if percent != last[0]:
            last[0] = percent
            print(f"\rreference: {percent:3d} %", end="", file=sys.stderr, flush=True)
        return True

    return report


def format_table(rows, args, frame) -> str:
    """Markdown table: one row per preset, iteration count and region."""
    settings = frame.settings
    lines = [
        f"scene `{args.scene}`, reference `{args.reference}`, {settings.width}×"
        f"{settings.height} px, RSM {settings.rsm_size}² ({frame.vpls.count} VPLs), grid "
        f"{settings.grid_size}³, geometry volume `{settings.geometry_volume}`, injection "
        f"offset {settings.injection_offset_cells:g} cells, gather damping "
        f"{'on' if settings.gather_damping else 'off'}, bounces {settings.bounces}",
        "",
        "| preset | iterations | region | rel. L2 | RMSE | flux ratio LPV/ref | ratio r, g, b |",
        "|---|---:|---|---:|---:|---:|---|",
    ]
    for name, steps, region, stats in rows:
        if isinstance(steps, tuple):   # with --cascades
            steps = f"{steps[0]}, {steps[1]} cascade{'s' if steps[1] > 1 else ''}"
        if stats is None:
            lines.append(f"| {name} | {steps} | {region} | – | – | – | empty region |")
            continue
        rgb = ", ".join(f"{v:.3f}" for v in stats.flux_ratio_rgb)
        lines.append(f"| {name} | {steps} | {region} | {stats.relative_l2:.3f} | "
                     f"{stats.rmse:.4g} | {stats.flux_ratio:.3f} | {rgb} |")
    return "\n".join(lines)


def _auto_exposure(reference, valid) -> float:
    import numpy as np

    values = np.asarray(reference)[valid]
    top = float(np.percentile(values, 99.0)) if values.size else 0.0
    return 1.0 / top if top > 0 else 1.0


def _to_srgb8(linear):
    import numpy as np

    x = np.clip(np.nan_to_num(np.asarray(linear, np.float64)), 0.0, 1.0)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (srgb * 255.0 + 0.5).astype(np.uint8)


def _save(path: Path, linear) -> None:
    """Linear (H, W, 3), row 0 at the top (FrameResult's order), to an sRGB PNG."""
    from PIL import Image

    Image.fromarray(_to_srgb8(linear)).save(path)


def _save_error(path: Path, error) -> None:
    """The false-colour error (already display colours) with a colour bar and its scale."""
    import numpy as np
    from PIL import Image, ImageDraw

    from explorer.truth.metrics import diverging_colormap

    height, width = error.rgb.shape[:2]
    ramp_height, text_height = max(6, height // 20), 12
    ramp = np.linspace(-error.scale, error.scale, width)
    bar = np.broadcast_to(diverging_colormap(ramp, error.scale)[None], (ramp_height, width, 3))
    canvas = np.ones((height + ramp_height + 2 * text_height, width, 3))
    canvas[:height] = error.rgb
    canvas[height:height + ramp_height] = bar
    image = Image.fromarray((np.clip(canvas, 0, 1) * 255 + 0.5).astype(np.uint8))
    draw = ImageDraw.Draw(image)
    unit = "log2(LPV/ref)" if error.mode == "log2-ratio" else "LPV - ref"
    y = height + ramp_height
    # first text row: the values at the ends of the ramp; second row: what is shown
    draw.text((1, y), f"-{error.scale:.3g}", fill=(0, 0, 0))
    label = f"+{error.scale:.3g}"
    draw.text((max(width - 6 * len(label) - 1, 0), y), label, fill=(0, 0, 0))
    draw.text((1, y + text_height), unit, fill=(0, 0, 0))
    image.save(path)
