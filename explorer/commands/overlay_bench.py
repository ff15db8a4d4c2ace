"""Time the overlay compositor against the pipeline's own passes, in the same run:
``python -m explorer.commands.overlay_bench [--size 512x512] [--grid 32] [--rsm 256]``.

Each row redraws the picture ``--repeat`` times with one overlay on and prints the median
wall-clock milliseconds (``ctx.finish()`` around each draw): moving the slice a layer each
time (the static layer of frame, blockers and VPLs is reused), and changing the VPL disc
size each time (everything is redrawn, as after a new frame). Beside them the G-buffer and
gather passes of the frame: what a camera move costs.
"""

from __future__ import annotations

import argparse
import statistics
import time

OVERLAY_ROWS = {
    "none": {},
    "slice": {"slice": True},
    "glyphs": {"glyphs": True},
    "vpls (all)": {"vpls": True, "vpl_density": 1.0},
    "vpls (1/4)": {"vpls": True, "vpl_density": 0.25},
    "blockers": {"blockers": True},
    "lattice + cascades": {"lattice": True, "cascade_boxes": True},
    "everything": {"slice": True, "glyphs": True, "vpls": True, "lattice": True,
                   "cascade_boxes": True, "blockers": True},
}


def main(argv: list[str] | None = None) -> int:
    from explorer.commands.options import image_size, size_type
    from explorer.lpv.pipeline import Pipeline
    from explorer.lpv.settings import Settings
    from explorer.ui.overlays.compositor import Compositor
    from explorer.ui.state import OverlayState

    parser = argparse.ArgumentParser(prog="python -m explorer.commands.overlay_bench")
    parser.add_argument("--size", type=size_type(image_size), default=(512, 512))
    parser.add_argument("--grid", type=int, default=32)
    parser.add_argument("--rsm", type=int, default=256)
    parser.add_argument("--repeat", type=int, default=9)
    args = parser.parse_args(argv)
    settings = Settings(grid_size=args.grid, rsm_size=args.rsm, width=args.size[0],
                        height=args.size[1], geometry_volume="one-sided")
    with Pipeline(settings) as pipeline:
        result = pipeline.run(settings)
        compositor = Compositor(pipeline.ctx)
        try:
            print(f"{result.vpls.count} VPLs, {args.grid}³ grid, {args.size[0]}×{args.size[1]} "
                  f"pixels; pipeline: gbuffer {result.timings_ms['gbuffer']:.2f} ms, gather "
                  f"{result.timings_ms['gather']:.2f} ms ({pipeline.timing_methods['gather']})")
            print(f"{'overlay':<22}{'slice moved [ms]':>18}{'all redrawn [ms]':>18}")
            for name, switches in OVERLAY_ROWS.items():
                medians = []
                for vary in ("slice_index", "vpl_size"):
                    times = []
                    for i in range(args.repeat + 1):
                        change = {"slice_index": i % args.grid} if vary == "slice_index" \
                            else {"vpl_size": 0.5 + 0.01 * i}
                        overlays = OverlayState(**switches, **change)
                        pipeline.ctx.finish()
                        start = time.perf_counter()
                        compositor.compose("A", result, pipeline.final_texture.glo, False,
                                           overlays)
                        pipeline.ctx.finish()
                        if i:                  # the first one compiles and uploads
                            times.append((time.perf_counter() - start) * 1e3)
                    medians.append(statistics.median(times))
                print(f"{name:<22}{medians[0]:>18.2f}{medians[1]:>18.2f}")
        finally:
            compositor.release()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
