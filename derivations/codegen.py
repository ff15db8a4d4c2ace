"""Write the derived constants for the shaders and for Python.

Every registry result with a ``glsl_name`` becomes a constant in

* ``shaders/generated/constants.glsl``: ``const float NAME = value;`` printed by sympy's
  ``glsl_code`` from ``sp.N(expr, 12)`` (12 significant digits, more than a float holds);
* ``explorer/lpv/constants.py``: ``NAME = value`` with the full double precision
  (``repr(float(sp.N(expr, 30)))``).

Each constant carries its closed form (or, for a published decimal, where it was printed)
and the name of the derivation. No number is typed here: all come from ``derivations``.

Usage::

    python -m derivations.codegen           # (re)write both files
    python -m derivations.codegen --check   # exit 1 when a committed file is stale
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import sympy as sp
from sympy.printing.glsl import glsl_code

from derivations import errata
from derivations.registry import Result, all_results

REPO_ROOT = Path(__file__).resolve().parent.parent
GLSL_PATH = Path("shaders") / "generated" / "constants.glsl"
PYTHON_PATH = Path("explorer") / "lpv" / "constants.py"
GLSL_DIGITS = 12
REGENERATE = "python -m derivations.codegen"


def constants() -> list[Result]:
    """The results that become constants, in registry order."""
    return [item for item in all_results() if item.glsl_name is not None]


def closed_form(item: Result) -> str:
    """One-line description of where the value comes from, for the comments."""
    if item.module == "errata":
        row = errata.check(item.name.split(".", 1)[1])
        exact = sp.sstr(row.printed.exact) if row.printed.exact is not None else "none"
        return f"printed in {row.printed.source}; exact {exact} ({row.verdict})"
    return sp.sstr(item.expr)


def glsl_source() -> str:
    lines = [
        "#version 430 core",
        "// GENERATED FILE, do not edit. Written by `" + REGENERATE + "` from the exact",
        "// results in derivations/ (see derivations/registry.py); `" + REGENERATE
        + " --check`",
        "// and the test suite fail when it is stale. Shaders pull it in with an include",
        "// directive naming generated/constants.glsl (the program loader resolves it).",
        "// Each line: value to " + str(GLSL_DIGITS)
        + " significant digits  // closed form  [derivation]",
        "",
        "#ifndef LPV_GENERATED_CONSTANTS",
        "#define LPV_GENERATED_CONSTANTS",
        "",
    ]
    for item in constants():
        code = glsl_code(sp.N(item.expr, GLSL_DIGITS), assign_to=f"const float {item.glsl_name}")
        lines.append(f"{code}  // {closed_form(item)}  [{item.name}]")
    lines += ["", "#endif  // LPV_GENERATED_CONSTANTS", ""]
    return "\n".join(lines)


def python_source() -> str:
    lines = [
        '"""Derived constants (GENERATED FILE, do not edit).',
        "",
        f"Written by ``{REGENERATE}`` from the exact results in ``derivations/``;",
        f"``{REGENERATE} --check`` and the test suite fail when it is stale. The",
        "same names and values as ``shaders/generated/constants.glsl``, in full double",
        "precision. The comment above each constant gives its closed form and derivation.",
        '"""',
        "",
    ]
    for item in constants():
        comment = f"# {closed_form(item)}  [{item.name}]"
        if len(comment) > 99:  # keep the generated module within the line-length limit
            comment = f"# {closed_form(item)}\n#   [{item.name}]"
        lines.append(comment)
        lines.append(f"{item.glsl_name} = {float(sp.N(item.expr, 30))!r}")
    lines += ["", "# constant name -> the derivation it comes from (derivations.registry.get)",
              "DERIVATION: dict[str, str] = {"]
    lines += [f'    "{item.glsl_name}": "{item.name}",' for item in constants()]
    lines += ["}", ""]
    return "\n".join(lines)


def outputs() -> dict[Path, str]:
    """Relative path -> the text it must hold."""
    return {GLSL_PATH: glsl_source(), PYTHON_PATH: python_source()}


def stale_files(root: Path = REPO_ROOT) -> list[Path]:
    """The generated files under ``root`` whose content differs from a fresh run."""
    stale = []
    for relative, text in outputs().items():
        path = root / relative
        if not path.is_file() or path.read_text(encoding="utf-8") != text:
            stale.append(relative)
    return stale


def write(root: Path = REPO_ROOT) -> list[Path]:
    """Write the generated files under ``root``; returns those that changed."""
    changed = []
    for relative, text in outputs().items():
        path = root / relative
        if not path.is_file() or path.read_text(encoding="utf-8") != text:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text, encoding="utf-8")
            changed.append(relative)
    return changed


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m derivations.codegen",
                                     description="Generate the derived constants.")
    parser.add_argument("--check", action="store_true",
                        help="do not write; exit 1 when a generated file is stale")
    parser.add_argument("--root", type=Path, default=REPO_ROOT,
                        help="repository root holding shaders/ and explorer/ (default: this "
                             "checkout)")
    args = parser.parse_args(argv)
    if args.check:
        stale = stale_files(args.root)
        for path in stale:
            print(f"stale: {path} (run `{REGENERATE}`)", file=sys.stderr)
        if not stale:
            print(f"{len(constants())} constants up to date")
        return 1 if stale else 0
    changed = write(args.root)
    for path in changed:
        print(f"wrote {path}")
    if not changed:
        print(f"{len(constants())} constants already up to date")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
