"""``lpv-explorer lessons [ID]``: list the lessons, or print one lesson's steps;
``lpv-explorer lessons --export ID --step K --out step.png`` writes a step as the window
shows it (a hidden window: needs a display, e.g. ``xvfb-run``).

Listing also validates every lesson; a broken one is reported with its error and makes
the command exit 1, so CI and lesson authors see mistakes at once.
"""

from __future__ import annotations

import argparse
import sys
import textwrap
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("lesson", nargs="?", metavar="ID",
                        help="a lesson id, number or file stem: print its steps")
    parser.add_argument("--dir", type=Path, default=None, metavar="PATH",
                        help="read lessons from this folder instead of the shipped ones")
    group = parser.add_argument_group("export a step as the window shows it")
    group.add_argument("--export", metavar="ID", help="lesson id, number or file stem")
    group.add_argument("--step", type=int, default=1, metavar="K",
                       help="step of the exported lesson (default: 1)")
    group.add_argument("--out", type=Path, default=None, metavar="PNG",
                       help="the PNG to write (default: ./<lesson>-step<K>.png)")
    group.add_argument("--size", default="1600x900", metavar="WxH",
                       help="window size in pixels (default: 1600x900)")
    group.add_argument("--try", dest="try_this", type=int, default=None, metavar="K",
                       help="press the step's K-th try-this button before writing")


def main(args: argparse.Namespace) -> int:
    from explorer.lessons import find_lesson, load_all

    if args.export:
        return _export(args)

    lessons, errors = load_all(args.dir)
    if args.lesson is None:
        _print_list(lessons)
    else:
        try:
            lesson = find_lesson(args.lesson, lessons)
        except KeyError as exc:
            print(f"lpv-explorer lessons: {exc.args[0]}", file=sys.stderr)
            _print_errors(errors)
            return 1
        _print_lesson(lesson)
    _print_errors(errors)
    return 1 if errors else 0


def _print_list(lessons) -> None:
    if not lessons:
        print("no lessons found")
        return
    width = max(len(lesson.id) for lesson in lessons)
    for lesson in lessons:
        count = len(lesson.steps)
        print(f"{lesson.number:02d}  {lesson.id:<{width}}  {lesson.title}  "
              f"({count} step{'s' if count != 1 else ''})")


def _plain(text: str) -> str:
    """Lesson text for a terminal: derived numbers filled in, live ones named in
    brackets (they are measured in the window), markers spelled out, math as text."""
    from explorer import lesson_text, live_values
    from explorer.lessons import math_to_text

    def value(name: str, fmt: str) -> str:
        if name.startswith("derived."):
            return live_values.render(name, fmt, live_values.LiveContext())
        return f"[{name}]"

    text = lesson_text.substitute(text, value)
    text = lesson_text.MARKER_FIELD.sub(lambda m: f"[{m.group(1)} {m.group(2)}]", text)
    return math_to_text(text.replace("$$", "$"))


def _print_lesson(lesson) -> None:
    print(f"{lesson.title}  [{lesson.id}, {lesson.path.name}]")
    print(textwrap.fill(lesson.summary, width=88))
    for step in lesson.steps:
        print()
        print(f"--- step {step.number}/{len(lesson.steps)}: {step.title}")
        shows = [f"scene {step.scene}", f"view {step.view}"]
        if step.compare_preset:
            shows.append(f"against {step.compare_preset}")
        if step.plot:
            shows.append(f"plot {step.plot}")
        changed = [name for name in step.corrections.names()
                   if getattr(step.corrections, name) is False]
        shows.append("corrections: " + ("all on" if not changed else
                                        "off: " + ", ".join(changed)))
        if step.overrides:
            shows.append(", ".join(f"{k}={v}" for k, v in step.overrides))
        print(textwrap.fill("shows: " + "; ".join(shows), width=88, subsequent_indent="  "))
        print()
        print(_plain(step.text.strip()))
        if step.formulas:
            print()
            print("formulas: " + ", ".join(step.formulas))
        for item in step.try_this:
            print(textwrap.fill(f"try this [{item.control} = {item.value!r}]: "
                                f"{_plain(item.prompt)}", width=88, subsequent_indent="  "))
    print()
    print(f"render a step: lpv-explorer render --lesson {lesson.id} --step 1")


def _print_errors(errors) -> None:
    for error in errors:
        print(f"broken lesson: {error}", file=sys.stderr)


# --- `lpv-explorer render --lesson ID --step K` -------------------------------------------
# The render command (explorer/commands/render.py) adds the two options with
# add_render_arguments() and hands over to render_lesson_step() when --lesson is given.

def add_render_arguments(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group(
        "lesson steps", "render what a lesson step shows: its scene, settings, corrections "
        "and view; --grid, --iterations, --size, --rsm-size, --exposure, --downsample, "
        "--downsample-factor, --geometry-volume and --indirect-only override the step, "
        "--scene and --preset are ignored")
    group.add_argument("--lesson", metavar="ID", help="lesson id, number or file stem")
    group.add_argument("--step", type=int, default=1, metavar="K",
                       help="step number within the lesson (default: 1)")


def render_lesson_step(args: argparse.Namespace) -> int:
    """Render step ``args.step`` of lesson ``args.lesson`` to ``args.out``."""
    from explorer.commands.render import (
        CAMERA_VIEWS,
        SETTING_OPTIONS,
        option_changes,
        output_changes,
        output_paths,
        print_audit,
        render_error,
        write_png,
    )
    from explorer.gl.context import GLUnavailableError
    from explorer.gl.program import ShaderError
    from explorer.lessons import (
        COMPARE_VIEWS,
        LessonError,
        find_lesson,
        load_lesson,
        render_step,
    )
    from explorer.lpv.pipeline import Pipeline
    from explorer.resources import lesson_dir

    try:
        lessons = []
        for path in sorted(lesson_dir().glob("*.toml")):
            try:
                lessons.append(load_lesson(path, check_formula=None))
            except LessonError:
                continue  # `lpv-explorer lessons` reports broken lessons
        lesson = find_lesson(args.lesson, lessons)
        step = lesson.step(args.step)
    except (KeyError, IndexError) as exc:
        return render_error(exc.args[0], 2)
    changes = {**option_changes(args, SETTING_OPTIONS), **output_changes(args)}
    try:
        settings = step.settings().with_changes(**changes)
    except ValueError as exc:
        return render_error(exc, 2)
    print(f"lesson {lesson.id}, step {step.number}/{len(lesson.steps)}: {step.title}")
    views = args.view or [step.view]
    try:
        with Pipeline(settings) as pipeline:
            for view, path in output_paths(args.out, views).items():
                if view == step.view:
                    image, _ = render_step(pipeline, step, settings)
                else:
                    pipeline.run(settings)
                    image = pipeline.view(view)
                write_png(image, path, enlarge=view not in CAMERA_VIEWS + COMPARE_VIEWS)
                shown = f"{view} against {step.compare_preset}" if step.compare_preset and \
                    view == step.view else view
                print(f"wrote {path} ({shown})")
            if args.audit:
                print_audit(pipeline.run(settings))
    except (ValueError, FloatingPointError, GLUnavailableError, ShaderError, OSError) as exc:
        return render_error(exc, 1)
    return 0


def _export(args: argparse.Namespace) -> int:
    from explorer.gl.window import WindowError
    from explorer.ui.export import export_step

    try:
        width, height = (int(v) for v in args.size.lower().split("x"))
    except ValueError:
        print(f"lpv-explorer lessons: --size must look like 1600x900, got {args.size!r}",
              file=sys.stderr)
        return 2
    if width < 640 or height < 400:
        print("lpv-explorer lessons: --size must be at least 640x400", file=sys.stderr)
        return 2
    out = args.out or Path.cwd() / f"{args.export}-step{args.step}.png"
    if out.suffix.lower() != ".png":
        print(f"lpv-explorer lessons: --out must be a .png file, got {out}", file=sys.stderr)
        return 2
    try:
        path = export_step(args.export, args.step, out, width, height,
                           try_this=args.try_this)
    except (KeyError, IndexError) as exc:
        print(f"lpv-explorer lessons: {exc.args[0]}", file=sys.stderr)
        return 2
    except (WindowError, TimeoutError, OSError) as exc:
        print(f"lpv-explorer lessons: {exc}", file=sys.stderr)
        return 1
    print(f"wrote {path}")
    return 0
