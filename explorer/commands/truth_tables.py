"""docs/ERRORS.md's accuracy tables against physics: every LPV variant against Mitsuba 3.

One data file, ``docs/errors-physics.json``, holds every table: the scene and its sizes
(``base``: Settings fields), Mitsuba's samples per pixel and variant, the variants (a
label and the Settings changes of each, e.g. ``{"geometry_volume": "one-sided"}`` or
``{"corrections": {"ping_pong": false}}``) and the values last measured (``rows``, full
precision). Each table appears in docs/ERRORS.md between

    <!-- physics: NAME (python -m explorer.commands.truth_tables) -->
    ...
    <!-- end physics -->

For each table, one Mitsuba render set of the scene (direct, one bounce, all bounces;
explorer/truth/mitsuba_render.py) and the project's one-bounce reference (the VPLs the
LPV injected, gathered with shadow rays) at the same pixels; then each variant's LPV
frame against all three. The reference's own row against Mitsuba shows what the RSM's
sampling, the 1/r² clamp and the shadow maps cost; the rest of an LPV row's error is the
grid's. Mitsuba's noise (half the distance between two seeds' images) is in each
caption. Mitsuba's ``scalar_rgb`` variant with fixed seeds and the LPV on Mesa llvmpipe
give the same values on every run, so ``--check`` holds a fresh measurement of the
``small`` tables to the digits the page prints (tests/truth/test_truth_tables.py).

Usage (from the repository root; needs ``pip install 'lpv-explorer[truth]'``)::

    python -m explorer.commands.truth_tables --check             # the small tables, fresh
    python -m explorer.commands.truth_tables --measure all       # every table (minutes)
    python -m explorer.commands.truth_tables --measure cornell   # one table
    python -m explorer.commands.truth_tables --render            # ERRORS.md from the data
"""

from __future__ import annotations

import json
import re
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "docs" / "errors-physics.json"
DOCUMENT = ROOT / "docs" / "ERRORS.md"
SIZES = ("small", "large")
BLOCK = re.compile(r"<!-- physics: (?P<name>[\w.-]+) "
                   r"\(python -m explorer\.commands\.truth_tables\) -->\n"
                   r"(?P<body>.*?)<!-- end physics -->", re.S)
TRUTHS = ("reference", "one-bounce", "multi-bounce")
"""What each LPV row is held against: the project's reference, Mitsuba's one bounce and
Mitsuba's every bounce."""
HEADERS = ("variant", "vs ref.: rel. L2", "flux", "vs Mitsuba 1 bounce: rel. L2", "flux",
           "r, g, b", "vs Mitsuba all bounces: rel. L2", "flux", "r, g, b")
ALIGN = ("---", "---:", "---:", "---:", "---:", "---", "---:", "---:", "---")


def marker(name: str) -> str:
    return f"<!-- physics: {name} (python -m explorer.commands.truth_tables) -->"


def load(path: Path = DATA) -> dict:
    from explorer.safe_files import parse_json, read_text

    data = parse_json(read_text(path, "data file"), path)
    for name, table in data["tables"].items():
        if table.get("size") not in SIZES:
            raise ValueError(f"{path}: table {name!r}: size must be one of {SIZES}")
        labels = [variant["label"] for variant in table["variants"]]
        if len(set(labels)) != len(labels):
            raise ValueError(f"{path}: table {name!r}: variant labels must be unique")
    return data


def save(data: dict, path: Path = DATA) -> None:
    """The data file with one variant and one row per line."""
    lines = ["{", f'  "about": {json.dumps(data["about"], ensure_ascii=False)},',
             '  "tables": {']
    names = list(data["tables"])
    for index, name in enumerate(names):
        table = data["tables"][name]
        lines.append(f"    {json.dumps(name)}: {{")
        for key in (key for key in table if key not in ("variants", "rows")):
            lines.append(f"      {json.dumps(key)}: "
                         f"{json.dumps(table[key], ensure_ascii=False)},")
        variants = [f"        {json.dumps(v, ensure_ascii=False)}" for v in table["variants"]]
        lines.append('      "variants": [\n' + ",\n".join(variants) + "\n      ],")
        rows = [f"        {json.dumps(row, ensure_ascii=False)}" for row in table.get("rows", [])]
        lines.append('      "rows": [' + ("\n" + ",\n".join(rows) + "\n      ]" if rows else "]"))
        lines.append("    }" + ("," if index < len(names) - 1 else ""))
    lines += ["  }", "}"]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


# ------------------------------------------------------------------------- measuring

def _metrics(image, truth, mask) -> dict:
    from explorer.truth.metrics import error_stats

    image = np.asarray(image, np.float64)
    stats = error_stats(image, truth, mask)
    return {"relative_l2": stats.relative_l2, "flux_ratio": stats.flux_ratio,
            "flux_ratio_rgb": list(stats.flux_ratio_rgb),
            "mean": float(image[mask].mean()), "truth_mean": float(truth[mask].mean())}


def measure_table(table: dict, ctx) -> dict:
    """Every variant of ``table`` against the reference and Mitsuba: the rows, the
    caption and the seconds it took."""
    from explorer.lpv.pipeline import Pipeline
    from explorer.lpv.settings import Settings
    from explorer.truth.gbuffer import scene_for
    from explorer.truth.mitsuba_render import render_truth
    from explorer.truth.render import reference_for_frame

    started = time.perf_counter()
    base = Settings().with_changes(**table["base"])
    scene = scene_for(base)
    truth = render_truth(scene, base.width, base.height, table["spp"], table["variant"])
    min_distance = None
    masks = None
    references: list[tuple[object, tuple]] = []
    rows = []
    with Pipeline(base, ctx) as pipeline:
        for variant in table["variants"]:
            settings = base.with_changes(**variant["changes"])
            frame = pipeline.run(settings)
            if min_distance is None:     # half a cell of the base grid, for every variant
                min_distance = 0.5 * frame.grid_spec.cell_size
            cached = next((value for vpls, value in references
                           if _same_vpls(vpls, frame.vpls)), None)
            if cached is None:
                cached = reference_for_frame(frame, True, min_distance, ctx=ctx, scene=scene)
                references.append((frame.vpls, cached))
            reference, gbuffer = cached
            valid = gbuffer.valid
            if masks is None:
                masks = _region_masks(table, scene, base, valid, ctx)
            lpv = np.asarray(frame.indirect, np.float64)[..., :3]
            for region, mask in masks.items():
                suffix = "" if region == "image" else f" · {region}"
                if not any(row["variant"] == f"reference (project){suffix}" for row in rows):
                    rows.append({"variant": f"reference (project){suffix}", "reference": None,
                                 **{name: _metrics(reference, truth[name].image, mask)
                                    for name in TRUTHS[1:]}})
                rows.append({"variant": variant["label"] + suffix,
                             **{name: _metrics(lpv, reference if name == "reference"
                                               else truth[name].image, mask)
                                for name in TRUTHS}})
    direct = _metrics(frame.direct[..., :3], truth["direct"].image, valid)
    caption = (f"scene `{base.scene}`, {base.width}×{base.height} px, RSM {base.rsm_size}², "
               f"grid {base.grid_size}³, {base.iterations} iterations unless the variant "
               f"says; Mitsuba `{truth.variant}` {truth.spp} spp × 2 seeds, noise (rel. L2, "
               f"flux) one bounce {truth['one-bounce'].noise_l2:.3f}, "
               f"{truth['one-bounce'].noise_flux:.4f}, all bounces "
               f"{truth['multi-bounce'].noise_l2:.3f}, "
               f"{truth['multi-bounce'].noise_flux:.4f}; the explorer's direct light / "
               f"Mitsuba's: flux {direct['flux_ratio']:.3f}")
    return {"rows": rows, "caption": caption, "seconds": time.perf_counter() - started}


def _region_masks(table: dict, scene, settings, valid, ctx) -> dict[str, np.ndarray]:
    """The whole image and each surface of ``table["regions"]`` (explorer/scene/parts.py)
    among the pixels that see a surface."""
    masks = {"image": valid}
    names = table.get("regions", [])
    if names:
        from explorer.truth.surface_masks import render_triangle_ids, surface_masks

        ids = render_triangle_ids(ctx, scene, settings.width, settings.height)
        masks.update({name: mask & valid
                      for name, mask in surface_masks(scene, ids, names).items()})
    return masks


def _same_vpls(a, b) -> bool:
    return (a.count == b.count and np.array_equal(np.asarray(a.positions),
                                                  np.asarray(b.positions))
            and np.array_equal(np.asarray(a.flux), np.asarray(b.flux)))


def measure(data: dict, names: list[str], ctx=None) -> dict[str, dict]:
    from explorer.gl.context import given_or_headless

    with given_or_headless(ctx) as ctx:
        return {name: measure_table(data["tables"][name], ctx) for name in names}


# ------------------------------------------------------------------------- rendering

def _number(value: float) -> str:
    """Three decimals; three significant digits from 1000 on (in-place propagation
    overflows by orders of magnitude)."""
    return f"{value:.3f}" if abs(value) < 1000 else f"{value:.3g}"


def _cells(metrics: dict | None, rgb: bool) -> list[str]:
    if metrics is None:
        return ["–", "–"] + (["–"] if rgb else [])
    if metrics.get("truth_mean") == 0.0 and metrics["mean"] > 0.0:
        # nothing arrives in truth (the two rooms' dark side): a ratio is infinite, the
        # light that leaked is the number
        return [f"leak: mean {metrics['mean']:.3g}", "–"] + (["–"] if rgb else [])
    cells = [_number(metrics["relative_l2"]), _number(metrics["flux_ratio"])]
    if rgb:
        cells.append(", ".join(_number(v) for v in metrics["flux_ratio_rgb"]))
    return cells


def render_table(table: dict) -> str:
    lines = [table.get("caption", ""), "", "| " + " | ".join(HEADERS) + " |",
             "|" + "|".join(ALIGN) + "|"]
    for row in table.get("rows", []):
        cells = [row["variant"], *_cells(row["reference"], False),
                 *_cells(row["one-bounce"], True), *_cells(row["multi-bounce"], True)]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def render_document(text: str, data: dict) -> str:
    seen = [match["name"] for match in BLOCK.finditer(text)]
    missing = sorted(set(data["tables"]) - set(seen))
    unknown = sorted(set(seen) - set(data["tables"]))
    if missing or unknown or len(seen) != len(set(seen)):
        raise ValueError(f"docs/ERRORS.md and {DATA.name} disagree: tables without a block "
                         f"{missing}, blocks of no table {unknown}, blocks {seen}")
    return BLOCK.sub(lambda m: f"{marker(m['name'])}\n{render_table(data['tables'][m['name']])}"
                     f"\n<!-- end physics -->", text)


def printed_differences(name: str, recorded: dict, fresh: dict) -> list[str]:
    """The cells a fresh measurement prints otherwise than the recorded one."""
    old, new = render_table(recorded).splitlines(), render_table(fresh).splitlines()
    if len(old) != len(new):
        return [f"{name}: {len(new)} lines measured, {len(old)} recorded"]
    return [f"{name}: recorded {a!r}\n{' ' * len(name)}  measured {b!r}"
            for a, b in zip(old, new) if a != b]


def main(argv: list[str] | None = None) -> int:
    from explorer.commands.tables import report, table_parser

    parser = table_parser(
        "python -m explorer.commands.truth_tables", __doc__.split("\n\n")[0], DATA,
        DOCUMENT,
        check="docs/ERRORS.md is the data file, and a fresh run of the small tables prints "
              "the recorded digits",
        measure="re-measure tables (small, large, all or names) and rewrite the data file "
                "and docs/ERRORS.md",
        render="rewrite docs/ERRORS.md's physics tables from the data file")
    args = parser.parse_args(argv)
    prog = parser.prog
    try:
        from explorer.safe_files import read_text

        data = load(args.data)
        text = read_text(args.document, "document")
        render_document(text, data)
        names = []
        for item in args.measure or (["small"] if args.check else []):
            if item in (*SIZES, "all"):
                names += [n for n, t in data["tables"].items()
                          if item == "all" or t["size"] == item]
            elif item in data["tables"]:
                names.append(item)
            else:
                raise ValueError(f"--measure {item!r}: not small, large, all or a table "
                                 f"({', '.join(data['tables'])})")
    except (OSError, ValueError, KeyError) as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return 2
    if args.render:
        args.document.write_text(render_document(text, data), encoding="utf-8")
        return 0
    from explorer.truth.mitsuba_render import MitsubaUnavailable

    try:
        results = measure(data, list(dict.fromkeys(names)))
    except MitsubaUnavailable as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return 1
    for name, result in results.items():
        print(f"{name}: measured in {result['seconds']:.1f} s", file=sys.stderr)
    if args.measure:
        for name, result in results.items():
            data["tables"][name]["rows"] = result["rows"]
            data["tables"][name]["caption"] = result["caption"]
        save(data, args.data)
        args.document.write_text(render_document(text, data), encoding="utf-8")
        print(f"wrote {args.data.name} and {args.document.name}")
        return 0
    problems = [] if render_document(text, data) == text else [
        "docs/ERRORS.md's physics tables are not the data file's (--render rewrites them)"]
    for name, result in results.items():
        problems += printed_differences(name, data["tables"][name], result)
    return report(problems, f"docs/ERRORS.md matches the data file; {len(results)} tables "
                            f"re-measured to their printed digits")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
