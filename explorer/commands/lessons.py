"""``lpv-explorer lessons [ID]``: list the lessons, or print one lesson's steps;
``lpv-explorer lessons --export ID --step K --out step.png`` writes a step as the window
shows it, headless (glfw's null platform with EGL: no display needed), once its frame has
converged (it says it waits); ``lpv-explorer lessons [ID] --check`` verifies the steps'
``[[steps.checks]]`` on their converged frames, rendered headless
(explorer/lessons/verify.py).

Listing also validates every lesson; a broken one is reported with its error and makes
the command exit 1, so CI and lesson authors see mistakes at once.
"""

from __future__ import annotations

import argparse
import sys
import textwrap
from pathlib import Path

from explorer.commands.options import size_type


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("lesson", nargs="?", metavar="ID",
                        help="a lesson id, number or file stem: print its steps")
    parser.add_argument("--dir", type=Path, default=None, metavar="PATH",
                        help="read lessons from this folder instead of the shipped ones")
    parser.add_argument("--check", action="store_true",
                        help="verify the claims the steps check ([[steps.checks]]) on "
                             "their converged frames, rendered headless at a small size; "
                             "exit 1 if one fails")
    group = parser.add_argument_group("export a step as the window shows it")
    group.add_argument("--export", metavar="ID", help="lesson id, number or file stem")
    group.add_argument("--step", type=int, default=None, metavar="K",
                       help="step of the exported lesson (default: 1)")
    group.add_argument("--out", type=Path, default=None, metavar="PNG",
                       help="the PNG to write (default: ./<lesson>-step<K>.png)")
    group.add_argument("--size", default=(1600, 900), metavar="WxH",
                       type=size_type(_export_size),
                       help="window size in pixels, at least 640x400 (default: 1600x900)")
    group.add_argument("--try", dest="try_this", type=int, default=None, metavar="K",
                       help="press the step's K-th try-this button before writing")
    group.add_argument("--no-overlays", dest="overlays", action="store_false",
                       help="leave out the in-scene overlays the step's [steps.show] sets "
                            "(to see what the main view shows without them)")


def _export_size(width: int, height: int) -> tuple[int, int]:
    """An export window size: the persisted window size's range, and room for the article
    beside the view (640x400 at least)."""
    from explorer.schema import SettingError, specs
    from explorer.ui.state import AppState

    if width < 640 or height < 400:
        raise SettingError("size", f"size must be at least 640x400, got {width}x{height}")
    return specs(AppState)["window_size"].check("size", (width, height))


def main(args: argparse.Namespace) -> int:
    from explorer.commands.options import CommandError
    from explorer.lessons import find_lesson, load_all

    if args.dir is not None and not args.dir.is_dir():
        raise CommandError(f"--dir {args.dir}: no such folder")
    if args.export:
        return _export(args)
    given = [flag for flag, value in (("--step", args.step), ("--out", args.out),
                                      ("--try", args.try_this)) if value is not None]
    given += [] if args.overlays else ["--no-overlays"]
    if args.check and not given:
        return _check(args)
    if given:
        raise CommandError(f"{', '.join(given)} need{'s' if len(given) == 1 else ''} "
                           "--export ID")
    from explorer.lessons.glossary import GlossaryError, load_glossary

    lessons, errors = load_all(args.dir)
    try:
        load_glossary(args.dir)
    except GlossaryError as exc:
        errors.append(exc)
    if not lessons and not errors:
        raise CommandError(f"no lessons (*.toml files) in {args.dir or 'the shipped lessons'}",
                           1)
    if args.lesson is None:
        _print_list(lessons)
    else:
        try:
            lesson = find_lesson(args.lesson, lessons, errors)
        except KeyError as exc:
            raise CommandError(exc.args[0]) from None
        _print_lesson(lesson)
    _print_errors(errors)
    return 1 if errors else 0


def _check(args: argparse.Namespace) -> int:
    """Verify the checks of lesson ``args.lesson`` (all lessons when None)."""
    from explorer.commands.options import CommandError
    from explorer.gl.context import create_headless_context, release_headless_context
    from explorer.lessons.verify import verify_step
    from explorer.lessons import find_lesson, load_all, preview_settings
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.figures import declared_readouts

    lessons, errors = load_all(args.dir)
    if args.lesson is not None:
        try:
            lessons = [find_lesson(args.lesson, lessons, errors)]
        except KeyError as exc:
            raise CommandError(exc.args[0]) from None
    steps = [(lesson, step) for lesson in lessons for step in lesson.steps if step.checks]
    failed = total = 0
    if steps:
        ctx = create_headless_context()
        try:
            with Pipeline(preview_settings(steps[0][1]), ctx=ctx) as pipeline:
                for lesson, step in steps:
                    print(f"{lesson.path.stem} step {step.number}: {step.title}")
                    for outcome in verify_step(pipeline, step,
                                               figure_readouts=declared_readouts):
                        total += 1
                        failed += not outcome.holds
                        print(f"  {outcome}")
        finally:
            release_headless_context(ctx)
    print(f"{total - failed} of {total} checks hold on {len(steps)} steps")
    _print_errors(errors)
    return 1 if failed or errors else 0


def _print_list(lessons) -> None:
    width = max((len(lesson.id) for lesson in lessons), default=0)
    for lesson in lessons:
        count = len(lesson.steps)
        print(f"{lesson.number:02d}  {lesson.id:<{width}}  {lesson.title}  "
              f"({count} step{'s' if count != 1 else ''})")


def _plain(text: str, mark_ids: tuple[str, ...] = (), settings=None) -> str:
    """Lesson text for a terminal: derived numbers filled in, live ones named in
    brackets (they are measured in the window), markers spelled out, math as text."""
    from explorer.lessons import live_values
    from explorer.lessons import text as lesson_text
    from explorer.lessons import math_to_text

    def value(name: str, fmt: str) -> str:
        if name.startswith(("derived.", "settings.", "corrections.")):
            return live_values.render(name, fmt, live_values.LiveContext(settings=settings))
        try:
            doc = live_values.lookup(name, (), tuple(mark_ids)).doc
        except KeyError:
            doc = name
        return f"[{doc}]"

    text = lesson_text.substitute(text, value)
    def marker(match) -> str:
        if match.group(1) == "formula":
            from explorer import derived

            return f"[formula: {derived.get(match.group(2)).statement}]"
        return f"[{match.group(1)} {match.group(2)}]"

    text = lesson_text.MARKER_FIELD.sub(marker, text)
    return math_to_text(text.replace("$$", "$"))


def _setting_label(name: str) -> str:
    from explorer.schema import specs
    from explorer.lpv.settings import Settings

    spec = specs(Settings).get(name)
    return (getattr(spec, "label", "") or name.replace("_", " ")).lower()


def _print_lesson(lesson) -> None:
    from explorer.lessons import CORRECTIONS_TITLES
    from explorer.lessons.live_values import format_value

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
        changed = [CORRECTIONS_TITLES.get(name, name) for name in step.corrections.names()
                   if getattr(step.corrections, name) is False]
        shows.append("corrections: " + ("all on" if not changed else
                                        "published: " + ", ".join(changed)))
        if step.overrides:
            shows.append(", ".join(f"{_setting_label(k)} {format_value(v, 'g')}"
                                   for k, v in step.overrides))
        print(textwrap.fill("shows: " + "; ".join(shows), width=88, subsequent_indent="  "))
        print()
        print(_plain(step.text.strip(), step.mark_ids, step.settings()))
        if step.formulas:
            from explorer import derived

            print()
            for name in step.formulas:
                print(textwrap.fill("formula: " + derived.get(name).statement, width=88,
                                    subsequent_indent="  "))
        for item in step.try_this:
            if item.predict is not None:
                choices = " / ".join(item.predict.choices)
                answer = item.predict.choices[item.predict.answer - 1]
                print(textwrap.fill(f"predict: {item.predict.question} ({choices}; the "
                                    f"answer: {answer})", width=88, subsequent_indent="  "))
            prompt = _plain(item.prompt, step.mark_ids, item.apply(step.settings()))
            print(textwrap.fill(f"try this [{item.button()[0]}]: {prompt}", width=88,
                                subsequent_indent="  "))
    print()
    print(f"render a step: lpv-explorer render --lesson {lesson.id} --step 1")


def _print_errors(errors) -> None:
    for error in errors:
        print(f"broken lesson: {error}", file=sys.stderr)


def _export(args: argparse.Namespace) -> int:
    """Write step ``args.step`` of lesson ``args.export`` as the window shows it."""
    from explorer.commands.options import CommandError, Outputs
    from explorer.gl.window import WindowError
    from explorer.ui.export import export_step

    step = 1 if args.step is None else args.step
    print(f"exporting {args.export} step {step}: waiting for the converged frame", flush=True)
    with Outputs() as outputs:
        out = outputs.file(args.out or Path.cwd() / f"{args.export}-step{step}.png",
                           suffixes=(".png",))
        width, height = args.size
        try:
            outputs.write(out, lambda path: export_step(args.export, step, path, width,
                                                        height, try_this=args.try_this,
                                                        overlays=args.overlays))
        except (KeyError, IndexError) as exc:
            raise CommandError(exc.args[0]) from None
        except (WindowError, TimeoutError) as exc:
            raise CommandError(exc, 1) from None
    print(f"wrote {out} (the converged frame)")
    return 0
