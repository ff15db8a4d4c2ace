"""``lpv-explorer run``: open the explorer window.

``--screenshot PATH --frames N`` draws N frames, writes the last one (panels included) to
PATH and exits: scripted runs, README screenshots and CI smoke tests.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--lesson", metavar="ID", help="open a lesson (e.g. 01 or its slug)")
    parser.add_argument("--scene", metavar="NAME|PATH",
                        help="a built-in scene (cornell, single-source, room, atrium) or a "
                             "mesh file")
    parser.add_argument("--preset", choices=("original", "corrected"),
                        help="start with the published or the corrected formulas")
    parser.add_argument("--compare", choices=("single", "split", "difference"),
                        help="view mode: one configuration, split A|B, or their difference")
    parser.add_argument("--size", metavar="WxH", default=None,
                        help="window size in pixels (default: as it was last closed)")
    parser.add_argument("--screenshot", metavar="PATH", type=Path,
                        help="write a PNG of the window after --frames frames, then exit")
    parser.add_argument("--frames", metavar="N", type=int, default=None,
                        help="draw N frames then exit (default with --screenshot: 30)")
    parser.add_argument("--hidden", action="store_true",
                        help="do not show the window (scripted runs)")
    parser.add_argument("--no-persist", action="store_true",
                        help="neither read nor write the settings file")


def _parse_size(text: str | None) -> tuple[int | None, int | None]:
    if text is None:
        return None, None   # the size the window had last time
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise SystemExit(f"lpv-explorer run: --size must look like 1280x800, got {text!r}")
    if width < 200 or height < 150:
        raise SystemExit("lpv-explorer run: --size must be at least 200x150")
    return width, height


def main(args: argparse.Namespace) -> int:
    if args.frames is not None and args.frames < 1:
        print("lpv-explorer run: --frames must be at least 1", file=sys.stderr)
        return 2
    width, height = _parse_size(args.size)
    frames = args.frames if args.frames is not None else (30 if args.screenshot else None)

    from explorer.gl.window import WindowError
    from explorer.ui.app import App
    from explorer.ui.state import AppState

    state = None
    if args.no_persist:
        state = AppState()
    try:
        app = App(state, width=width, height=height, visible=not args.hidden,
                  persist_settings=not args.no_persist)
    except WindowError as exc:
        print(f"lpv-explorer: {exc}", file=sys.stderr)
        return 1
    try:
        if args.scene:
            app.state.requests.open_scene = args.scene
        if args.preset:
            app.state.apply_preset(args.preset)
        if args.compare:
            app.state.view_mode = args.compare
        if args.lesson:
            problem = _open_lesson(app, args.lesson)
            if problem:
                print(f"lpv-explorer run: {problem}", file=sys.stderr)
                return 2
        return app.run(frames=frames, screenshot=args.screenshot)
    finally:
        app.close()


def _open_lesson(app, lesson_id: str) -> str | None:
    """Hand the lesson to the lessons panel when this build has one."""
    try:
        from explorer import lessons  # noqa: F401
    except ModuleNotFoundError:
        return "this build has no lessons module"
    app.state.lesson_id = lesson_id
    return None
