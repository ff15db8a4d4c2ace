"""``lpv-explorer bench --gpu-report OUT.json``: every figure BENCHMARKS.md states, measured
in one go on the device at hand (meant for a GPU, within about five minutes) and written
as one JSON and one table.

Parts, each a ``bench`` run of its own in a child process (one that fails or runs past its
time is recorded as such and the others still run):

* ``passes``: milliseconds per pass (timer queries on a GPU) and the propagation's GB/s
  (with ``--peak-gbs`` its share of the device's peak), at :data:`GPU_SIZES` on a GPU,
  :data:`SOFTWARE_SIZES` on a software renderer (so that the run still fits);
* ``variants``: the same at 32³ × 8 with every variant row (audit, damping, bounces,
  fog, glossy, the minimal kernel's ``×base``);
* ``overhead``: ``bench --overhead`` (GL calls, finishes, synchronous read-backs, Python
  milliseconds per kind of frame, and the default window frame's target);
* ``interactive``: ``bench --interactive`` (the window's launch, orbit, toggles, longest
  frame), under ``xvfb-run`` when there is no display.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from explorer.commands import options

GPU_SIZES = ("--grids", "16,32,64,128", "--iterations", "8,16,32", "--size", "960x540",
             "--variants", "none", "--repeat", "5")
SOFTWARE_SIZES = ("--grids", "16,32", "--iterations", "8", "--size", "256x256",
                  "--rsm-size", "128", "--variants", "none", "--repeat", "1")
VARIANT_ROWS = ("--grids", "32", "--iterations", "8", "--repeat", "3")
SOFTWARE_VARIANT_ROWS = ("--grids", "16", "--iterations", "8", "--size", "256x256",
                         "--rsm-size", "128", "--repeat", "1",
                         "--variants", "audit,audit-flux,damping,glossy")
PART_TIMEOUT_S = {"passes": 120, "variants": 90, "overhead": 60, "interactive": 240}
"""The longest each part may run (the whole report stays within about five minutes on a
GPU; on llvmpipe the smaller sizes keep it there)."""
TABLE_KEYS = (
    ("overhead", "full", "python ms of a full frame", "outside_gl_ms"),
    ("overhead", "camera", "python ms of a camera frame", "outside_gl_ms"),
    ("overhead", "display", "python ms of a display frame", "outside_gl_ms"),
    ("overhead", "window", "finishes in a window frame (worst)", ("max", "finishes")),
    ("overhead", "window", "synchronous read-backs in a window frame (worst)",
     ("max", "read-backs")),
)


def run_gpu_report(args: argparse.Namespace, out: Path) -> int:
    """Run every part (module docstring), write ``out`` and print the table; 0 when every
    part ran, 1 otherwise."""
    from explorer.gl.context import create_headless_context, probe, release_headless_context
    from explorer.lpv.timing import is_software_renderer

    ctx = create_headless_context()
    try:
        caps, software = probe(ctx), is_software_renderer(ctx)
    finally:
        release_headless_context(ctx)
    began = time.monotonic()
    peak = () if args.peak_gbs is None else ("--peak-gbs", str(args.peak_gbs))
    parts: dict[str, dict] = {}
    with tempfile.TemporaryDirectory(prefix="lpv-gpu-report-") as folder:
        plans = {
            "passes": [*(SOFTWARE_SIZES if software else GPU_SIZES), *peak],
            "variants": [*(SOFTWARE_VARIANT_ROWS if software else VARIANT_ROWS), *peak],
            "overhead": ["--overhead"],
            "interactive": ["--interactive", "--frames", "30" if software else "60"],
        }
        for name, extra in plans.items():
            parts[name] = _part(name, extra, Path(folder))
            print(f"gpu report: {name} {parts[name]['status']} in "
                  f"{parts[name]['seconds']:.0f} s", flush=True)
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    report = {"device": caps.renderer, "version": caps.version, "date": when,
              "software_renderer": software, "peak_gbs": args.peak_gbs,
              "seconds": time.monotonic() - began, "parts": parts}
    out.write_text(json.dumps(report, indent=2))
    print(format_report(report))
    print(f"wrote {out}")
    return 0 if all(part["status"] in ("ok", "target missed") for part in parts.values()) \
        else 1


def _part(name: str, extra: list[str], folder: Path) -> dict:
    """One ``bench`` run in a child process with ``--json``: its status, seconds, the
    JSON it wrote and the end of what it printed."""
    json_path = folder / f"{name}.json"
    command = [sys.executable, "-m", "explorer", "bench", *extra, "--json", str(json_path)]
    if name == "interactive" and not os.environ.get("DISPLAY"):
        xvfb = shutil.which("xvfb-run")
        if xvfb is None:
            return {"status": "skipped: no display and no xvfb-run", "seconds": 0.0}
        command = [xvfb, "-a", "-s", "-screen 0 1700x1100x24", *command]
    start = time.monotonic()
    try:
        done = subprocess.run(command, capture_output=True, text=True,
                              timeout=PART_TIMEOUT_S[name])
    except subprocess.TimeoutExpired:
        return {"status": f"timed out after {PART_TIMEOUT_S[name]} s",
                "seconds": time.monotonic() - start}
    seconds = time.monotonic() - start
    data = json.loads(json_path.read_text()) if json_path.is_file() else None
    # bench --overhead exits 1 when the window frame misses its target: a figure, not a
    # failure of the part
    missed = name == "overhead" and done.returncode == 1 and data is not None
    status = "ok" if done.returncode == 0 else "target missed" if missed else \
        f"failed (exit {done.returncode})"
    return {"status": status, "seconds": seconds, "command": command[command.index("-m"):],
            "data": data, "printed": done.stdout[-6000:],
            "errors": done.stderr[-2000:] if done.returncode else ""}


def format_report(report: dict) -> str:
    """The report's headline figures as a Markdown table (the JSON holds them all)."""
    lines = [f"GPU report: {report['device']} ({report['version']}), {report['date']}, "
             f"{report['seconds']:.0f} s", "", "| figure | value |", "|---|---:|"]
    for part in ("passes", "variants"):
        for row in (report["parts"][part].get("data") or {}).get("rows", []):
            label = f"{row['variant']}, {row['grid']}³ × {row['iterations']}"
            timing = ", ".join(sorted(set(row["methods"].values()))) or "-"
            lines.append(f"| frame ms ({timing}), {label} | {row['frame_ms']:.2f} |")
            if row.get("propagation_gbs") is not None:
                share = "" if not report["peak_gbs"] else \
                    f" ({100 * row['propagation_gbs'] / report['peak_gbs']:.1f} % of peak)"
                lines.append(f"| propagation GB/s, {label} | {row['propagation_gbs']:.2f}"
                             f"{share} |")
            if row.get("kernel_ratio") is not None:
                lines.append(f"| ×base (the minimal kernel), {label} | "
                             f"{row['kernel_ratio']:.2f} |")
    overhead = {row["frame"]: row for row in
                (report["parts"]["overhead"].get("data") or {}).get("overhead", [])}
    for part, frame, label, key in TABLE_KEYS:
        row = overhead.get(frame) if part == "overhead" else None
        if row is None:
            continue
        value = row[key[0]][key[1]] if isinstance(key, tuple) else row[key]
        lines.append(f"| {label} | {float(value):.2f} |")
    interactive = report["parts"]["interactive"].get("data") or {}
    from explorer.commands.interactive_bench import KEYS

    for key, label, unit, fmt in KEYS:
        if interactive.get(key) is not None:
            lines.append(f"| {label} ({unit}) | {format(interactive[key], fmt)} |")
    for name, part in report["parts"].items():
        lines.append(f"| part {name} | {part['status']}, {part['seconds']:.0f} s |")
    return "\n".join(lines)


def main(args: argparse.Namespace) -> int:
    with options.Outputs("--gpu-report") as outputs:
        out = outputs.file(args.gpu_report, (".json",))
        return run_gpu_report(args, out)
