"""``--lessons DIR`` (alias ``--dir``): a lesson folder of one's own, the same option in
every command that reads lessons (run, render, lessons, site), checked the same way.

The window lists the shipped course and the folder side by side (``--no-shipped``: the
folder alone); the other commands read the folder instead of the shipped lessons.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from explorer.commands.options import CommandError

FLAGS = ("--lessons", "--dir")


class _Folder(argparse.Action):
    """Stores the folder and the flag that named it (for the messages); the two spellings
    or one given twice with different folders is refused, never one silently kept."""

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        given = getattr(namespace, self.dest, None)
        if given is not None and Path(given) != Path(values):
            parser.error(f"{namespace.lessons_flag} {given} and {option_string} {values}: "
                         "one lesson folder at a time")
        setattr(namespace, self.dest, Path(values))
        namespace.lessons_flag = option_string


def add_folder_option(parser: argparse.ArgumentParser, flags: tuple[str, ...] = FLAGS,
                      alone: bool = False) -> None:
    """Add the folder option (``flags``: its spellings, the first the name used in the
    help); ``alone``: also ``--no-shipped`` (the window's list without the course)."""
    what = ("list this folder's lessons beside the shipped course" if alone else
            "read the lessons from this folder instead of the shipped ones")
    parser.add_argument(*flags, dest="lessons_dir", action=_Folder, default=None,
                        metavar="DIR", help=f"{what} (a lesson names a scene file or a mesh "
                                            "relative to itself)")
    parser.set_defaults(lessons_flag=flags[0])
    if alone:
        parser.add_argument("--no-shipped", dest="shipped", action="store_false",
                            help=f"with {flags[0]}: list the folder's lessons alone")


def folder_of(args: argparse.Namespace) -> Path | None:
    """The folder the options name (None: the shipped lessons); one line when it is not a
    folder."""
    folder = getattr(args, "lessons_dir", None)
    if getattr(args, "shipped", True) is False and folder is None:
        raise CommandError(f"--no-shipped needs {args.lessons_flag} DIR (the lessons to list)")
    if folder is None:
        return None
    if not folder.is_dir():
        what = "not a folder" if folder.exists() else "no such folder"
        raise CommandError(f"{args.lessons_flag} {folder}: {what}")
    return folder


def load_folder(args: argparse.Namespace, **load_options):
    """The course the options name (explorer.lessons.folder.Course): the folder alone,
    or the shipped lessons without one; ``load_options``: ``load_all``'s."""
    from explorer.lessons.folder import load_course

    return load_course(folder_of(args), shipped=False, **load_options)
