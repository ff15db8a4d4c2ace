"""``lpv-explorer run``: open the explorer window.

``--screenshot PATH --frames N`` draws N frames, then waits for the converged picture
(the pipeline works a few milliseconds per frame, and a lesson step applied by the
panels starts a new frame) and says so, writes the window (panels included) to PATH and
exits: scripted runs, README screenshots and CI smoke tests. ``--no-wait`` writes the
frame after N frames as it is. Every option is
checked before the window opens (an unknown lesson or scene, a window larger than
:data:`~explorer.ui.state.MAX_WINDOW_SIZE`, a screenshot path that cannot be written).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from explorer.commands.lesson_folder import add_folder_option, folder_of
from explorer.commands.options import (
    CommandError,
    Outputs,
    add_placement_options,
    check_scene,
    placement_changes,
    scene_help,
    setting_type,
    size_type,
    spec_help,
    value_type,
)
from explorer.lpv.settings import PRESETS, Settings
from explorer.schema import Spec, specs

FRAMES = Spec(kind="int", low=1, high=10**9, optional=True,
              doc="Draw this many frames, then exit (default with --screenshot: 30; the "
                  "screenshot waits for the converged picture).")
STEP = Spec(kind="int", low=1, high=1000, optional=True,
            doc="Open the lesson at this step (default: 1).")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from explorer.ui.state import VIEW_MODES, AppState

    window = specs(AppState)["window_size"]
    parser.add_argument("--lesson", metavar="ID", help="open a lesson (e.g. 01 or its slug)")
    add_folder_option(parser, alone=True)
    parser.add_argument("--scene", metavar="NAME|PATH", type=setting_type("scene"),
                        help=scene_help(spec_help(specs(Settings)["scene"])))
    parser.add_argument("--preset", choices=list(PRESETS),
                        help="start with these formulas (configuration A)")
    add_placement_options(parser)
    parser.add_argument("--light-flux", metavar="W", type=setting_type("light_flux"),
                        default=None, help=spec_help(specs(Settings)["light_flux"]))
    parser.add_argument("--step", metavar="K", type=value_type("step", STEP), default=None,
                        help="with --lesson: " + spec_help(STEP)[0].lower() + spec_help(STEP)[1:])
    parser.add_argument("--compare", choices=VIEW_MODES,
                        help="view mode: one configuration, split A|B, or their difference")
    parser.add_argument("--size", metavar="WxH", default=None, type=size_type(window_size),
                        help=f"window size in pixels, each in [{window.low:g}, "
                             f"{window.high:g}] (default: as it was last closed)")
    parser.add_argument("--screenshot", metavar="PATH", type=Path,
                        help="write a PNG of the window after --frames frames, then exit")
    parser.add_argument("--frames", metavar="N", type=value_type("frames", FRAMES),
                        default=None, help=spec_help(FRAMES))
    parser.add_argument("--no-wait", dest="wait", action="store_false",
                        help="with --screenshot: write the frame after --frames frames as "
                             "it is, without waiting for it to converge (the view then "
                             "says \"propagating k/N\" and the lesson's numbers are "
                             "marked ≈)")
    parser.add_argument("--hidden", action="store_true",
                        help="do not show the window (scripted runs)")
    parser.add_argument("--no-persist", action="store_true",
                        help="neither read nor write the settings file")
    parser.add_argument("--repaint-all", action="store_true",
                        help="paint the whole window every frame, not only where the "
                             "panels changed (a check of the partial painting)")


def window_size(width: int, height: int) -> tuple[int, int]:
    """(width, height) checked by the persisted window size's spec."""
    from explorer.ui.state import AppState

    return specs(AppState)["window_size"].check("window size", (width, height))


def main(args: argparse.Namespace) -> int:
    if args.step is not None and not args.lesson:
        raise CommandError("--step needs --lesson")
    if not args.wait and args.screenshot is None:
        raise CommandError("--no-wait only acts with --screenshot; add that or leave "
                           "--no-wait out")
    frames = args.frames if args.frames is not None else (30 if args.screenshot else None)
    if args.scene:
        check_scene(args.scene)    # a broken mesh or scene file: refused before the window
    folder = folder_of(args)
    if args.lesson:
        _check_lesson(args.lesson, args.step, folder, args.shipped)
    if args.screenshot is not None:
        Outputs("--screenshot").file(args.screenshot)

    from explorer.gl.window import WindowError
    from explorer.ui.app import App
    from explorer.ui.state import AppState
    from explorer.ui.window_options import WindowOptions

    width, height = args.size or (None, None)
    try:
        app = App(AppState() if args.no_persist else None,
                  WindowOptions(width=width, height=height, visible=not args.hidden,
                                persist_settings=not args.no_persist,
                                partial_paint=not args.repaint_all))
    except WindowError as exc:
        raise CommandError(exc, 1) from None
    try:
        placement = placement_changes(args)
        if args.light_flux is not None:
            placement["light_flux"] = args.light_flux
        if args.scene or placement:
            # opening a scene resets its camera and lights; --light / --camera come after
            app.state.requests.open_scene = args.scene or app.state.settings.scene
            app.state.requests.scene_overrides = placement or None
        if args.preset:
            app.state.apply_preset(args.preset)
        if args.compare:
            app.state.view_mode = args.compare
        if folder is not None:
            app.state.lesson_folder = str(folder)
            app.state.lesson_folder_alone = not args.shipped
        if args.lesson:
            app.state.lesson_id, app.state.lesson_step = args.lesson, args.step or 1
        return app.run(frames=frames, screenshot=args.screenshot, converged=args.wait)
    finally:
        app.close()


def _check_lesson(key: str, step: int | None, folder: Path | None, shipped: bool) -> None:
    """The lesson exists and loads (its own error otherwise) and has step ``step``, before
    the window opens."""
    from explorer.lessons.folder import load_course

    course = load_course(folder, shipped, check_formula=None)
    try:
        lesson = course.find(key)
        if step is not None:
            lesson.step(step)
    except (KeyError, IndexError) as exc:
        raise CommandError(exc.args[0]) from None
