"""Numpy prototype of two published leak reductions, measured against the reference.

It re-runs injection and propagation with the numpy twin (``explorer.lpv.twin.light_grid``,
whose ``gather`` mirrors the GPU's final gather). The pipeline now has the first two as
``Settings.injection_offset_cells`` and ``Settings.gather_damping`` (measured with
``lpv-explorer compare`` in docs/ERRORS.md); this study also tries the gather offset.
``python -m explorer.truth.leaks --scene room`` prints the table recorded in
docs/ERRORS.md.

* **Injection offset** (Kaplanyan & Dachsbacher): inject each VPL at ``p + δ·h·n``
  (``h`` the cell size, ``δ = ½``) instead of ``p``, so a VPL lands in the cell in front of
  its surface instead of whichever side of a cell boundary float rounding picks, and a
  surface does not gather its own VPLs from the cell it lies in.
* **Directional-derivative damping** in the final gather: with ``E(x)`` the gathered
  irradiance for the pixel's normal ``n`` at ``x``, light that mostly arrives from behind
  the surface (leaking through it) makes ``E`` grow towards ``−n``. The central difference
  over one cell, ``∂_n E ≈ (E(p + ½h·n) − E(p − ½h·n))/h``, gives the factor
  ``f = clamp(1 + h·∂_n E / E(p − ½h·n), 0, 1) = clamp(E(p + ½h·n)/E(p − ½h·n), 0, 1)``
  per channel (1 where ``E(p − ½h·n) = 0``), and ``E' = f·E(p)``.
* **Gather offset** (for comparison): sample the grid at ``p + ½h·n``.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from explorer.lpv.grid import GridSpec
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.twin.light_grid import derivative_damping, gather_irradiance, sample_grid
from explorer.lpv.twin.tonemap import luminance
from explorer.lpv.vpl import VplArrays

__all__ = ["VARIANTS", "derivative_damping", "gather_irradiance", "offset_vpls",
           "sample_grid", "study", "variant_irradiance"]

VARIANTS = ("baseline", "inject-offset", "gather-offset", "damping", "inject-offset+damping")


def offset_vpls(vpls: VplArrays, distance: float) -> VplArrays:
    """The VPLs moved ``distance`` along their normals (everything else unchanged)."""
    positions = np.asarray(vpls.positions, np.float64)
    moved = positions + distance * np.asarray(vpls.normals, np.float64)
    return VplArrays(moved, vpls.normals, vpls.flux, vpls.depth, vpls.texel_area,
                     vpls.projection)


def variant_irradiance(variant: str, vpls: VplArrays, spec: GridSpec, corrections,
                       iterations: int, positions: np.ndarray, normals: np.ndarray
                       ) -> np.ndarray:
    """(P, 3) LPV irradiance at the points for one of :data:`VARIANTS` (numpy LPV)."""
    if variant not in VARIANTS:
        raise ValueError(f"variant must be one of {VARIANTS}, got {variant!r}")
    half = 0.5 * spec.cell_size
    if variant.startswith("inject-offset"):
        vpls = offset_vpls(vpls, half)
    injected = twin.inject(vpls, spec, corrections)
    accumulated = sum(twin.propagate(injected, corrections, iterations))
    offset = half if variant == "gather-offset" else 0.0
    irradiance = gather_irradiance(accumulated, spec, positions, normals, offset)
    if variant.endswith("damping"):
        irradiance *= derivative_damping(accumulated, spec, positions, normals)
    return irradiance


def study(scene: str = "room", iterations=(4, 8, 16), width: int = 128, height: int = 128,
          rsm_size: int = 64, grid_size: int = 32, ctx=None, spot_cone: bool = True
          ) -> list[dict]:
    """Every variant × iteration count against both references; one dict per row with
    relative L2 and flux ratios (whole image, and the pixels where the visible reference
    has less than half the unoccluded light: where a leak would show). ``spot_cone``:
    ``Settings.spot_cone`` (False: the 90° square frustum docs/ERRORS.md measured)."""
    from explorer.lpv.pipeline import Pipeline
    from explorer.lpv.settings import PRESETS, Settings
    from explorer.truth.metrics import error_stats
    from explorer.truth.render import reference_for_frame

    corrections = PRESETS["corrected"]
    settings = Settings(scene=scene, width=width, height=height, rsm_size=rsm_size,
                        grid_size=grid_size, corrections=corrections, spot_cone=spot_cone)
    with Pipeline(settings, ctx) as pipeline:
        frame = pipeline.run()
        visible, gbuffer = reference_for_frame(frame, True, ctx=pipeline.ctx)
        unoccluded, _ = reference_for_frame(frame, False, ctx=pipeline.ctx)
    valid = gbuffer.valid
    shadowed = valid & (luminance(visible) < 0.5 * luminance(unoccluded))
    positions, normals = gbuffer.position[valid], gbuffer.normal[valid]
    albedo = gbuffer.albedo[valid]
    rows = []
    for steps in iterations:
        for variant in VARIANTS:
            irradiance = variant_irradiance(variant, frame.vpls, frame.grid_spec, corrections,
                                            steps, positions, normals)
            image = np.zeros(valid.shape + (3,))
            image[valid] = albedo / np.pi * irradiance
            row = {"variant": variant, "iterations": steps,
                   "visible": error_stats(image, visible, valid),
                   "unoccluded": error_stats(image, unoccluded, valid)}
            row["shadowed"] = (error_stats(image, visible, shadowed).flux_ratio
                               if shadowed.any() else float("nan"))
            row["lit"] = (error_stats(image, visible, valid & ~shadowed).flux_ratio
                          if (valid & ~shadowed).any() else float("nan"))
            rows.append(row)
    return rows


def format_rows(rows: list[dict]) -> str:
    lines = ["| variant | iterations | rel. L2 (visible) | flux ratio (visible) | "
             "rel. L2 (unoccluded) | flux ratio (unoccluded) | flux ratio, shadowed px | "
             "flux ratio, lit px |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        lines.append(f"| {r['variant']} | {r['iterations']} | {r['visible'].relative_l2:.3f} | "
                     f"{r['visible'].flux_ratio:.3f} | {r['unoccluded'].relative_l2:.3f} | "
                     f"{r['unoccluded'].flux_ratio:.3f} | {r['shadowed']:.3f} | "
                     f"{r['lit']:.3f} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m explorer.truth.leaks",
                                     description="measure leak reductions against the "
                                                 "one-bounce reference (numpy LPV)")
    parser.add_argument("--scene", default="room")
    parser.add_argument("--iterations", default="4,8,16")
    parser.add_argument("--size", type=int, default=128, help="image width and height")
    parser.add_argument("--spot-cone", action=argparse.BooleanOptionalAction, default=True,
                        help="spot lights through their cone (default) or, with "
                             "--no-spot-cone, the 90° square frustum")
    args = parser.parse_args(argv)
    try:
        steps = [int(v) for v in args.iterations.split(",")]
    except ValueError:
        print(f"--iterations {args.iterations!r}: expected integers like 4,8,16",
              file=sys.stderr)
        return 2
    print(format_rows(study(args.scene, steps, args.size, args.size,
                            spot_cone=args.spot_cone)))
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
