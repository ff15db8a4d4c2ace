"""``lpv-explorer render``: one frame headlessly, written as PNG (one file per view)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from explorer.lpv.settings import (
    CASCADE_ITERATIONS,
    DOWNSAMPLE_MODES,
    GEOMETRY_VOLUME_MODES,
    MAX_SHADOW_KERNEL,
    PRESETS,
    VIEWS,
)
from explorer.lpv.tonemap import TONE_MAPS

MIN_PNG_SIZE = 256
"""Views not sized by --size (RSM and grid views) are enlarged by whole pixels to at least
this size."""
CAMERA_VIEWS = ("final", "direct", "indirect", "albedo", "cascade-weights")


def parse_size(text: str) -> tuple[int, int]:
    """``"WxH"`` -> (W, H); an ArgumentTypeError saying what is expected otherwise."""
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like 512x512, got {text!r}") from None
    if width < 1 or height < 1:
        raise argparse.ArgumentTypeError(f"size must be at least 1x1, got {text!r}")
    return width, height


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--scene", default="cornell",
                        help="built-in scene (cornell, single-source, room, atrium) or a mesh "
                             "file (OBJ, GLB/glTF, PLY, STL); default: cornell")
    parser.add_argument("--preset", default="corrected", choices=sorted(PRESETS),
                        help="formulas: the corrected ones or the published ones")
    parser.add_argument("--out", default="frame.png", type=Path,
                        help="PNG to write; with several --view, one file per view named "
                             "<stem>-<view>.png")
    parser.add_argument("--view", action="append", choices=VIEWS, metavar="VIEW",
                        help=f"what to write (repeatable): {', '.join(VIEWS)}; default: final")
    parser.add_argument("--grid", type=int, help="grid resolution N (N³ cells)")
    parser.add_argument("--iterations", type=int, help="propagation steps")
    parser.add_argument("--size", type=parse_size, help="image size WxH")
    parser.add_argument("--rsm-size", type=int, help="RSM resolution (square)")
    parser.add_argument("--exposure", type=float, help="exposure multiplier")
    parser.add_argument("--downsample", choices=DOWNSAMPLE_MODES, help="RSM downsample")
    parser.add_argument("--downsample-factor", type=int, help="RSM downsample block size")
    parser.add_argument("--geometry-volume", choices=GEOMETRY_VOLUME_MODES,
                        help="fuzzy occlusion")
    add_leak_arguments(parser)
    add_sh_order_argument(parser)
    add_light_arguments(parser)
    add_display_arguments(parser)
    parser.add_argument("--indirect-only", action="store_true",
                        help="final image without the direct light")
    parser.add_argument("--slice", type=int, dest="z",
                        help="z slice of the grid views (default: the middle)")
    parser.add_argument("--coefficient", type=int, choices=range(9), metavar="K",
                        help="grid-slice: show SH coefficient K (0..3, or 0..8 with "
                             "--sh-order 2) instead of the flux")
    parser.add_argument("--cascades", type=int,
                        help="nested LPV grids around the camera's focus, each with twice the "
                             "cells of the last (default 1: one grid around the scene)")
    parser.add_argument("--cascade-extent", type=float,
                        help="edge of the finest cascade in world units (default: the "
                             "single grid's edge / 2^(cascades-1))")
    parser.add_argument("--cascade-iterations", choices=CASCADE_ITERATIONS,
                        help="same: every cascade propagates --iterations steps (default); "
                             "same-distance: finer cascades propagate 2x more per level")
    parser.add_argument("--cascade", type=int, default=None,
                        help="grid views (grid-slice, geometry-volume): show this cascade "
                             "(0 = finest, the default)")
    parser.add_argument("--audit", action="store_true", help="print the energy audit")
    parser.add_argument("--debug-nan", action="store_true",
                        help="check every pass for NaN/Inf and name the first bad one")
    # --lesson ID --step K (lessons helper): the options and their handling live in
    # explorer/commands/lessons.py.
    from explorer.commands.lessons import add_render_arguments

    add_render_arguments(parser)


def add_leak_arguments(parser: argparse.ArgumentParser) -> None:
    """--injection-offset, --gather-damping, --bounces (shared with ``compare``); left out
    they keep the Settings defaults."""
    parser.add_argument("--injection-offset", type=float, metavar="CELLS",
                        help="inject each VPL this many cells along its normal "
                             "(0..1; default 0.5)")
    parser.add_argument("--gather-damping", action=argparse.BooleanOptionalAction,
                        default=None,
                        help="damp the indirect light by its derivative along the normal "
                             "(default off)")
    parser.add_argument("--bounces", type=int, choices=(1, 2),
                        help="2: the geometry volume reflects the light it blocks (needs "
                             "--geometry-volume; default 1)")


def parse_cone(text: str) -> tuple[float, float]:
    """``"INNER,OUTER"`` half-angles in degrees -> (inner, outer)."""
    try:
        inner, outer = (float(part) for part in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"cone angles must look like 30,60 (inner and outer "
                                         f"half-angles in degrees), got {text!r}") from None
    return inner, outer


def add_light_arguments(parser: argparse.ArgumentParser) -> None:
    """--spot-cone/--no-spot-cone and --cone-angles (shared with ``compare``)."""
    parser.add_argument("--spot-cone", action=argparse.BooleanOptionalAction, default=None,
                        help="spot lights shine through their cone with a smooth falloff "
                             "(default); --no-spot-cone: the 90° square frustum with uniform "
                             "intensity (the published setup)")
    parser.add_argument("--cone-angles", type=parse_cone, metavar="INNER,OUTER",
                        help="the spot cone's inner and outer half-angles in degrees "
                             "(0 <= inner <= outer <= 80; default: the scene's)")


def add_display_arguments(parser: argparse.ArgumentParser) -> None:
    """--shadow-kernel, --tone-map, --auto-exposure/--no-auto-exposure."""
    parser.add_argument("--shadow-kernel", type=int, metavar="K",
                        help=f"PCF box of the direct light's shadows, K texels wide "
                             f"(1..{MAX_SHADOW_KERNEL}; 1 = hard; default 3)")
    parser.add_argument("--tone-map", choices=TONE_MAPS,
                        help="display tone curve: filmic (ACES fit, default) or linear-clip")
    parser.add_argument("--auto-exposure", action=argparse.BooleanOptionalAction,
                        default=None,
                        help="expose the log-average luminance at middle grey, with "
                             "--exposure as a compensation (default on)")


def add_sh_order_argument(parser: argparse.ArgumentParser) -> None:
    """--sh-order: L1 (4 coefficients per colour) or L2 (9) spherical harmonics."""
    parser.add_argument("--sh-order", type=int, metavar="ORDER",
                        help="spherical harmonics of the light grid: 1 = L1, 4 coefficients "
                             "(default), 2 = L2, 9 coefficients (docs/MODEL.md 'L2 option')")


# (option dest, Settings field) pairs: an option given on the command line sets the field.
STEP_OPTIONS = (("grid", "grid_size"), ("iterations", "iterations"),
                ("rsm_size", "rsm_size"), ("exposure", "exposure"),
                ("downsample", "downsample"), ("downsample_factor", "downsample_factor"),
                ("geometry_volume", "geometry_volume"))
"""The sizes and modes a command line sets (with the tables below, all of them also
override a lesson step in ``render --lesson``)."""
CASCADE_OPTIONS = (("cascades", "cascades"), ("cascade_extent", "cascade_extent"),
                   ("cascade_iterations", "cascade_iterations"))
SH_OPTIONS = (("sh_order", "sh_order"),)
LEAK_OPTIONS = (("injection_offset", "injection_offset_cells"),
                ("gather_damping", "gather_damping"), ("bounces", "bounces"))
LIGHT_OPTIONS = (("spot_cone", "spot_cone"), ("cone_angles", "spot_cone_degrees"))
DISPLAY_OPTIONS = (("shadow_kernel", "shadow_kernel"), ("tone_map", "tone_map"),
                   ("auto_exposure", "auto_exposure"))
SETTING_OPTIONS = (STEP_OPTIONS + CASCADE_OPTIONS + SH_OPTIONS + LEAK_OPTIONS + LIGHT_OPTIONS
                   + DISPLAY_OPTIONS)
"""Every (option, Settings field) pair ``render`` takes, plain or with ``--lesson``."""


def option_changes(args: argparse.Namespace,
                   options: tuple[tuple[str, str], ...]) -> dict[str, object]:
    """The Settings changes for the ``(dest, field)`` options given (not None) in ``args``."""
    changes: dict[str, object] = {}
    for name, field in options:
        value = getattr(args, name, None)
        if value is not None:
            changes[field] = value
    return changes


def leak_changes(args: argparse.Namespace) -> dict[str, object]:
    """The Settings changes the :func:`add_leak_arguments` flags ask for."""
    return option_changes(args, LEAK_OPTIONS)


def output_changes(args: argparse.Namespace) -> dict[str, object]:
    """The Settings changes of --size, --indirect-only and --debug-nan."""
    changes: dict[str, object] = {}
    if args.size is not None:
        changes["width"], changes["height"] = args.size
    if args.indirect_only:
        changes["indirect_only"] = True
    if args.debug_nan:
        changes["debug_nan"] = True
    return changes


def settings_from_args(args: argparse.Namespace):
    """Settings from the command line (fields left out keep their defaults)."""
    from explorer.lpv.settings import Settings, preset

    changes: dict[str, object] = {"scene": args.scene, "corrections": preset(args.preset)}
    changes.update(option_changes(args, SETTING_OPTIONS))
    changes.update(output_changes(args))
    return Settings(**changes)


def write_png(image, path: Path, enlarge: bool = False) -> None:
    """A [0, 1] float image as 8-bit RGB PNG; with ``enlarge``, a small image is repeated
    by whole pixels up to :data:`MIN_PNG_SIZE`."""
    import numpy as np
    from PIL import Image

    pixels = np.clip(np.nan_to_num(image), 0.0, 1.0)
    repeat = max(1, -(-MIN_PNG_SIZE // max(pixels.shape[:2])))
    if enlarge and repeat > 1:
        pixels = pixels.repeat(repeat, axis=0).repeat(repeat, axis=1)
    path.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray((pixels * 255.0 + 0.5).astype(np.uint8), "RGB").save(path)


def output_paths(out: Path, views: list[str]) -> dict[str, Path]:
    if len(views) == 1:
        return {views[0]: out}
    suffix = out.suffix or ".png"
    return {view: out.with_name(f"{out.stem}-{view}{suffix}") for view in views}


def format_audit(audit) -> str:
    rows = [("rsm", audit.rsm), ("injected", audit.injected),
            ("accumulated", audit.accumulated), ("gathered", audit.gathered),
            ("border loss (all steps)", audit.border_loss.sum(axis=0)),
            ("clamp gain (all steps)", audit.clamp_gain.sum(axis=0)),
            ("occluded (all steps)", audit.occluded.sum(axis=0)),
            ("blocked, bounces 2", audit.blocked.sum(axis=0)),
            ("reflected, bounces 2", audit.reflected.sum(axis=0))]
    lines = ["energy audit [W]            red        green       blue"]
    lines += [f"  {name:<24}" + "".join(f"{float(v):11.4g}" for v in values)
              for name, values in rows]
    return "\n".join(lines)


def print_audit(result) -> None:
    """The energy audit of a frame, and one line per cascade when there are several."""
    print(format_audit(result.audit))
    if len(result.cascade_audits) > 1:
        print(format_cascade_audits(result))


def format_cascade_audits(result) -> str:
    """One line per cascade: cell size and the flux injected / accumulated / lost at the
    border in that cascade (the cascades overlap: their fluxes do not add up)."""
    lines = ["cascades [W, summed over r, g, b]  cell size   injected  accumulated  border"]
    for k, (spec, audit) in enumerate(zip(result.cascade_specs, result.cascade_audits)):
        lines.append(f"  cascade {k:<26}{spec.cell_size:10.4g}{audit.injected.sum():11.4g}"
                     f"{audit.accumulated.sum():13.4g}{audit.border_loss.sum():8.4g}")
    return "\n".join(lines)


def render_error(error: object, code: int) -> int:
    """Report a failed ``render`` (also ``render --lesson``) on stderr; returns ``code``."""
    print(f"lpv-explorer render: error: {error}", file=sys.stderr)
    return code


def main(args: argparse.Namespace) -> int:
    from explorer.gl.context import GLUnavailableError
    from explorer.gl.program import ShaderError
    from explorer.lpv.pipeline import Pipeline
    from explorer.scene import SceneError

    if getattr(args, "lesson", None) is not None:
        from explorer.commands.lessons import render_lesson_step

        return render_lesson_step(args)
    views = args.view or ["final"]
    try:
        settings = settings_from_args(args)
    except (ValueError, KeyError) as exc:
        return render_error(exc, 2)
    try:
        with Pipeline(settings) as pipeline:
            result = pipeline.run()
            options = {"z": args.z, "coefficient": args.coefficient, "cascade": args.cascade}
            for view, path in output_paths(args.out, views).items():
                wanted = {k: v for k, v in options.items()
                          if v is not None and view in ("grid-slice", "geometry-volume")
                          and (k != "coefficient" or view == "grid-slice")}
                write_png(pipeline.view(view, **wanted), path,
                          enlarge=view not in CAMERA_VIEWS)
                print(f"wrote {path} ({view})")
            if args.audit:
                print_audit(result)
    except SceneError as exc:
        return render_error(exc, 2)
    except (ValueError, FloatingPointError, GLUnavailableError, ShaderError, OSError) as exc:
        return render_error(exc, 1)
    return 0
