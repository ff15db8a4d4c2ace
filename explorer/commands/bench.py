"""``lpv-explorer bench``: milliseconds per pass and per frame over grid sizes and
iteration counts, and the memory bandwidth the propagation achieves.

With ``--cascades`` every cascade count is a row: the inject, geometry and propagate
columns then hold all cascades together (each cascade is a full grid), and the bandwidth
counts every cascade's grids.

``--scene`` picks what is rendered; the header names it with its triangle count, which
the RSM and G-buffer passes scale with: ``bench --scene atrium`` times the large
procedural courtyard (over 100 000 triangles) instead of the 34-triangle Cornell box.

Bandwidth model: one propagation step reads the previous grid and writes the next one
(3 textures × one texel per cell each) and reads and writes the accumulation grid, so it
moves at least ``4 × 3 × texel_bytes`` per cell (192 B with rgba32f, 96 B with rgba16f);
neighbour reads are assumed to hit the cache. The propagate pass time also holds the
energy-audit reduction and the copy of grid_0 into the accumulation grid, so the figure is
a lower bound of what the propagation kernel alone reaches. With ``--sh-order 2`` (L2) a
cell holds 3 texels per channel, so a step moves 3× as many bytes.
"""

from __future__ import annotations

import argparse
import datetime
import json
import statistics
import sys
from pathlib import Path

from explorer.commands.render import parse_size
from explorer.lpv.settings import GEOMETRY_VOLUME_MODES, GRID_FORMATS, PRESETS

FULL_GRIDS = (16, 32, 64, 128)
FULL_ITERATIONS = (4, 8, 16, 32, 64)
SOFTWARE_GRIDS = (16, 32, 64)
SOFTWARE_ITERATIONS = (4, 8, 16)
QUICK_GRIDS = (8, 16)
QUICK_ITERATIONS = (2, 4)
TEXEL_BYTES = {"rgba32f": 16, "rgba16f": 8}
PASS_COLUMNS = ("rsm", "downsample", "inject", "geometry", "propagate", "gbuffer", "gather",
                "display")
VARIANTS: dict[str, dict[str, object]] = {
    "offset-0": {"injection_offset_cells": 0.0},
    "damping": {"gather_damping": True},
    "bounces-2": {"bounces": 2},
}
"""Extra rows (at each grid's largest iteration count): the leak-reduction and bounce
options against the default settings. bounces-2 turns a one-sided geometry volume on if
--geometry-volume is off (it needs one)."""


def parse_variants(text: str) -> tuple[str, ...]:
    names = tuple(part.strip() for part in text.split(",") if part.strip())
    if names == ("none",):
        return ()
    unknown = [name for name in names if name not in VARIANTS]
    if unknown or not names:
        raise argparse.ArgumentTypeError(f"variants must be 'none' or a comma list of "
                                         f"{', '.join(VARIANTS)}; got {text!r}")
    return names


def parse_list(text: str) -> tuple[int, ...]:
    try:
        values = tuple(int(part) for part in text.split(",") if part.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas, got "
                                         f"{text!r}") from None
    if not values or min(values) < 0:
        raise argparse.ArgumentTypeError(f"expected non-negative numbers, got {text!r}")
    return values


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--scene", default="cornell",
                        help="scene to render (default cornell; atrium: the large procedural "
                             "courtyard)")
    parser.add_argument("--preset", default="corrected", choices=sorted(PRESETS))
    parser.add_argument("--grids", type=parse_list,
                        help="grid resolutions, e.g. 16,32,64,128 (default: that list on a "
                             "GPU, 16,32,64 on a software renderer)")
    parser.add_argument("--iterations", type=parse_list,
                        help="propagation steps, e.g. 4,8,16,32,64 (default: that list on a "
                             "GPU, 4,8,16 on a software renderer)")
    parser.add_argument("--size", type=parse_size, default=(512, 512),
                        help="image size WxH (default 512x512)")
    parser.add_argument("--rsm-size", type=int, default=256, help="RSM size (default 256)")
    parser.add_argument("--format", default="rgba32f", choices=GRID_FORMATS,
                        help="grid texture format")
    parser.add_argument("--geometry-volume", default="off", choices=GEOMETRY_VOLUME_MODES)
    parser.add_argument("--variants", type=parse_variants, default=tuple(VARIANTS),
                        help=f"extra rows at each grid's largest iteration count: "
                             f"{', '.join(VARIANTS)} (comma list) or none (default: all)")
    parser.add_argument("--cascades", type=parse_list, default=(1,),
                        help="LPV cascade counts, e.g. 1,2,3 (default 1); each count is a "
                             "row per grid and iteration count")
    parser.add_argument("--sh-order", type=parse_list, default=(1,),
                        help="SH orders of the grid, e.g. 1,2 (L1 and L2; default 1); each "
                             "order is a row per grid and iteration count")
    parser.add_argument("--repeat", type=int, default=3,
                        help="timed frames per configuration; the median is reported")
    parser.add_argument("--quick", action="store_true",
                        help="CI-sized run: grids 8,16, iterations 2,4, 64x64 image, 64² RSM, "
                             "one timed frame")
    parser.add_argument("--peak-gbs", type=float,
                        help="the device's peak memory bandwidth in GB/s, to print the "
                             "propagation's share of it")
    parser.add_argument("--json", type=Path, help="also write the results as JSON here")


def propagation_bytes(grid: int, iterations: int, fmt: str, sh_order: int = 1) -> int:
    """Bytes one frame's propagation moves at least (module docstring); L2 (``sh_order``
    2) stores 3 texels per cell and channel."""
    groups = 3 if sh_order == 2 else 1
    return 4 * 3 * groups * TEXEL_BYTES[fmt] * grid**3 * iterations


def run_bench(args: argparse.Namespace, pipeline) -> list[dict]:
    from explorer.lpv.settings import Settings, preset

    quick = args.quick
    if quick:
        grids, iterations = args.grids or QUICK_GRIDS, args.iterations or QUICK_ITERATIONS
        width, height, rsm_size, repeat = 64, 64, 64, 1
    else:
        software = pipeline.software_renderer
        grids = args.grids or (SOFTWARE_GRIDS if software else FULL_GRIDS)
        iterations = args.iterations or (SOFTWARE_ITERATIONS if software else FULL_ITERATIONS)
        (width, height), rsm_size, repeat = args.size, args.rsm_size, max(1, args.repeat)
    rows = []
    cascade_counts = getattr(args, "cascades", None) or (1,)
    sh_orders = getattr(args, "sh_order", None) or (1,)
    for order in sh_orders:
        if order not in (1, 2):
            raise ValueError(f"--sh-order: the SH order must be 1 (L1) or 2 (L2), got {order}")
    for grid in grids:
        runs = [("default", steps, k, order, {}) for steps in iterations
                for k in cascade_counts for order in sh_orders]
        runs += [(name, max(iterations), 1, sh_orders[0], VARIANTS[name])
                 for name in args.variants]
        for variant, steps, cascades, order, changes in runs:
            settings = Settings(scene=args.scene, corrections=preset(args.preset),
                                grid_size=grid, iterations=steps, rsm_size=rsm_size,
                                width=width, height=height, grid_format=args.format,
                                geometry_volume=args.geometry_volume, cascades=cascades,
                                sh_order=order)
            if changes.get("bounces", 1) > 1 and settings.geometry_volume == "off":
                changes = {**changes, "geometry_volume": "one-sided"}
            settings = settings.with_changes(**changes)
            pipeline.run(settings)                    # warm-up: compiles, allocates
            samples: dict[str, list[float]] = {}
            for _ in range(repeat):
                pipeline.invalidate("rsm")
                result = pipeline.run(settings)
                for name in result.stages_run:
                    if name in result.timings_ms:
                        samples.setdefault(name, []).append(result.timings_ms[name])
            passes = {name: statistics.median(values) for name, values in samples.items()}
            row = {"variant": variant, "grid": grid, "iterations": steps, "cascades": cascades,
                   "sh_order": order, "passes_ms": passes, "frame_ms": sum(passes.values()),
                   "methods": dict(pipeline.timing_methods)}
            propagate_ms = passes.get("propagate", 0.0)
            if steps > 0 and propagate_ms > 0:
                moved = cascades * propagation_bytes(grid, steps, args.format, order)
                row["propagation_gbs"] = moved / (propagate_ms * 1e-3) / 1e9
                row["ms_per_step"] = propagate_ms / steps
            rows.append(row)
    return rows


def format_table(rows: list[dict], peak_gbs: float | None) -> str:
    header = ["variant", "grid", "iters", "cascades", "sh", *PASS_COLUMNS, "frame", "ms/step",
              "GB/s"]
    if peak_gbs:
        header.append("% peak")
    lines = ["  ".join(f"{h:>10}" for h in header)]
    for row in rows:
        cells = [row.get("variant", "default"), f"{row['grid']}³", str(row["iterations"]),
                 str(row.get("cascades", 1)), f"L{row.get('sh_order', 1)}"]
        cells += [f"{row['passes_ms'][name]:.2f}" if name in row["passes_ms"] else "-"
                  for name in PASS_COLUMNS]
        cells.append(f"{row['frame_ms']:.2f}")
        cells.append(f"{row['ms_per_step']:.3f}" if "ms_per_step" in row else "-")
        gbs = row.get("propagation_gbs")
        cells.append(f"{gbs:.2f}" if gbs is not None else "-")
        if peak_gbs:
            cells.append(f"{100 * gbs / peak_gbs:.1f}" if gbs is not None else "-")
        lines.append("  ".join(f"{c:>10}" for c in cells))
    return "\n".join(lines)


def main(args: argparse.Namespace) -> int:
    from explorer.gl.context import GLUnavailableError, probe
    from explorer.lpv.pipeline import Pipeline
    from explorer.lpv.settings import Settings
    from explorer.scene import SceneError

    if args.peak_gbs is not None and not args.peak_gbs > 0:
        print("lpv-explorer bench: error: --peak-gbs must be positive", file=sys.stderr)
        return 2
    try:
        with Pipeline(Settings(scene=args.scene)) as pipeline:
            caps = probe(pipeline.ctx)
            rows = run_bench(args, pipeline)
            triangles = pipeline.base_scene.triangle_count
    except (SceneError, ValueError) as exc:
        print(f"lpv-explorer bench: error: {exc}", file=sys.stderr)
        return 2
    except (GLUnavailableError, FloatingPointError) as exc:
        print(f"lpv-explorer bench: error: {exc}", file=sys.stderr)
        return 1
    methods = sorted({method for row in rows for method in row["methods"].values()})
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    print(f"device: {caps.renderer} ({caps.version}); {when}")
    print(f"scene {args.scene} ({triangles} triangles), preset {args.preset}, "
          f"format {args.format}, "
          f"geometry volume {args.geometry_volume}; timing: {', '.join(methods)}; "
          f"milliseconds per pass (median){' [quick]' if args.quick else ''}")
    print(format_table(rows, args.peak_gbs))
    if args.peak_gbs is None:
        print("(pass --peak-gbs <device peak bandwidth in GB/s> to see the share reached)")
    if args.json is not None:
        args.json.write_text(json.dumps({"device": caps.renderer, "version": caps.version,
                                         "date": when, "scene": args.scene,
                                         "triangles": triangles, "rows": rows}, indent=2))
    return 0
