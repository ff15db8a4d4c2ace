"""``lpv-explorer constants``: every exact result the renderer relies on.

Each entry shows the registry name (``<module>.<item>``), the closed form (plain and
LaTeX), the value to 20 significant digits (``sp.N(expr, 20)``; formulas and vectors have
none), the GLSL constant it feeds, and a one-line statement. ``--name`` selects one entry
by registry name or by GLSL constant name; ``--json`` prints machine-readable output (a
list, or one object with ``--name``). ``--errata`` prints the check of every number the
seed documents print, as a markdown table. ``--format glsl|hlsl|cpp|js|json`` prints the
porting sheet (derivations/porting.py): the exact constants, the per-face weights Δω/π and
the SH and grid conventions, ready to paste into an engine; ``--prefix`` (default ``LPV_``)
starts every GLSL, HLSL and C/C++ name and ``--namespace`` (default ``lpv``) holds the C++
ones.
"""

from __future__ import annotations

import argparse
import json

VALUE_DIGITS = 20


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true",
                        help="print JSON (values as strings, to keep all 20 digits)")
    parser.add_argument("--name", metavar="NAME",
                        help="only this result: a registry name such as "
                             "solid_angles.front_face, or a GLSL name such as SH_C1")
    parser.add_argument("--errata", action="store_true",
                        help="print the table of published numbers vs exact values (markdown)")
    parser.add_argument("--format", choices=("glsl", "hlsl", "cpp", "js", "json"), default=None,
                        dest="sheet_format",
                        help="print the porting sheet in this language: the exact constants, "
                             "the per-face weights and the SH conventions (cpp: one header "
                             "valid as C89/C99/C11 and C++11 on, each constant as double "
                             "LPV_NAME and float LPV_NAME_F; js: an ES module)")
    parser.add_argument("--prefix", metavar="TEXT", default=None,
                        help="with --format glsl, hlsl or cpp: what every name starts with, "
                             "so that none meets an engine's own PI or SH_C0 (default LPV_; "
                             "'' for the bare names)")
    parser.add_argument("--namespace", metavar="NAME", default=None,
                        help="with --format cpp: the C++ namespace of the constants (default "
                             "lpv: lpv::LPV_PI; '' for none); C sees the same names at file "
                             "scope")


def entry(item) -> dict[str, object]:
    """One result as plain data (what ``--json`` prints)."""
    import sympy as sp

    value = str(sp.N(item.expr, VALUE_DIGITS)) if item.is_number else None
    return {
        "name": item.name,
        "module": item.module,
        "statement": item.statement,
        "closed_form": sp.sstr(item.expr),
        "latex": sp.latex(item.expr),
        "value": value,
        "glsl_name": item.glsl_name,
    }


def _find(name: str):
    """The result named by registry or GLSL name. The generated tables know every name, so
    an unknown one is refused at once and a known one derives only its own module."""
    from derivations.registry import get_one
    from explorer import derived
    from explorer.lpv.constants import DERIVATION

    name = DERIVATION.get(name, name)
    derived.get(name)  # KeyError naming the closest matches, without sympy
    return get_one(name)


def _print_text(entries: list[dict[str, object]]) -> None:
    for data in entries:
        head = str(data["name"])
        if data["value"] is not None:
            head += f" = {data['value']}"
        if data["glsl_name"]:
            head += f"   [{data['glsl_name']}]"
        print(head)
        print(f"    closed form: {data['closed_form']}")
        print(f"    LaTeX:       {data['latex']}")
        print(f"    {data['statement']}")


def _sheet(args: argparse.Namespace) -> str:
    """The porting sheet ``--format`` asks for, after checking ``--prefix``/``--namespace``."""
    from derivations import porting
    from explorer.commands.options import CommandError

    fmt = args.sheet_format
    if args.prefix is not None and fmt not in ("glsl", "hlsl", "cpp"):
        raise CommandError("--prefix only acts with --format glsl, hlsl or cpp (a JS module "
                           "and JSON keep the bare names)")
    if args.namespace is not None and fmt != "cpp":
        raise CommandError("--namespace only acts with --format cpp")
    prefix = porting.DEFAULT_PREFIX if args.prefix is None else args.prefix
    namespace = porting.DEFAULT_NAMESPACE if args.namespace is None else args.namespace
    try:
        return porting.sheet(fmt, prefix, namespace)
    except ValueError as exc:
        raise CommandError(f"--prefix/--namespace: {exc}") from None


def main(args: argparse.Namespace) -> int:
    from derivations.registry import all_results

    if args.sheet_format is not None or args.prefix is not None or args.namespace is not None:
        print(_sheet(args), end="")
        return 0
    if args.errata:
        from derivations import errata

        print(errata.markdown(), end="")
        return 0
    if args.name is not None:
        try:
            selected = [_find(args.name)]
        except KeyError as exc:
            from explorer.commands.options import CommandError

            raise CommandError(exc.args[0]) from None
    else:
        selected = all_results()
    entries = [entry(item) for item in selected]
    if args.json:
        payload = entries[0] if args.name is not None else entries
        print(json.dumps(payload, indent=2, ensure_ascii=False))
    else:
        _print_text(entries)
    return 0
