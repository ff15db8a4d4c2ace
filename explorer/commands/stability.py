"""``lpv-explorer stability``: the frame-to-frame change of the indirect image while the
light, an object or the camera moves slowly, with and without a snapping switch
(``--snap``: cascades or RSM; explorer/lpv/stability.py, docs/MODEL.md "Moving objects and
temporal stability").

Each row renders ``--frames + 1`` frames, frame ``t`` moved by ``t·--step`` world units
along ``--axis`` (``--move light-turn``: the light turned by ``t·--step`` degrees about
``--axis`` through its position), and prints the mean and the largest per-pixel change
of the indirect luminance between consecutive frames, relative to the first frame's mean. Cascade
snapping only acts on cascades that follow the camera (``--move camera`` with
``--cascades`` 2 or more), RSM snapping on a moving light's RSM (``--move light``: it
snaps translations, so a turning light's rows are the same frames); the command says so
when the two rows cannot differ.
"""

from __future__ import annotations

import argparse

import numpy as np

from explorer.commands import options
from explorer.lpv.stability import AXES, MOVES, SNAPS, Motion, StabilityRun, measure
from explorer.schema import Spec

DEFAULTS = {"size": (128, 128), "rsm_size": 64, "grid_size": 16}
"""Sizes that keep a sequence to seconds on llvmpipe."""
FRAMES = Spec(kind="int", low=1, high=10000, doc="Frame-to-frame changes measured (frames + 1 "
              "frames are rendered per row).")
STEP = Spec(kind="float", low=-1e6, high=1e6, doc="World units the thing moves per frame "
            "(negative: the other way); degrees per frame with --move light-turn.")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--move", choices=MOVES, default="light",
                        help="what moves: the primary light, an object or the camera; "
                             "light-turn turns the primary light about --axis through its "
                             "position (default: light)")
    parser.add_argument("--object", dest="moving_object", default=None, metavar="NAME",
                        help="the object that moves with --move object (default: the "
                             "scene's second object, e.g. cornell's short block)")
    parser.add_argument("--frames", type=options.value_type("frames", FRAMES), default=8,
                        metavar="N",
                        help=options.spec_help(FRAMES, 8))
    parser.add_argument("--step", type=options.value_type("step", STEP), default=None,
                        metavar="X",
                        help=options.spec_help(STEP, "a tenth of a cell of the finest "
                                                     "grid; with --move light-turn a tenth "
                                                     "of the angle an RSM texel spans at a "
                                                     "spot's centre"))
    parser.add_argument("--axis", choices=tuple(AXES), default="x",
                        help="the direction of the motion (default: x)")
    parser.add_argument("--snap", choices=tuple(SNAPS), default="cascades",
                        help="the snapping switch the two rows turn on and off: cascades "
                             "(Settings.cascade_snap) or rsm (Settings.rsm_snap; the other "
                             "keeps its default) (default: cascades)")
    options.add_setting_options(parser, exclude=("exposure", "indirect_only", "cascade_snap",
                                                 "rsm_snap", "object_transforms"),
                                defaults=DEFAULTS)


def main(args: argparse.Namespace) -> int:
    from explorer.lpv.pipeline import Pipeline
    from explorer.scene import SceneError

    base = options.settings_from_args(args)
    options.check_scene(base.scene)
    try:
        with Pipeline(base) as pipeline:
            first = options.run_pipeline(pipeline, base)
            step = args.step if args.step is not None else default_step(
                args.move, first.grid_spec.cell_size,
                pipeline.base_scene.for_settings(base).light, base.rsm_size)
            motion = Motion(args.move, step, args.axis, args.moving_object)
            if args.move == "object":
                motion.object_name(pipeline.base_scene)      # a clear error first
            runs = [measure(lambda s: options.run_pipeline(pipeline, s),
                            lambda s: pipeline.base_scene.for_settings(s), base, motion,
                            args.frames, snap, args.snap) for snap in (True, False)]
            print(format_report(base, motion, first.grid_spec.cell_size, args.frames, runs,
                                pipeline.base_scene, args.snap))
    except SceneError as exc:
        raise options.CommandError(exc) from None
    except options.render_failures() as exc:
        raise options.CommandError(exc, 1) from None
    return 0


TURN_NOTES = {
    "spot": "(RSM snapping moves the light's eye in its image plane, a translation: a spot "
            "turning about its own position has no move to snap, so the two rows are the "
            "same frames)",
    "directional": "(a directional light's eye turns about the scene box's centre, and the "
                   "image-plane axes its snap rounds along turn with it: the snap adds a "
                   "jump of up to half a texel to the turn instead of holding the VPLs)",
    "point": "(a point light shines every way: turning it changes nothing)",
}
"""What ``--snap rsm`` does for a light of each kind that turns (explorer/lpv/rsm_snap.py)."""


def default_step(move: str, finest_cell: float, light, rsm_size: int) -> float:
    """A tenth of the finest cell per frame; for a turning light a tenth of the angle one
    RSM texel spans at the centre of a spot's view, ``atan(2t/N)`` (degrees; ``t`` the
    frustum's half width at depth 1). A turn of a light that is not a spot needs
    ``--step``."""
    if move != "light-turn":
        return 0.1 * finest_cell
    if getattr(light, "kind", None) != "spot":
        raise options.CommandError(f"--move light-turn turns a spot light by default; the "
                                   f"primary light {light.name!r} is a {light.kind} light: "
                                   f"give --step in degrees per frame")
    return 0.1 * float(np.degrees(np.arctan(2.0 * light.frustum_half_width / rsm_size)))


def format_report(settings, motion: Motion, finest_cell: float, frames: int,
                  runs: list[StabilityRun], scene, switch: str = "cascades") -> str:
    """The header line and one row per snapping setting of ``switch`` (:data:`SNAPS`)."""
    light = scene.for_settings(settings).light
    what = {"light": f"the light {light.name!r}", "camera": "the camera",
            "light-turn": f"the light {light.name!r}",
            "object": f"object {motion.object_name(scene)!r}"}[motion.move]
    how = (f"turns {motion.step:.4g}° per frame about {motion.axis}"
           if motion.move == "light-turn" else
           f"moves {motion.step:.4g} m ({motion.step / finest_cell:.3g} finest cells) per "
           f"frame along {motion.axis}")
    lines = [f"scene {settings.scene}: {what} {how}, {frames} frames; "
             f"{settings.cascades} cascade(s) of "
             f"{settings.grid_size}³ cells; change of the indirect luminance between "
             f"frames on the surface points both show, relative to the first frame's mean",
             "",
             f"| {'cascade' if switch == 'cascades' else 'RSM'} snapping | mean change | "
             "largest pixel change | frames changed |",
             "|---|---:|---:|---:|"]
    for run in runs:
        lines.append(f"| {'on' if run.snap else 'off'} | {100 * run.mean:.3f} % | "
                     f"{100 * run.peak:.2f} % | {run.frames_changed}/{frames} |")
    if switch == "rsm":
        if motion.move == "light-turn":
            lines += ["", TURN_NOTES[light.kind]]
        elif motion.move != "light":
            lines += ["", "(RSM snapping acts on a moving light: with a still one neither "
                      "row's RSM moves)"]
    elif settings.cascades == 1 or motion.move != "camera":
        lines.append("")
        lines.append("(snapping moves only cascades that follow the camera: with "
                     f"{'one grid' if settings.cascades == 1 else 'a still camera'} the "
                     "two rows are the same frames)")
    return "\n".join(lines)
