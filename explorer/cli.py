"""Command line: ``lpv-explorer COMMAND`` (run, render, constants, lessons, compare, diff,
export-mitsuba, site, bench, stability, doctor).

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
    "render": "render a frame or a lesson step headlessly to PNG, EXR or NPY, every stage "
              "as float arrays with --dump",
    "constants": "list the exact constants the renderer uses; --format glsl|hlsl|cpp|json: "
                 "the porting sheet",
    "lessons": "list, print, check, lint or export the lessons (lessons list | print ID | "
               "check | lint | export ID), or start one (lessons new NAME); --dir DIR: a "
               "folder of your own",
    "compare": "compare LPV against the one-bounce reference (error tables and images)",
    "diff": "their stages (an .npz named as render --dump names them) against ours: the "
            "largest and relative error per cell and pixel, and where",
    "bench": "time each GPU pass over grid sizes and iterations",
    "stability": "frame-to-frame change of the indirect light while a light, an object or "
                 "the camera moves",
    "doctor": "report what the GL driver offers and what is missing",
    "export-mitsuba": "write a scene as a Mitsuba 3 scene (XML or Python; its PLY meshes and "
                      "textures in OUT-files/)",
    "site": "build the course as a static web site (pages, pictures, baked numbers)",
}


def build_parser() -> argparse.ArgumentParser:
    from explorer.commands.options import ArgumentParser

    parser = ArgumentParser(
        prog="lpv-explorer",
        description="Explore Light Propagation Volumes: derivations, GPU passes, lessons.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, help_text in COMMANDS.items():
        sub_parser = sub.add_parser(name, help=help_text, description=help_text)
        _load(name).add_arguments(sub_parser)
        parser.command_parsers[name] = sub_parser
    return parser


def _parse(parser: argparse.ArgumentParser, argv: list[str]) -> argparse.Namespace:
    """Parse ``argv``; an option the command does not know is reported by that
    command's parser (``lpv-explorer render: error: unrecognized arguments: ...``)."""
    args, extras = parser.parse_known_args(argv)
    if extras:
        parser.command_parsers[args.command].error(
            f"unrecognized arguments: {' '.join(extras)}")
    return args


def _load(name: str):
    return importlib.import_module(f"explorer.commands.{name.replace('-', '_')}")


class StdoutError(Exception):
    """Standard output cannot be written (closed, or on a full disk)."""


class _GuardedStdout:
    """Standard output that turns a failed write into :class:`StdoutError` (a broken pipe
    stays ``BrokenPipeError``), so that no command mistakes it for a failure of its own
    files and :func:`main` reports it as one line. ``stream`` None: stdout was closed
    when the process started (``lpv-explorer constants >&-``)."""

    def __init__(self, stream) -> None:
        self._stream = stream

    def _call(self, method: str, *args):
        if self._stream is None:
            raise StdoutError("standard output is closed")
        try:
            return getattr(self._stream, method)(*args)
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise StdoutError(exc.strerror or str(exc)) from None

    def write(self, text: str) -> int:
        return self._call("write", text)

    def flush(self) -> None:
        self._call("flush")

    def isatty(self) -> bool:
        return self._stream is not None and self._stream.isatty()

    def __getattr__(self, name: str):
        if self._stream is None:
            raise StdoutError("standard output is closed")
        return getattr(self._stream, name)


def _silence_stdout() -> None:
    """Point file descriptor 1 at /dev/null, so the interpreter's final flush of what is
    still buffered cannot fail a second time."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
    except OSError:
        pass
    real = getattr(sys.stdout, "_stream", sys.stdout)
    if real is not None:
        try:
            real.flush()
        except OSError:
            pass
    sys.stdout = open(os.devnull, "w")


def main(argv: list[str] | None = None) -> int:
    """Run one command; returns its exit status. Bad input and failed requests end as one
    line on stderr (``lpv-explorer <cmd>: error: ...``), never a traceback: 2 for bad
    input, 1 for a request that failed, 130 for Ctrl-C, 143 for SIGTERM and 129 for
    SIGHUP (after the command removed what it had half written)."""
    from explorer import stop_signals
    from explorer.commands.options import CommandError

    if sys.stderr is None:            # stderr closed: messages have nowhere to go
        sys.stderr = open(os.devnull, "w")
    if not isinstance(sys.stdout, _GuardedStdout):
        sys.stdout = _GuardedStdout(sys.stdout)
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or (argv[0].startswith("-") and argv[0] not in ("-h", "--help")):
        argv = ["run", *argv]
    prog = f"lpv-explorer {argv[0]}" if argv[0] in COMMANDS else "lpv-explorer"
    try:
        parser = build_parser()
        args = _parse(parser, argv)
        if args.command is None:
            parser.print_help()
            return 2
        with stop_signals.raising():        # SIGTERM, SIGHUP unwind as Ctrl-C does
            code = int(_load(args.command).main(args) or 0)
            sys.stdout.flush()
    except SystemExit as exc:       # argparse: --help (0) or a bad option (2)
        return exc.code if isinstance(exc.code, int) else 2
    except CommandError as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return exc.code
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except stop_signals.Stopped as exc:
        print(f"{prog}: {exc}", file=sys.stderr)
        return exc.exit_code
    except StdoutError as exc:
        print(f"{prog}: error: cannot write to standard output: {exc}", file=sys.stderr)
        _silence_stdout()
        return 1
    except BrokenPipeError:
        # The reader went away (`lpv-explorer lessons | head`): stop quietly, as Unix tools
        # do. Point stdout at devnull so the interpreter's final flush cannot fail again.
        _silence_stdout()
        return 141 - 128   # SIGPIPE's number, the code `head` pipelines expect
    return code


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
