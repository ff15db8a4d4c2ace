"""``lpv-explorer site OUT/``: build the course as a static web site.

Every lesson (or those ``--only`` names) of the shipped course (or of the folder
``--lessons DIR`` names, a teacher's) becomes a page; each step's pictures are
rendered headlessly at ``--size`` and its numbers baked from those frames. The figures
are drawn in a hidden window (under ``xvfb-run`` when it is installed). The site needs no
server: open ``OUT/index.html``, or copy the folder to any static host.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from explorer.commands.lesson_folder import add_folder_option, folder_of
from explorer.commands.options import size_type


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("out", type=Path, metavar="OUT",
                        help="folder to write the site into (new, empty, or a site built "
                             "before, which is replaced)")
    add_folder_option(parser)
    parser.add_argument("--only", type=_keys, default=(), metavar="ID[,ID...]",
                        help="only these lessons (ids, numbers or file stems; default: all)")
    parser.add_argument("--size", type=size_type(_view_size), default=(960, 600),
                        metavar="WxH", help="pixels of each step's 3D view (default 960x600)")
    parser.add_argument("--figure-width", type=int, default=640, metavar="PX",
                        help="width of an inline figure in CSS pixels, drawn at twice that "
                             "(default 640, at least 240)")
    parser.add_argument("--png", action="store_true",
                        help="write the 3D views as PNG rather than JPEG (larger)")


def _keys(text: str) -> tuple[str, ...]:
    keys = tuple(part.strip() for part in text.split(","))
    if not all(keys):
        raise argparse.ArgumentTypeError(f"expected lesson ids separated by commas, got "
                                         f"{text!r}")
    return keys


def _view_size(width: int, height: int) -> tuple[int, int]:
    from explorer.schema import SettingError

    if not (64 <= width <= 4096 and 64 <= height <= 4096):
        raise SettingError("size", f"size must be within 64x64 and 4096x4096, got "
                                   f"{width}x{height}")
    return width, height


def main(args: argparse.Namespace) -> int:
    from explorer.commands.options import CommandError
    from explorer.site.build import SiteError, SiteOptions, build_site
    from explorer.site.figure_shots import FigureShotError

    folder = folder_of(args)
    if not 240 <= args.figure_width <= 2000:
        raise CommandError(f"--figure-width must be in [240, 2000], got {args.figure_width}")
    options = SiteOptions(out=args.out, lessons=args.only, size=args.size,
                          figure_width=args.figure_width, lessons_dir=folder,
                          image_format="png" if args.png else "jpg")
    try:
        report = build_site(options)
    except SiteError as exc:
        raise CommandError(exc) from None
    except FigureShotError as exc:
        raise CommandError(exc, 1) from None
    for line in sorted(set(report.pending)):
        print(f"site: no value: {line}")
    print(report.summary())
    print(f"open {report.out / 'index.html'}")
    return 0
