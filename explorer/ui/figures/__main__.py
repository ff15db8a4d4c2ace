"""Show one figure alone: ``python -m explorer.ui.figures KIND [--PARAM VALUE ...]``.

With ``--screenshot out.png`` it draws ``--frames`` frames in a hidden window and writes
the last one; without, it opens a window until you close it. ``--list`` prints the kinds
and their parameters. The audit figures plot a pipeline run of the Cornell box at a small
size (configuration A with ``--preset``, B with ``--compare``). A value that starts with
a minus sign but is not a number is written with ``=``: ``--direction=-z``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from explorer.figure_params import FigureParamError, ParamInfo
from explorer.ui.figures.registry import FIGURES, USES_RESULTS, FigureKind, parse_figure

PROG = "python -m explorer.ui.figures"


def _bool(text: str) -> bool:
    if text.lower() in ("true", "1", "yes", "on"):
        return True
    if text.lower() in ("false", "0", "no", "off"):
        return False
    raise argparse.ArgumentTypeError(f"expected true or false, got {text!r}")


def _number(text: str) -> int | float:
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


_CONVERT = {"bool": _bool, "int": _number, "float": _number, "choice": str}


def build_parser(kind: FigureKind | None) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    parser.add_argument("kind", nargs="?", help=f"one of {', '.join(FIGURES)}")
    parser.add_argument("--list", action="store_true", help="list the kinds and parameters")
    parser.add_argument("--screenshot", type=Path, help="write the window to this PNG")
    parser.add_argument("--frames", type=int, default=6, help="frames before the screenshot")
    parser.add_argument("--width", type=int, default=1000, help="window width (pixels)")
    parser.add_argument("--height", type=int, default=800, help="window height (pixels)")
    parser.add_argument("--figure-width", type=float, default=None,
                        help="figure width (pixels); default: the window's")
    parser.add_argument("--preset", default="corrected",
                        help="audit figures: configuration A's preset")
    parser.add_argument("--compare", default="original",
                        help="audit figures: configuration B's preset, or 'none'")
    if kind is not None:
        group = parser.add_argument_group(f"parameters of {kind.name}")
        for info in kind.params:
            flags = sorted({f"--{info.name}", f"--{info.name.replace('_', '-')}"})
            group.add_argument(*flags, dest=f"param_{info.name}", type=_CONVERT[info.spec.kind],
                               default=None, help=f"{info.doc} ({info.allowed()}; default "
                               f"{info.default!r})")
    return parser


def describe(info: ParamInfo) -> str:
    return f"  {info.name} = {info.default!r}  ({info.allowed()})\n      {info.doc}"


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    first = build_parser(None).parse_known_args(argv)[0]
    if first.list:
        for kind in FIGURES.values():
            print(f"{kind.name}: {kind.title}")
            print("\n".join(describe(info) for info in kind.params))
        return 0
    if first.kind is None:
        build_parser(None).print_usage(sys.stderr)
        print(f"{PROG}: name a figure kind: {', '.join(FIGURES)}", file=sys.stderr)
        return 2
    if first.kind not in FIGURES:
        print(f"{PROG}: unknown figure kind {first.kind!r}; choose one of "
              f"{', '.join(FIGURES)}", file=sys.stderr)
        return 2
    kind = FIGURES[first.kind]
    args = build_parser(kind).parse_args(argv)
    table = {"kind": kind.name}
    table.update({info.name: getattr(args, f"param_{info.name}") for info in kind.params
                  if getattr(args, f"param_{info.name}") is not None})
    try:
        spec = parse_figure(table)
    except FigureParamError as exc:
        print(f"{PROG}: {exc}", file=sys.stderr)
        return 2
    if args.screenshot is not None and args.screenshot.suffix.lower() != ".png":
        print(f"{PROG}: --screenshot must name a .png file, got {str(args.screenshot)!r}",
              file=sys.stderr)
        return 2
    return show(spec, args)


def show(spec, args) -> int:
    from explorer.ui.figures.harness import FigureWindow, pipeline_results

    interactive = args.screenshot is None
    with FigureWindow(args.width, args.height, visible=interactive) as window:
        if spec.kind in USES_RESULTS:
            window.context.results = pipeline_results(window.ctx, _settings(args))
        if interactive:
            while window.frame(spec, args.figure_width):
                pass
            return 0
        window.render(spec, args.frames, args.figure_width)
        try:
            path = window.screenshot(args.screenshot)
        except OSError as exc:
            print(f"{PROG}: could not write {args.screenshot}: {exc}", file=sys.stderr)
            return 1
    print(f"{PROG}: wrote {path}")
    return 0


def _settings(args) -> list:
    from explorer.lpv.settings import Settings

    base = Settings(grid_size=16, iterations=8, rsm_size=128, width=128, height=128)
    sides = [base.with_changes(corrections=args.preset)]
    if args.compare != "none":
        sides.append(base.with_changes(corrections=args.compare))
    return sides


if __name__ == "__main__":
    raise SystemExit(main())
