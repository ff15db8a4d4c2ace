"""docs/ERRORS.md's measured tables, produced from ``lpv-explorer compare`` runs.

One data file, ``docs/errors-measured.json``, holds every table: the compare command
lines it runs (``runs``: compare's own options plus labels for extra leading columns),
the columns it shows, and the values last measured (``rows``, full precision). Each table
appears in docs/ERRORS.md between the markers

    <!-- measured: NAME (python -m explorer.commands.tables) -->
    ...
    <!-- end measured -->

and is rendered from the data file, never typed in. Tables of ``size`` "small" run in a
few seconds on llvmpipe; the test suite re-runs them (tests/truth/test_accuracy.py) and fails
when a metric leaves the band ``band.relative`` around the recorded value, so a change
in any pass's output or in the reference shows up as an accuracy change. The "large" ones
(256² px, 32³ grids, the reference over 2000–8000 VPLs) are re-measured by hand.

Usage (from the repository root)::

    python -m explorer.commands.tables --check              # fresh run of the small tables
    python -m explorer.commands.tables --check --size all   # of every table (slow)
    python -m explorer.commands.tables --measure small      # re-measure, rewrite both files
    python -m explorer.commands.tables --measure cornell-visible room-visible
    python -m explorer.commands.tables --render             # ERRORS.md from the data file

``--check`` reports every table of docs/ERRORS.md that differs from the data file and
every fresh metric outside the band; the exit status is 1 when there is any.
"""

from __future__ import annotations

import argparse
import json
import re
import shlex
import sys
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "docs" / "errors-measured.json"
DOCUMENT = ROOT / "docs" / "ERRORS.md"
SIZES = ("small", "large")
METRICS = ("relative_l2", "rmse", "flux_ratio", "flux_ratio_rgb")
FIELDS = {"preset": ("preset", "---"), "iterations": ("iterations", "---:"),
          "cascades": ("cascades", "---:"), "sh": ("SH", "---"), "region": ("region", "---")}
"""Row fields a table can show as a column: name in the data -> (header, alignment)."""
BLOCK = re.compile(r"<!-- measured: (?P<name>[\w.-]+) "
                   r"\(python -m explorer\.commands\.tables\) -->\n"
                   r"(?P<body>.*?)<!-- end measured -->", re.S)


def marker(name: str) -> str:
    return f"<!-- measured: {name} (python -m explorer.commands.tables) -->"


# ------------------------------------------------------------------------- data file


def load(path: Path = DATA) -> dict:
    from explorer.safe_files import parse_json, read_text

    data = parse_json(read_text(path, "data file"), path)
    for name, table in data["tables"].items():
        if table.get("size") not in SIZES:
            raise ValueError(f"{path}: table {name!r}: size must be one of {SIZES}, got "
                             f"{table.get('size')!r}")
        for column in table["columns"]:
            labels = [run.get("labels", {}) for run in table["runs"]]
            if column not in FIELDS and not all(column in given for given in labels):
                raise ValueError(f"{path}: table {name!r}: column {column!r} is neither a "
                                 f"row field ({', '.join(FIELDS)}) nor a label of every run")
    return data


def save(data: dict, path: Path = DATA) -> None:
    """The data file with one row per line (diffs show which values moved)."""
    lines = ["{", f'  "about": {json.dumps(data["about"], ensure_ascii=False)},',
             f'  "band": {json.dumps(data["band"], ensure_ascii=False)},', '  "tables": {']
    names = list(data["tables"])
    for index, name in enumerate(names):
        table = data["tables"][name]
        lines.append(f"    {json.dumps(name)}: {{")
        for key in (key for key in table if key not in ("runs", "rows")):
            value = json.dumps(table[key], ensure_ascii=False)
            lines.append(f"      {json.dumps(key)}: {value},")
        runs = [f"        {json.dumps(run, ensure_ascii=False)}" for run in table["runs"]]
        lines.append('      "runs": [\n' + ",\n".join(runs) + "\n      ],")
        rows = [f"        {json.dumps(row, ensure_ascii=False)}" for row in table.get("rows", [])]
        lines.append('      "rows": [' + ("\n" + ",\n".join(rows) + "\n      ]" if rows else "]"))
        lines.append("    }" + ("," if index < len(names) - 1 else ""))
    lines += ["  }", "}"]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


# ------------------------------------------------------------------------- measuring


@dataclass
class Measured:
    rows: list[dict]
    caption: str
    seconds: float


def compare_arguments(text: str) -> argparse.Namespace:
    """``lpv-explorer compare`` options (a command line without the command) as parsed by
    the command itself."""
    from explorer.commands.compare import add_arguments

    parser = argparse.ArgumentParser(prog="lpv-explorer compare", exit_on_error=False)
    add_arguments(parser)
    try:
        return parser.parse_args([*shlex.split(text), "--quiet"])
    except (argparse.ArgumentError, SystemExit) as exc:
        raise ValueError(f"bad compare options {text!r}: {exc}") from None


def measure_table(table: dict, ctx, references=None) -> Measured:
    """Run every compare command line of ``table``; rows in run order, each with the run's
    labels. ``references``: a compare.ReferenceCache shared between tables."""
    from explorer.commands import options
    from explorer.commands.compare import ReferenceCache, plan_runs, run_comparison, settings_line
    from explorer.truth.gbuffer import scene_for

    references = references if references is not None else ReferenceCache()
    started = time.perf_counter()
    rows, captions = [], []
    for run in table["runs"]:
        args = compare_arguments(run["args"])
        base = options.settings_from_args(args)
        scene = scene_for(base)
        comparison = run_comparison(args, plan_runs(args, base), ctx, scene, references)
        captions.append(settings_line(args, comparison.frame))
        for row in comparison.rows:
            stats = row.stats
            rows.append({
                "labels": run.get("labels", {}), "preset": row.preset,
                "iterations": row.iterations, "cascades": row.cascades,
                "sh": f"L{row.sh_order}", "region": row.region,
                "relative_l2": None if stats is None else stats.relative_l2,
                "rmse": None if stats is None else stats.rmse,
                "flux_ratio": None if stats is None else stats.flux_ratio,
                "flux_ratio_rgb": None if stats is None else list(stats.flux_ratio_rgb),
            })
    return Measured(rows, captions[0], time.perf_counter() - started)


def measure(data: dict, names: list[str], ctx=None) -> dict[str, Measured]:
    """Fresh measurements of the named tables, one GL context and reference cache for all."""
    from explorer.commands.compare import ReferenceCache
    from explorer.gl.context import given_or_headless

    references = ReferenceCache()
    results = {}
    with given_or_headless(ctx) as ctx:
        for name in names:
            results[name] = measure_table(data["tables"][name], ctx, references)
    return results


# ------------------------------------------------------------------------- rendering


def _cell(row: dict, column: str) -> str:
    if column in FIELDS:
        return str(row[column])
    return str(row["labels"][column])


def render_table(table: dict) -> str:
    """The markdown of one table: compare's settings line of its first run (``caption``)
    when ``settings_line`` is true, then the columns and the metrics as
    ``lpv-explorer compare`` prints them."""
    from explorer.commands.compare import METRIC_ALIGN, METRIC_HEADERS, metric_cells
    from explorer.truth.metrics import ErrorStats

    columns = table["columns"]
    headers = [FIELDS[c][0] if c in FIELDS else c for c in columns] + list(METRIC_HEADERS)
    align = [FIELDS[c][1] if c in FIELDS else "---" for c in columns] + list(METRIC_ALIGN)
    lines = []
    if table.get("settings_line", False):
        lines += [table["caption"], ""]
    lines += ["| " + " | ".join(headers) + " |", "|" + "|".join(align) + "|"]
    for row in table["rows"]:
        stats = None if row["relative_l2"] is None else ErrorStats(
            row["relative_l2"], row["rmse"], row["flux_ratio"], tuple(row["flux_ratio_rgb"]), 0)
        lines.append("| " + " | ".join([_cell(row, c) for c in columns] + metric_cells(stats))
                     + " |")
    return "\n".join(lines)


def render_document(text: str, data: dict) -> str:
    """``text`` with every measured block replaced by its table from ``data``; every table
    must have exactly one block and every block a table."""
    seen = [match["name"] for match in BLOCK.finditer(text)]
    unknown = sorted(set(seen) - set(data["tables"]))
    missing = sorted(set(data["tables"]) - set(seen))
    twice = sorted({name for name in seen if seen.count(name) > 1})
    if unknown or missing or twice:
        raise ValueError("docs/ERRORS.md and the data file disagree: "
                         + "; ".join(part for part in (
                             f"blocks of no table: {', '.join(unknown)}" if unknown else "",
                             f"tables without a block: {', '.join(missing)}" if missing else "",
                             f"blocks twice: {', '.join(twice)}" if twice else "") if part))
    return BLOCK.sub(lambda m: f"{marker(m['name'])}\n{render_table(data['tables'][m['name']])}"
                     f"\n<!-- end measured -->", text)


# ------------------------------------------------------------------------- checking


def _identity(row: dict) -> tuple:
    return (tuple(sorted(row["labels"].items())), row["preset"], row["iterations"],
            row["cascades"], row["sh"], row["region"])


def differences(name: str, recorded: list[dict], fresh: list[dict], band: float) -> list[str]:
    """One line per fresh metric outside ``band`` (relative) of the recorded one, or per
    row that is not the recorded row."""
    if [_identity(r) for r in recorded] != [_identity(r) for r in fresh]:
        return [f"{name}: the rows differ: recorded {[_identity(r) for r in recorded]}, "
                f"fresh {[_identity(r) for r in fresh]}"]
    found = []
    for old, new in zip(recorded, fresh):
        for metric in METRICS:
            a, b = old[metric], new[metric]
            if a is None or b is None:
                if a is not b:
                    found.append(f"{name} {_identity(old)}: {metric} recorded {a}, fresh {b}")
                continue
            for x, y in zip(a if isinstance(a, list) else [a], b if isinstance(b, list) else [b]):
                if abs(y - x) > band * abs(x):
                    found.append(f"{name} {_identity(old)}: {metric} recorded {x:.6g}, fresh "
                                 f"{y:.6g} ({(y - x) / x:+.2e} relative, band {band:g})")
    return found


def document_differences(text: str, data: dict) -> list[str]:
    """The tables of docs/ERRORS.md that are not what the data file renders."""
    rendered = render_document(text, data)
    if rendered == text:
        return []
    wrong = []
    fresh_blocks = {m["name"]: m["body"] for m in BLOCK.finditer(rendered)}
    for match in BLOCK.finditer(text):
        if match["body"] != fresh_blocks[match["name"]]:
            wrong.append(f"docs/ERRORS.md table {match['name']!r} is not the data file's "
                         f"(python -m explorer.commands.tables --render rewrites it)")
    return wrong


def names_of(data: dict, size: str) -> list[str]:
    return [name for name, table in data["tables"].items()
            if size == "all" or table["size"] == size]


def table_parser(prog: str, description: str, data: Path, document: Path, check: str,
                 measure: str, render: str) -> argparse.ArgumentParser:
    """The options of a command that keeps generated tables in docs/ERRORS.md: one of
    ``--check``, ``--measure SIZE_OR_NAME...`` and ``--render`` (each with its help), and
    the hidden ``--data`` / ``--document`` paths (tests point them elsewhere)."""
    parser = argparse.ArgumentParser(prog=prog, description=description)
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--check", action="store_true", help=check)
    action.add_argument("--measure", nargs="+", metavar="SIZE_OR_NAME", help=measure)
    action.add_argument("--render", action="store_true", help=render)
    parser.add_argument("--data", type=Path, default=data, help=argparse.SUPPRESS)
    parser.add_argument("--document", type=Path, default=document, help=argparse.SUPPRESS)
    return parser


def report(problems: list[str], agreed: str) -> int:
    """Print each problem, or ``agreed`` when there is none; the exit status (1: any)."""
    for line in problems:
        print(line)
    if not problems:
        print(agreed)
    return 1 if problems else 0


def main(argv: list[str] | None = None) -> int:
    parser = table_parser(
        "python -m explorer.commands.tables", __doc__.split("\n\n")[0], DATA, DOCUMENT,
        check="compare docs/ERRORS.md with the data file, and a fresh run of the tables of "
              "--size with the recorded values",
        measure="re-measure tables (small, large, all, or table names), write the values "
                "to the data file and the tables to docs/ERRORS.md",
        render="rewrite docs/ERRORS.md's tables from the data file")
    parser.add_argument("--size", choices=(*SIZES, "all"), default="small",
                        help="tables --check runs (default: small)")
    args = parser.parse_args(argv)
    try:
        from explorer.safe_files import read_text

        data = load(args.data)
        text = read_text(args.document, "document")
        if args.measure:
            names = []
            for item in args.measure:
                if item in (*SIZES, "all"):
                    names += names_of(data, item)
                elif item in data["tables"]:
                    names.append(item)
                else:
                    raise ValueError(f"--measure {item!r}: not small, large, all or a table "
                                     f"({', '.join(data['tables'])})")
            names = list(dict.fromkeys(names))
        elif args.check:
            names = names_of(data, args.size)
        else:
            names = []
        render_document(text, data)   # the blocks and tables match before anything runs
    except (OSError, ValueError, KeyError) as exc:
        print(f"python -m explorer.commands.tables: error: {exc}", file=sys.stderr)
        return 2
    if args.render:
        args.document.write_text(render_document(text, data), encoding="utf-8")
        return 0
    problems = [] if args.measure else document_differences(text, data)
    results = measure(data, names)
    for name, result in results.items():
        print(f"{name}: measured in {result.seconds:.1f} s", file=sys.stderr)
    if args.measure:
        for name, result in results.items():
            data["tables"][name]["rows"] = result.rows
            data["tables"][name]["caption"] = result.caption
        save(data, args.data)
        args.document.write_text(render_document(text, data), encoding="utf-8")
        print(f"wrote {args.data} and {args.document}")
        return 0
    band = float(data["band"]["relative"])
    for name, result in results.items():
        problems += differences(name, data["tables"][name]["rows"], result.rows, band)
    return report(problems, f"docs/ERRORS.md matches the data file; {len(names)} tables "
                            f"re-measured within {band:g} of the recorded values")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
