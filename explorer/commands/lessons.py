"""``lpv-explorer lessons [ID]``: list the lessons, or print one lesson's steps.

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


def main(args: argparse.Namespace) -> int:
    from explorer.commands.options import CommandError
    from explorer.lessons import find_lesson, load_all

    if args.dir is not None and not args.dir.is_dir():
        raise CommandError(f"--dir {args.dir}: no such folder")
    lessons, errors = load_all(args.dir)
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


def _print_list(lessons) -> None:
    width = max((len(lesson.id) for lesson in lessons), default=0)
    for lesson in lessons:
        count = len(lesson.steps)
        print(f"{lesson.number:02d}  {lesson.id:<{width}}  {lesson.title}  "
              f"({count} step{'s' if count != 1 else ''})")


def _print_lesson(lesson) -> None:
    from explorer.lessons import math_to_text

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
        print(math_to_text(step.text.strip()))
        if step.formulas:
            print()
            print("formulas: " + ", ".join(step.formulas))
        for item in step.try_this:
            print(textwrap.fill(f"try this [{item.control}]: {item.prompt}", width=88,
                                subsequent_indent="  "))
    print()
    print(f"render a step: lpv-explorer render --lesson {lesson.id} --step 1")


def _print_errors(errors) -> None:
    for error in errors:
        print(f"broken lesson: {error}", file=sys.stderr)
