"""``lpv-explorer lessons [ID]``: list the lessons, or print one lesson's steps;
``lpv-explorer lessons new NAME [--dir DIR]`` writes a small working lesson to start from
(explorer/lessons/template.py); ``lpv-explorer lessons --export ID --step K --out
step.png`` writes a step as the window shows it, headless (glfw's null platform with EGL:
no display needed), once its frame has converged (it says it waits); ``lpv-explorer
lessons [ID] --check [DIR]`` verifies the steps' ``[[steps.checks]]`` on their converged
frames, rendered headless (explorer/lessons/verify.py), and prints each claim with the
numbers it read; ``lpv-explorer lessons [ID] --lint [DIR]`` holds a folder's lessons to
what the shipped course is held to (explorer/lessons/words.py, explorer/ui/lesson_lint.py).

The verbs may also be written as words: ``lessons list``, ``lessons print ID``,
``lessons check [ID | DIR]``, ``lessons lint [ID | DIR]`` and ``lessons export ID`` are
``lessons``, ``lessons ID``, ``--check``, ``--lint`` and ``--export ID`` (a word that is
a folder is the folder, as ``--check DIR`` takes it; a lesson whose id is a verb is
named by its number or file stem).

Every verb reads the folder ``--dir DIR`` (or ``--lessons DIR``, or the DIR given to
``--check``/``--lint``) instead of the shipped lessons. Listing also validates every
lesson; a broken one is reported with its error and makes the command exit 1, so CI and
lesson authors see mistakes at once.
"""

from __future__ import annotations

import argparse
import sys
import textwrap
from pathlib import Path

from explorer.commands.lesson_folder import add_folder_option, folder_of
from explorer.commands.options import CommandError, size_type

NEW = "new"
"""The verb of ``lessons new NAME``."""
VERBS = (NEW, "list", "print", "check", "lint", "export")
"""The words ``lessons`` takes as a verb before its arguments (the rest are flags too)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("words", nargs="*", metavar="ID | VERB ...",
                        help="a lesson id, number or file stem: print its steps; or a "
                             "verb: list, print ID, check [ID|DIR], lint [ID|DIR], "
                             "export ID (as --check, --lint, --export), new NAME: write a "
                             "lesson called NAME to start from")
    add_folder_option(parser, ("--dir", "--lessons"))
    parser.add_argument("--check", nargs="?", const=True, default=False, metavar="DIR",
                        help="verify the claims the steps check ([[steps.checks]]) on "
                             "their converged frames, rendered headless at a small size, "
                             "and print each with its numbers; exit 1 if one fails")
    parser.add_argument("--lint", nargs="?", const=True, default=False, metavar="DIR",
                        help="hold the lessons to what the shipped course is held to: "
                             "words and typeset math only (no settings or quantity names, "
                             "no raw TeX outside math), every figure fits the article "
                             "column, every labelled mark in view; exit 1 on a finding")
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


def _verb_folder(args: argparse.Namespace) -> None:
    """``--check DIR`` / ``--lint DIR``: that folder, as ``--dir`` names it (both given
    with different folders: refused)."""
    for flag in ("check", "lint"):
        value = getattr(args, flag)
        if not isinstance(value, str):
            continue
        folder = Path(value)
        if args.lessons_dir is not None and args.lessons_dir != folder:
            raise CommandError(f"--{flag} {value} and {args.lessons_flag} "
                               f"{args.lessons_dir}: one lesson folder at a time")
        if not folder.is_dir():
            raise CommandError(f"--{flag} {value}: no such folder (to {flag} one lesson: "
                               f"lpv-explorer lessons ID --{flag})")
        args.lessons_dir, args.lessons_flag = folder, f"--{flag}"
        setattr(args, flag, True)


def _verb_words(args: argparse.Namespace) -> list[str]:
    """The words after a verb written as a word (``lessons check my-lessons``), the verb
    turned into its flag; the words as given when the first is no verb."""
    words = list(args.words)
    verb = words[0] if words else None
    if verb not in VERBS or verb == NEW:
        return words
    rest = words[1:]
    flags = [flag for flag, on in (("--check", args.check), ("--lint", args.lint),
                                   ("--export", args.export)) if on]
    if flags and flags != [f"--{verb}"]:
        raise CommandError(f"lessons {verb} and {flags[0]}: one verb at a time")
    if len(rest) > 1 or (verb == "list" and rest):
        raise CommandError(f"lessons {verb}: {'no' if verb == 'list' else 'one'} "
                           f"{'lesson' if verb != 'list' else 'argument'}"
                           f"{'' if verb == 'list' else ' at a time'}, got {' '.join(rest)}"
                           + (" (a lesson's steps: lpv-explorer lessons print ID)"
                              if verb == "list" else ""))
    if verb in ("print", "export") and not rest:
        raise CommandError(f"lessons {verb} ID: name the lesson (its id, number or file "
                           "stem; lpv-explorer lessons list lists them)")
    if verb == "export":
        args.export = rest[0]
        return []
    if verb in ("check", "lint"):
        # a folder there is the folder, as --check DIR takes it; else a lesson of the course
        if rest and Path(rest[0]).is_dir():
            setattr(args, verb, rest[0])
            rest = []
        elif rest and ("/" in rest[0] or "\\" in rest[0]):
            raise CommandError(f"lessons {verb} {rest[0]}: no such folder")
        elif not isinstance(getattr(args, verb), str):
            setattr(args, verb, True)
    return rest


def main(args: argparse.Namespace) -> int:
    from explorer.lessons.glossary import GlossaryError, load_glossary

    if args.words[:1] == [NEW]:
        _verb_folder(args)
        return _new(args, list(args.words[1:]))
    words = _verb_words(args)
    _verb_folder(args)
    if len(words) > 1:
        raise CommandError(f"one lesson at a time, got {' '.join(words)} (to start a "
                           "lesson: lpv-explorer lessons new NAME)")
    args.lesson = words[0] if words else None
    folder = folder_of(args)
    verbs = [flag for flag, on in (("--check", args.check), ("--lint", args.lint),
                                   ("--export", args.export)) if on]
    if len(verbs) > 1:
        raise CommandError(f"{' and '.join(verbs)}: one at a time")
    if args.export:
        if args.lesson is not None:
            raise CommandError(f"--export {args.export} names the lesson; drop {args.lesson}")
        return _export(args, folder)
    given = [flag for flag, value in (("--step", args.step), ("--out", args.out),
                                      ("--try", args.try_this)) if value is not None]
    given += [] if args.overlays else ["--no-overlays"]
    if given:
        raise CommandError(f"{', '.join(given)} need{'s' if len(given) == 1 else ''} "
                           "--export ID")
    course = _course(args, folder)
    if args.check:
        return _check(args, course)
    if args.lint:
        return _lint(args, course)
    errors = list(course.errors)
    try:
        load_glossary(folder)
    except GlossaryError as exc:
        errors.append(exc)
    if args.lesson is None:
        _print_list(course.lessons)
    else:
        _print_lesson(_chosen(args, course)[0])
    _print_errors(errors)
    return 1 if errors else 0


def _course(args: argparse.Namespace, folder: Path | None):
    from explorer.lessons.folder import load_course

    course = load_course(folder, shipped=False)
    if not course.lessons and not course.errors:
        raise CommandError(f"no lessons (*.toml files) in {folder or 'the shipped lessons'}"
                           + (f"; start one: lpv-explorer lessons new NAME --dir {folder}"
                              if folder else ""), 1)
    return course


def _chosen(args: argparse.Namespace, course) -> list:
    """The lesson ``args.lesson`` names (its own error when broken), or every lesson."""
    if args.lesson is None:
        return list(course.lessons)
    try:
        return [course.find(args.lesson)]
    except KeyError as exc:
        raise CommandError(exc.args[0]) from None


def _new(args: argparse.Namespace, names: list[str]) -> int:
    """Write ``NN-<id>.toml`` (NN: the folder's next number) from the template."""
    from explorer.commands.options import Outputs
    from explorer.lessons import load_lesson
    from explorer.lessons.template import new_lesson

    if len(names) != 1:
        raise CommandError("lessons new NAME: give the new lesson's name (one word, or "
                           "quoted words)" if not names else
                           f"lessons new NAME: one name, got {' '.join(names)} (quote a "
                           "name of several words)")
    for flag, on in (("--check", args.check), ("--lint", args.lint),
                     ("--export", args.export)):
        if on:
            raise CommandError(f"lessons new writes a lesson; {flag} is another verb")
    folder = args.lessons_dir or Path.cwd()
    if folder.exists() and not folder.is_dir():
        raise CommandError(f"{args.lessons_flag} {folder}: not a folder")
    try:
        lesson_id, text = new_lesson(names[0])
    except ValueError as exc:
        raise CommandError(exc) from None
    if lesson_id in VERBS:
        raise CommandError(f"lessons new {names[0]!r}: {lesson_id!r} is a verb of lessons "
                           f"(lessons {lesson_id} ...); give the lesson another name")
    taken = sorted(folder.glob("[0-9]*-*.toml")) if folder.is_dir() else []
    for path in taken:
        if path.stem.split("-", 1)[1] == lesson_id:
            raise CommandError(f"{path} is a lesson called {lesson_id!r} already")
    numbers = [int(path.name.split("-", 1)[0]) for path in taken
               if path.name.split("-", 1)[0].isdigit()]
    path = folder / f"{max(numbers, default=0) + 1:02d}-{lesson_id}.toml"
    with Outputs() as outputs:
        out = outputs.file(path, suffixes=(".toml",))
        if out.exists():
            raise CommandError(f"{out} exists; it is kept")
        outputs.write(out, lambda target: Path(target).write_text(text, encoding="utf-8"))
    lesson = load_lesson(out)      # what it wrote is a lesson (or this is a bug)
    shown = f" --dir {folder}" if args.lessons_dir is not None else ""
    print(f"wrote {out}: {lesson.title!r}, {len(lesson.steps)} steps")
    print(f"open it while you edit it (each save shows): lpv-explorer run --lessons {folder} "
          f"--lesson {lesson.id}")
    print(f"check its claims: lpv-explorer lessons{shown} --check; the guide: "
          "docs/AUTHORING.md")
    return 0


def _check(args: argparse.Namespace, course) -> int:
    """Verify the checks of the chosen lessons on their converged frames; each claim is
    printed with the numbers it read, a failing one marked FAILS."""
    from explorer.gl.context import create_headless_context, release_headless_context
    from explorer.lessons import preview_settings
    from explorer.lessons.verify import FrameCache, verify_step
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.figures import declared_readouts

    lessons = _chosen(args, course)
    steps = [(lesson, step) for lesson in lessons for step in lesson.steps if step.checks]
    failed = total = 0
    if steps:
        ctx = create_headless_context()
        cache = FrameCache()
        try:
            with Pipeline(preview_settings(steps[0][1]), ctx=ctx) as pipeline:
                for lesson, step in steps:
                    print(f"{lesson.path.stem} step {step.number}: {step.title}")
                    for outcome in verify_step(pipeline, step, figure_readouts=declared_readouts,
                                               cache=cache):
                        total += 1
                        failed += not outcome.holds
                        print(f"  {outcome}")
        finally:
            release_headless_context(ctx)
    print(f"{total - failed} of {total} checks hold on {len(steps)} steps"
          + _broken_note(course.errors, "checked"))
    _print_errors(course.errors)
    return 1 if failed or course.errors else 0


def _lint(args: argparse.Namespace, course) -> int:
    """The shipped course's rules on the chosen lessons: their words (no GL), their
    figures drawn at the article's column width (a hidden window) and their labelled
    marks placed in a tiny frame of each step (headless)."""
    from explorer.gl.context import create_headless_context, release_headless_context
    from explorer.gl.window import WindowError, headless_available
    from explorer.lessons import preview_settings
    from explorer.lessons.words import lesson_word_problems
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.lesson_lint import (
        figure_overflows,
        figure_window,
        hidden_marks,
        lesson_figures,
    )

    lessons = _chosen(args, course)
    found = [("words", line) for line in lesson_word_problems(lessons)]
    figures = lesson_figures(lessons)
    if figures:
        try:
            window = figure_window(900, 900, headless=headless_available())
        except WindowError as exc:
            raise CommandError(f"cannot draw the figures: {exc}", 1) from None
        try:
            found += [("figure", line) for line in figure_overflows(window, figures)]
        finally:
            window.close()
    marked = [lesson for lesson in lessons
              if any(mark.label for step in lesson.steps for mark in step.marks)]
    if marked:
        ctx = create_headless_context()
        try:
            with Pipeline(preview_settings(marked[0].steps[0]), ctx=ctx) as pipeline:
                found += [("mark", line) for line in hidden_marks(pipeline, marked)]
        finally:
            release_headless_context(ctx)
    for kind, line in found:
        print(f"{kind}: {line}")
    steps = sum(len(lesson.steps) for lesson in lessons)
    print(f"{_count(len(found), 'finding')} in {_count(len(lessons), 'lesson')} "
          f"({_count(steps, 'step')}, {_count(len(figures), 'figure')})"
          + _broken_note(course.errors, "linted"))
    _print_errors(course.errors)
    return 1 if found or course.errors else 0


def _broken_note(errors, verb: str) -> str:
    """The summary's note on the lessons that did not load (named one a line below it),
    so that "0 of 0 checks hold" never reads as a folder that passed."""
    if not errors:
        return ""
    return f"; {_count(len(errors), 'broken lesson')} not {verb} (each below, exit 1)"


def _count(number: int, noun: str) -> str:
    return f"{number} {noun}{'s' if number != 1 else ''}"


def _print_list(lessons) -> None:
    width = max((len(lesson.id) for lesson in lessons), default=0)
    for lesson in lessons:
        count = len(lesson.steps)
        print(f"{lesson.number:02d}  {lesson.id:<{width}}  {lesson.title}  "
              f"({count} step{'s' if count != 1 else ''})")


def _plain(text: str, mark_ids: tuple[str, ...] = (), settings=None) -> str:
    """Lesson text for a terminal: derived numbers filled in, live ones named in
    brackets (they are measured in the window), markers spelled out, math as text."""
    from explorer.lessons import live_values, math_to_text
    from explorer.lessons import text as lesson_text

    def value(name: str, fmt: str) -> str:
        if name.startswith(("derived.", "settings.", "corrections.")):
            return live_values.render(name, fmt, live_values.LiveContext(settings=settings))
        try:
            doc = live_values.lookup(name, (), tuple(mark_ids)).doc
        except KeyError:
            doc = name
        return f"[{doc}]"

    text = lesson_text.substitute(lesson_text.for_medium(text, "window"), value)

    def marker(match) -> str:
        if match.group(1) == "formula":
            from explorer import derived

            return f"[formula: {derived.get(match.group(2)).statement}]"
        return f"[{match.group(1)} {match.group(2)}]"

    text = lesson_text.MARKER_FIELD.sub(marker, text)
    return math_to_text(text.replace("$$", "$"))


def _setting_label(name: str) -> str:
    from explorer.lpv.settings import Settings
    from explorer.schema import specs

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


def _export(args: argparse.Namespace, folder: Path | None) -> int:
    """Write step ``args.step`` of lesson ``args.export`` (of ``folder``, else the
    shipped course) as the window shows it."""
    from explorer.commands.options import Outputs
    from explorer.gl.window import WindowError
    from explorer.ui.export import export_step, exported_lesson

    step = 1 if args.step is None else args.step
    try:     # a lesson, step or try-this that does not exist: one line, nothing before it
        exported_lesson(args.export, step, args.try_this, folder)
    except (KeyError, IndexError) as exc:
        raise CommandError(exc.args[0]) from None
    print(f"exporting {args.export} step {step}: waiting for the converged frame", flush=True)
    with Outputs() as outputs:
        out = outputs.file(args.out or Path.cwd() / f"{args.export}-step{step}.png",
                           suffixes=(".png",))
        width, height = args.size
        try:
            outputs.write(out, lambda path: export_step(args.export, step, path, width,
                                                        height, try_this=args.try_this,
                                                        overlays=args.overlays,
                                                        lessons_dir=folder))
        except (KeyError, IndexError) as exc:
            raise CommandError(exc.args[0]) from None
        except (WindowError, TimeoutError) as exc:
            raise CommandError(exc, 1) from None
    print(f"wrote {out} (the converged frame)")
    return 0
