"""``lpv-explorer bench --interactive`` and ``--soak MINUTES``: the real window driven
by :mod:`explorer.commands.interaction` in a child process (so that launch is measured
from a fresh interpreter, and ``--root`` can point at another checkout), its figures
printed and, with ``--json``, written under the keys of :data:`KEYS`."""

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

from explorer.commands import interaction, options, units_driver

KEYS = (("launch_to_first_lit_frame_s", "launch to the first lit frame", "s", ".2f"),
        ("launch_to_converged_s", "launch to the converged frame", "s", ".2f"),
        ("idle_frame_ms", "a redraw with nothing new", "ms", ".1f"),
        ("window_drawing_ms", "the window's own drawing (a redraw)", "ms", ".1f"),
        ("window_drawing_panels_ms", "  of which the panels built", "ms", ".1f"),
        ("window_drawing_render_and_swap_ms", "  of which rendered and swapped", "ms", ".1f"),
        ("window_drawing_render_ms", "  of which imgui's lists rendered", "ms", ".1f"),
        ("window_drawing_swap_ms", "  of which swapped", "ms", ".1f"),
        ("idle_painted_percent", "  of the window repainted (partial painting)", "%", ".0f"),
        ("idle_cpu_percent", "CPU while idle", "%", ".1f"),
        ("idle_frames_drawn_per_s", "frames drawn per second while idle", "/s", ".1f"),
        ("orbit_fps", "orbit: new pictures per second", "fps", ".1f"),
        ("orbit_window_fps", "orbit: frames per second", "fps", ".1f"),
        ("orbit_first_update_ms", "orbit: first moved picture", "ms", ".0f"),
        ("orbit_refine_ms", "orbit released to the full-size frame", "ms", ".0f"),
        ("display_change_ms", "display-only change, over a redraw", "ms", ".1f"),
        ("display_change_frame_ms", "display-only change, its whole frame", "ms", ".1f"),
        ("display_change_frame_cpu_ms", "  its CPU (all threads)", "ms", ".1f"),
        ("display_change_update_ms", "  of which the update (events, pipelines)", "ms", ".1f"),
        ("display_change_panels_ms", "  of which the panels built", "ms", ".1f"),
        ("display_change_render_ms", "  of which imgui's lists rendered", "ms", ".1f"),
        ("display_change_swap_ms", "  of which swapped", "ms", ".1f"),
        ("display_change_painted_percent", "  of the window repainted", "%", ".0f"),
        ("display_pass_ms", "display-only change, the view pass alone", "ms", ".2f"),
        ("toggle_first_update_ms", "toggle to the first updated picture (median)", "ms",
         ".0f"),
        ("toggle_converged_ms", "toggle to the converged picture (median)", "ms", ".0f"),
        ("iterations8_toggle_first_update_ms", "32³×8 toggle: first updated picture (median)",
         "ms", ".0f"),
        ("iterations8_slowest_first_update_ms", "32³×8 toggle: slowest first picture", "ms",
         ".0f"),
        ("iterations8_toggle_converged_ms", "32³×8 toggle: converged (median)", "ms", ".0f"),
        ("slider_first_update_ms", "slider drag: first updated picture", "ms", ".0f"),
        ("slider_converged_ms", "slider drag: converged after its last frame", "ms", ".0f"),
        ("slider_longest_frame_ms", "slider drag: longest frame", "ms", ".0f"),
        ("object_first_update_ms", "object move: first updated picture", "ms", ".0f"),
        ("object_converged_ms", "object move: converged after its last frame", "ms", ".0f"),
        ("object_longest_frame_ms", "object move: longest frame", "ms", ".0f"),
        ("grid64_first_update_ms", "grid 64³: first updated picture", "ms", ".0f"),
        ("grid64_converged_ms", "grid 64³: converged", "ms", ".0f"),
        ("grid64_toggle_first_update_ms", "64³ toggle: first updated picture", "ms", ".0f"),
        ("grid64_toggle_converged_ms", "64³ toggle: converged", "ms", ".0f"),
        ("longest_blocked_frame_ms", "longest frame", "ms", ".0f"),
        ("longest_interacting_frame_ms", "longest frame within 0.15 s of an input", "ms",
         ".0f"),
        ("longest_frame_cpu_ms", "most CPU a frame took (all threads)", "ms", ".0f"),
        ("longest_interacting_frame_cpu_ms", "  within 0.15 s of an input", "ms", ".0f"),
        ("longest_panels_ms", "longest building of the panels", "ms", ".1f"))


def run_window_bench(args: argparse.Namespace) -> int:
    if not os.environ.get("DISPLAY"):
        raise options.CommandError("the window bench needs a display: run it under "
                                   "xvfb-run -a -s '-screen 0 1700x1100x24'")
    root = (args.root or Path(__file__).resolve().parents[2]).resolve()
    if not (root / "explorer" / "ui" / "app.py").is_file():
        raise options.CommandError(f"--root {root}: no explorer/ui/app.py there")
    if args.soak_steps is not None:
        try:
            interaction.selected_steps(args.soak_steps)
        except ValueError as exc:
            raise options.CommandError(str(exc)) from None
    with options.Outputs("--json") as outputs:
        json_path = outputs.file(args.json, (".json",)) if args.json is not None else None
        figures = _child(root, args)
        when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        figures.update(date=when, root=str(root))
        print(f"window of {root} on {figures.get('renderer') or 'this GL'}; {when}")
        if args.soak is not None:
            _print_soak(figures)
        else:
            _print_session(figures)
        if json_path is not None:
            payload = json.dumps(figures, indent=2)
            outputs.write(json_path, lambda p: p.write_text(payload))
            print(f"wrote {json_path}")
    return 1 if args.soak is not None and (figures["growth"]
                                            or figures.get("over_budget")) else 0


def run_units_bench(args: argparse.Namespace) -> int:
    """``bench --units`` (explorer/commands/units_driver.py), in a child process driving
    ``--root``'s pipeline."""
    root = (args.root or Path(__file__).resolve().parents[2]).resolve()
    if not (root / "explorer" / "lpv" / "pipeline.py").is_file():
        raise options.CommandError(f"--root {root}: no explorer/lpv/pipeline.py there")
    with options.Outputs("--json") as outputs:
        json_path = outputs.file(args.json, (".json",)) if args.json is not None else None
        with tempfile.TemporaryDirectory(prefix="lpv-bench-") as folder:
            out = Path(folder) / "units.json"
            driver = Path(folder) / "lpv_units_driver.py"
            shutil.copyfile(units_driver.__file__, driver)
            command = [sys.executable, str(driver), "--json", str(out),
                       "--repeat", str(args.repeat or 2)]
            proc = subprocess.run(command, cwd=root, env=dict(os.environ, PYTHONPATH=str(root)),
                                  capture_output=True, text=True)
            if proc.returncode != 0 or not out.is_file():
                tail = proc.stderr.strip().splitlines()[-5:]
                raise options.CommandError("the unit bench failed: " + " | ".join(tail), 1)
            figures = json.loads(out.read_text())
        when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
        figures.update(date=when, root=str(root), load_average=load)
        print(f"pipeline of {root} on {figures.get('renderer') or 'this GL'}; {when}; load "
              f"average {load:.1f}; ms, median of {figures['repeat']} runs")
        print(units_driver.format_units(figures))
        if json_path is not None:
            payload = json.dumps(figures, indent=2)
            outputs.write(json_path, lambda p: p.write_text(payload))
            print(f"wrote {json_path}")
    return 0


def _child(root: Path, args: argparse.Namespace) -> dict:
    with tempfile.TemporaryDirectory(prefix="lpv-bench-") as folder:
        out = Path(folder) / "figures.json"
        # a copy of the driver alone in its folder: run as a script, its folder comes
        # first on sys.path, and explorer/commands/ holds names like "constants"
        driver = Path(folder) / "lpv_interaction_driver.py"
        shutil.copyfile(interaction.__file__, driver)
        command = [sys.executable, str(driver),
                   "--json", str(out), "--frames", str(args.frames)]
        if args.soak is not None:
            command += ["--soak", str(args.soak)]
        if args.soak_steps is not None:
            command += ["--soak-steps", args.soak_steps]
        if getattr(args, "finish_phases", False):
            command += ["--finish-phases"]
        env = dict(os.environ, PYTHONPATH=str(root),
                   XDG_CONFIG_HOME=str(Path(folder) / "config"))
        command += ["--spawned", repr(time.time())]
        proc = subprocess.run(command, cwd=root, env=env, capture_output=True, text=True)
        if proc.returncode != 0 or not out.is_file():
            tail = proc.stderr.strip().splitlines()[-5:]
            raise options.CommandError("the window session failed: " + " | ".join(tail), 1)
        return json.loads(out.read_text())


def _print_session(figures: dict) -> None:
    for key, label, unit, fmt in KEYS:
        value = figures.get(key)
        if value is not None:
            print(f"  {label:<48} {format(value, fmt):>9} {unit}")
    size = figures.get("orbit_render_size")
    if size:
        print(f"  {'orbit: render size while dragging':<48} {size[0]:>5}×{size[1]}")
    print(f"  longest frame ran: {figures.get('longest_blocked_frame_work', '')}")
    if figures.get("longest_interacting_frame_phase"):
        print(f"  longest frame within 0.15 s of an input: in "
              f"{figures['longest_interacting_frame_phase']}")
        if figures.get("longest_interacting_frame_detail"):
            print(f"    it ran: {figures['longest_interacting_frame_detail']}")
    if figures.get("longest_panels_what"):
        print(f"  longest building of the panels: {figures['longest_panels_what']}")
    for line in figures.get("slowest_frames", []):
        print(f"    slow frame: {line}")
    for name, times in figures.get("toggles", {}).items():
        print(f"    toggle {name:<22} first {times['first_update_ms']:7.0f} ms   converged "
              f"{times['converged_ms']:7.0f} ms")


def _print_soak(figures: dict) -> None:
    """The soak's samples by minute (the warm-up's among them), each kind of GL object and
    resident memory, then what grew after the warm-up (:func:`interaction.growth`)."""
    start, end = figures["start"], figures["end"]
    print(f"  soak {figures['minutes']:g} min after a warm-up pass of "
          f"{figures['warm_up_minutes']:.1f} min: {figures['passes']} passes over "
          f"{figures['steps']} steps, {figures['cycles']} cycles, {figures['frames']} frames")
    kinds = list(start["gl"])
    print("  minute  phase     resident MiB  " + "  ".join(f"{kind:>12}" for kind in kinds))
    for sample in figures["samples"]:
        print(f"  {sample['minute']:6.1f}  {sample['phase']:<8}  {sample['rss_mib']:12.0f}  "
              + "  ".join(f"{sample['gl'][kind]:>12d}" for kind in kinds))
    print(f"  resident memory: warm-up peak {figures['warm_up_peak_rss_mib']:.0f} MiB, "
          f"peak {figures['peak_rss_mib']:.0f} MiB; after the warm-up "
          f"{start['rss_mib']:.0f} MiB, at the end {end['rss_mib']:.0f} MiB")
    for entry in figures.get("resident_by_pass", ()):
        print(f"    pass {entry['pass']}{' (warm-up)' if entry['pass'] == 1 else ''}: "
              f"{entry['steps']} steps, resident median {entry['median_mib']:.0f} MiB, "
              f"peak {entry['peak_mib']:.0f} MiB ({entry['peak_step']}), "
              f"end {entry['end_mib']:.0f} MiB")
    budget = figures.get("over_budget")
    if budget:
        print(f"  OVER THE BUDGET of {figures['rss_budget_mib']:.0f} MiB resident after "
              f"{len(budget)} of {figures['cycles']} steps:")
        for line in budget[:20]:
            print(f"    {line}")
    elif budget is not None:
        print(f"  resident memory within the budget of {figures['rss_budget_mib']:.0f} MiB "
              f"after every step")
    if figures["growth"]:
        print(f"  GROWTH after the warm-up ({len(figures['growth'])}):")
        for line in figures["growth"][:20]:
            print(f"    {line}")
    else:
        print("  no growth after the warm-up: at each pass's end every GL object count "
              "at most the warm-up's end and resident memory within "
              f"{interaction.SOAK_RSS_SLACK:.0%} of it; from the third pass on every count "
              "at most the second pass's highest and resident memory within "
              f"{interaction.SOAK_RSS_SLACK:.0%} of its peak")
