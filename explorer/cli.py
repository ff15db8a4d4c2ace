"""Command line: ``lpv-explorer [run|render|constants|lessons|compare|bench|doctor]``.

Each subcommand lives in ``explorer/commands/<name>.py`` and exposes
``add_arguments(parser)`` and ``main(args) -> int``. Modules are imported only when their
command runs, so ``lpv-explorer constants`` never touches GL or imgui.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

# name -> one-line help; the module is explorer.commands.<name>
COMMANDS: dict[str, str] = {
    "run": "open the explorer window (the default when no command is given)",
    "render": "render a frame or a lesson step headlessly to PNG",
    "constants": "list the exact constants the renderer uses",
    "lessons": "list the lessons",
    "compare": "compare LPV against the one-bounce reference (error tables and images)",
    "bench": "time each GPU pass over grid sizes and iterations",
    "doctor": "report what the GL driver offers and what is missing",
}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="lpv-explorer",
        description="Explore Light Propagation Volumes: derivations, GPU passes, lessons.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, help_text in COMMANDS.items():
        sub_parser = sub.add_parser(name, help=help_text, description=help_text)
        module = _load(name)
        if module is not None:
            module.add_arguments(sub_parser)
    return parser


def _load(name: str):
    try:
        return importlib.import_module(f"explorer.commands.{name}")
    except ModuleNotFoundError as exc:
        if exc.name == f"explorer.commands.{name}":
            return None
        raise


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or (argv[0].startswith("-") and argv[0] not in ("-h", "--help")):
        argv = ["run", *argv]
    parser = build_parser()
    args = parser.parse_args(argv)
    module = _load(args.command)
    if module is None:
        print(f"lpv-explorer: the command {args.command!r} is not available in this build",
              file=sys.stderr)
        return 2
    try:
        code = int(module.main(args) or 0)
        sys.stdout.flush()
    except BrokenPipeError:
        # The reader went away (`lpv-explorer lessons | head`): stop quietly, as Unix tools
        # do. Point stdout at devnull so the interpreter's final flush cannot fail again.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141 - 128   # SIGPIPE's number, the code `head` pipelines expect
    return code


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
