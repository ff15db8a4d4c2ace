"""``lpv-explorer diff THEIRS.npz``: an engine's stages against this tool's, stage by
stage (explorer/exchange/diff.py): for every array named as ``render --dump`` names them
(grid_0 … grid_N, accumulated, irradiance, indirect, ...), the largest error and the
largest relative error per cell / pixel / texel / VPL, where they are, and the relative
L2 error of the stage.

Ours are rendered for the settings of ``--settings DUMP.json`` (a dump's sidecar; by
default THEIRS.json when it exists), with every settings option given applied over them;
``--vpls`` and ``--grid0`` feed their VPLs or grid into our frame first, so each stage can
be compared from the same input. ``--ours OURS.npz`` compares with a dump instead of
rendering. ``--atol A --rtol R`` hold every value to ``|theirs − ours| ≤ A + R·|ours|``
(numpy's isclose), ``--rel-l2 X`` each stage's relative L2 error to X, and ``--tolerance
X`` (the older test) each stage's largest relative error per element to X; any stage
missing one exits 1, and the table says which stage fails and why, with its worst elements.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from explorer.commands import options
from explorer.schema import Spec

TOLERANCE = Spec(kind="float", low=0.0, high=1e30, optional=True,
                 doc="Fail a stage (exit 1) when its largest relative error per element "
                     "exceeds this: an element's error norm over ours' norm there, elements "
                     "below 1e-6 of the stage's largest left out. Unchanged from before; it "
                     "is not --rtol (that one is per value, with --atol for near-empty "
                     "cells, as a float64 port needs).")
ATOL = Spec(kind="float", low=0.0, high=1e30, optional=True,
            doc="Fail a stage when any value has |theirs − ours| > atol + rtol·|ours| "
                "(numpy.isclose with ours as the reference; rtol 0 unless --rtol is given).")
RTOL = Spec(kind="float", low=0.0, high=1e30, optional=True,
            doc="The relative part of the isclose test (atol 0 unless --atol is given).")
REL_L2 = Spec(kind="float", low=0.0, high=1e30, optional=True,
              doc="Fail a stage when ‖theirs − ours‖₂ / ‖ours‖₂ over the stage exceeds this.")
WORST = Spec(kind="int", low=0, high=10000,
             doc="How many of each failing stage's worst elements to list with their values "
                 "on both sides (with no tolerance given: of each stage that differs).")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from explorer.commands.render import add_input_arguments

    parser.add_argument("theirs", type=Path, metavar="THEIRS.npz",
                        help="their arrays, named and laid out as `render --dump` writes them")
    parser.add_argument("--ours", type=Path, default=None, metavar="OURS.npz",
                        help="compare with this dump instead of rendering our frame")
    parser.add_argument("--settings", type=Path, default=None, metavar="DUMP.json",
                        help="render our frame with the settings of this sidecar (default: "
                             "THEIRS.json when it exists); options given override them")
    parser.add_argument("--json", action="store_true",
                        help="print the comparison as JSON instead of a table")
    parser.add_argument("--atol", type=options.value_type("atol", ATOL), default=None,
                        metavar="A", help=options.spec_help(ATOL))
    parser.add_argument("--rtol", type=options.value_type("rtol", RTOL), default=None,
                        metavar="R", help=options.spec_help(RTOL))
    parser.add_argument("--rel-l2", type=options.value_type("rel-l2", REL_L2), default=None,
                        metavar="X", help=options.spec_help(REL_L2))
    parser.add_argument("--tolerance", type=options.value_type("tolerance", TOLERANCE),
                        default=None, metavar="X", help=options.spec_help(TOLERANCE))
    parser.add_argument("--worst", type=options.value_type("worst", WORST), default=5,
                        metavar="K", help=options.spec_help(WORST, 5))
    group = parser.add_argument_group("their input into our frame")
    add_input_arguments(group)
    options.add_setting_options(parser)


def main(args: argparse.Namespace) -> int:
    from explorer.exchange.diff import diff_arrays, format_table, format_worst
    from explorer.exchange.files import FileFormatError, read_npz
    from explorer.exchange.tolerances import Tolerances

    tolerances = Tolerances(atol=args.atol, rtol=args.rtol, rel_l2=args.rel_l2,
                            max_relative=args.tolerance)

    try:
        theirs = read_npz(args.theirs, "THEIRS")
        if args.ours is not None:
            ours, settings, source = read_npz(args.ours, "--ours"), None, str(args.ours)
        else:
            settings, source = _settings(args), "rendered"
    except FileFormatError as exc:
        raise options.CommandError(exc) from None
    if args.ours is None:
        ours = _render(args, settings)
    diffs, only_theirs, only_ours = diff_arrays(theirs, ours, tolerances, args.worst)
    if not diffs:
        raise options.CommandError(f"THEIRS {args.theirs} holds no array named as ours "
                                   f"({', '.join(list(ours)[:6])}, ...); name them as "
                                   f"`render --dump` does")
    failed = [d.stage for d in diffs if d.passed is False]
    if args.json:
        print(json.dumps({"theirs": str(args.theirs), "ours": source,
                          "settings": None if settings is None else settings.to_dict(),
                          "stages": [d.as_dict() for d in diffs], "only_theirs": only_theirs,
                          "only_ours": only_ours, **tolerances.as_dict(),
                          "within_tolerance": not failed if tolerances.any else None,
                          "failed": failed}, indent=2, allow_nan=False))
    else:
        print(format_table(diffs))
        worst = format_worst(diffs)
        if worst:
            print(worst)
        if tolerances.any:
            print(f"{len(diffs) - len(failed)} of {len(diffs)} stages pass"
                  + (f"; failing: {', '.join(failed)}" if failed else ""))
        if only_theirs:
            print(f"only in theirs (not compared): {', '.join(only_theirs)}")
        if only_ours:
            print(f"only in ours: {', '.join(only_ours)}")
    return 1 if failed else 0


def _settings(args: argparse.Namespace):
    """Our frame's Settings: the sidecar's (``--settings``, or THEIRS.json), the options
    given applied over them."""
    from explorer.exchange.sidecar import read_settings, sidecar_path

    path = args.settings
    if path is None and sidecar_path(args.theirs).is_file():
        path = sidecar_path(args.theirs)
    base = None
    if path is not None:
        base = read_settings(path)
        if not args.json:
            print(f"our frame: the settings of {path}")
    return options.settings_from_args(args, base=base)


def _render(args: argparse.Namespace, settings) -> dict:
    """Our frame's stages (steps kept), their VPLs or grid_0 fed in when given."""
    from explorer.commands.render import frame_inputs, run_frame
    from explorer.exchange.stages import frame_arrays
    from explorer.lpv.pipeline import Pipeline
    from explorer.scene import SceneError

    options.check_scene(settings.scene)
    vpls, grid0 = frame_inputs(args, settings)
    try:
        with Pipeline(settings) as pipeline, options.Progress("diff") as progress:
            result = run_frame(pipeline, settings, progress, args, vpls, grid0,
                               keep_steps=True)
            return frame_arrays(result)
    except SceneError as exc:
        raise options.CommandError(exc, 2) from None
    except options.render_failures() as exc:
        raise options.CommandError(exc, 1) from None
