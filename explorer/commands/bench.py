"""``lpv-explorer bench``: milliseconds per pass and per frame over grid sizes and
iteration counts, and the memory bandwidth the propagation achieves.

With ``--cascades`` every cascade count is a row: the inject, geometry and propagate
columns then hold all cascades together (each cascade is a full grid), and the bandwidth
counts every cascade's grids.

``--scene`` picks what is rendered; the header names it with its triangle count, which
the RSM and G-buffer passes scale with: ``bench --scene atrium`` times the large
procedural courtyard (over 100 000 triangles) instead of the 34-triangle Cornell box.

Several lights and moving objects (docs/MODEL.md "Several lights", "Moving objects and
temporal stability"): the ``lights-2`` and ``lights-4`` rows light the scene with the
first 2 or 4 lights of its rig (``lights`` column: lights/RSM views; a point light
renders six views), and the ``moving-object`` row moves the scene's second object a
little before every timed frame, so the frame re-poses it (the ``pose`` column: the
wall-clock time of moving its corners and writing them to the vertex buffer) and runs
every stage after the scene's again, the G-buffer included.

Bandwidth model: one propagation step reads the previous grid and writes the next one
(3 textures × one texel per cell each) and reads and writes the accumulation grid, so it
moves at least ``4 × 3 × texel_bytes`` per cell (192 B with rgba32f, 96 B with rgba16f);
neighbour reads are assumed to hit the cache. The propagate pass time also holds the
energy-audit reduction and the copy of grid_0 into the accumulation grid, so the figure is
a lower bound of what the propagation kernel alone reaches. With ``--sh-order 2`` (L2) a
cell holds 3 texels per channel, so a step moves 3× as many bytes.

Rows are timed as the window runs the frame: without the per-step energy audit (the
``audit`` variant adds it). Baseline: for every single-cascade L1 row the minimal
propagation kernel (``shaders/propagate_minimal.glsl``: per neighbour three ``texelFetch``
of the SH grid, and four of the geometry volume when there is one, five faces written
out with the generated constants, the three target images written and added into the
three accumulation images; one barrier per step and one ``finish`` for all; no switches,
no audit) propagates the same injected grid, timed alternately with the pipeline's own
propagation in the same run; the ``×base`` column is the median of the frames' ratios of
the two (each frame's propagation over the baseline timed right after it), and a
``baseline`` row per grid shows the kernel's time.
"""

from __future__ import annotations

import argparse
import datetime
import json
import statistics
from pathlib import Path

from explorer.commands import options
from explorer.lpv.settings import Settings, preset_name
from explorer.schema import Spec

FULL_GRIDS = (16, 32, 64, 128)
FULL_ITERATIONS = (4, 8, 16, 32, 64)
SOFTWARE_GRIDS = (16, 32, 64)
SOFTWARE_ITERATIONS = (4, 8, 16)
QUICK_GRIDS = (8, 16)
QUICK_ITERATIONS = (2, 4)
QUICK_SIZES = {"width": 64, "height": 64, "rsm_size": 64}
TEXEL_BYTES = {"rgba32f": 16, "rgba16f": 8}
PASS_COLUMNS = ("pose", "rsm", "downsample", "inject", "geometry", "propagate", "gbuffer",
                "gather", "fog", "display")
VARIANTS: dict[str, dict[str, object]] = {
    "offset-0": {"injection_offset_cells": 0.0},
    "damping": {"gather_damping": True},
    "net-flux": {"gather_net_flux": True},
    "bounces-2": {"bounces": 2},
    "audit": {"need_audit": "full"},
    "audit-flux": {"need_audit": "flux"},
    "geometry": {},
    "camera-occluders": {"camera_occluders": True},
    "statistical": {"geometry_visibility": "statistical"},
    "flux-budget": {"flux_budget": True},
    "fog-16": {"fog": True, "fog_steps": 16},
    "fog-32": {"fog": True, "fog_steps": 32},
    "fog-64": {"fog": True, "fog_steps": 64},
    "glossy": {"glossy": True},
    "lights-2": {"light_count": 2},
    "lights-4": {"light_count": 4},
    "moving-object": {"move_object": True},
}
"""Extra rows (at each grid's largest iteration count): the leak-reduction and bounce
options against the default settings, the propagation with its full per-step energy
audit (``audit``) and with the flux per step only (``audit-flux``: the minimal kernel
and one flux reduction per step; the Plots panel's flux tab) (``need_audit`` is a run
option, not a Settings field: :data:`RUN_OPTIONS`), what each
feature beyond diffuse costs (docs/MODEL.md "Camera occluders", "Fog", "Glossy
reflections"): ``geometry`` (the RSM's occluders alone) against ``camera-occluders`` in
the geometry column, ``statistical`` (the volume's exp(−τ) visibility) against
``geometry`` and ``flux-budget`` (the budget's pass and clamp per step) against ``default``
in the propagate column, the fog column at 16, 32 and 64 march steps, and ``glossy`` against
``default`` in the gather column; several lights (the first ``light_count`` of the
scene's rig; a scene with fewer has no such row) and a moving object (module docstring).
The variants in :data:`NEEDS_GEOMETRY` turn a one-sided geometry volume on if
--geometry-volume is off (they need one)."""
NEEDS_GEOMETRY = ("bounces-2", "geometry", "camera-occluders", "statistical")
COMPARED = ("default", "audit", "audit-flux", "geometry", "statistical", "flux-budget")
"""Rows whose propagation is timed against the minimal kernel (with the geometry volume's
occlusion for ``geometry`` and ``statistical``): one bounce, L1, one cascade."""
RUN_OPTIONS = ("need_audit", "light_count", "move_object")
MOVE_STEP = 1e-3
"""World units the moving-object row moves its object before each frame."""
"""Keys of a variant that go to ``Pipeline.run`` instead of the Settings."""
DEFAULT_REPEAT = 3
REPEAT = Spec(kind="int", low=1, high=1000, doc="Timed frames per configuration; the "
              "median is reported.")
PEAK_GBS = Spec(kind="float", low=0.0, low_open=True, high=1e6, optional=True,
                doc="The device's peak memory bandwidth in GB/s, to print the "
                    "propagation's share of it.")


def parse_variants(text: str) -> tuple[str, ...]:
    names = tuple(part.strip() for part in text.split(",") if part.strip())
    if names == ("none",):
        return ()
    unknown = [name for name in names if name not in VARIANTS]
    if unknown or not names:
        raise argparse.ArgumentTypeError(f"variants must be 'none' or a comma list of "
                                         f"{', '.join(VARIANTS)}; got {text!r}")
    return names


INTERACTIVE_FRAMES = Spec(kind="int", low=1, high=100000,
                          doc="Frames of the camera orbit in --interactive.")
SOAK_MINUTES = Spec(kind="float", low=0.0, low_open=True, high=1440.0,
                    doc="Minutes of passes through the course after the warm-up pass.")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--interactive", action="store_true",
                        help="drive the real window through a scripted session (launch, "
                             "idle, orbit, exposure sweep, every correction toggled, a "
                             "slider drag, an object move, grid 64³) and print its "
                             "responsiveness (needs a display: xvfb-run)")
    parser.add_argument("--overhead", action="store_true",
                        help="per-frame CPU overhead on tiny sizes (8³, 64² image and RSM "
                             "unless given): wall and Python milliseconds outside GL, GL "
                             "calls, dispatches, draws, barriers, finishes, read-backs, "
                             "uniform uploads and bindings, for a full, a light, a camera "
                             "and a display frame (--repeat frames each, default 20)")
    parser.add_argument("--units", action="store_true",
                        help="the window's settings (960×540, 64³) through a grid change, "
                             "a correction toggled, the geometry volume, two lights, L2, "
                             "26 neighbours and a 1024² RSM with camera occluders, "
                             "each job one unit a call as the window runs it, every unit "
                             "finished on the GPU: per stage the units and the longest "
                             "unit's wall and CPU milliseconds (median of --repeat runs, "
                             "default 2; --root: another checkout)")
    parser.add_argument("--gpu-report", type=Path, default=None, metavar="OUT.json",
                        help="every figure of BENCHMARKS.md in one go (pass times and "
                             "GB/s, the variant rows, --overhead, --interactive; within "
                             "about five minutes on a GPU): one JSON and a table")
    parser.add_argument("--frames", type=options.value_type("frames", INTERACTIVE_FRAMES),
                        default=60, metavar="N",
                        help=options.spec_help(INTERACTIVE_FRAMES, 60))
    parser.add_argument("--soak", metavar="MINUTES",
                        type=options.value_type("soak", SOAK_MINUTES), default=None,
                        help=options.spec_help(SOAK_MINUTES) + " A warm-up pass through "
                             "the course (every step once, each with its grid, cascades, "
                             "view, buffer, a correction, a pick), then passes repeating it "
                             "for MINUTES (at least one). Prints resident memory and the GL "
                             "objects of each kind per minute; exits 1 on growth after the "
                             "warm-up: at a pass's end a count above the warm-up's end "
                             "or resident memory over it by more than a tenth; from the "
                             "third pass on a count above the second pass's highest of "
                             "its kind or resident memory over the second pass's peak by "
                             "more than a tenth; and on resident memory over 1.2 GiB.")
    parser.add_argument("--soak-steps", default=None, metavar="LESSON:STEP,...",
                        help="with --soak: the steps one pass takes (default every step of "
                             "every lesson), e.g. overview:2,errata:1")
    parser.add_argument("--finish-phases", action="store_true",
                        help="with --interactive: end each phase of a window frame (update, "
                             "panels, render, swap) with glFinish, so that the frame "
                             "profiles printed hold each phase's own GPU work (a diagnosis: "
                             "the figures are then not the window's own)")
    parser.add_argument("--root", type=Path, default=None, metavar="PATH",
                        help="with --interactive/--soak/--units: the source tree whose "
                             "window or pipeline is driven (default: this one), e.g. an "
                             "older checkout")
    parser.add_argument("--variants", type=parse_variants, default=tuple(VARIANTS),
                        metavar="NAME[,NAME...]",
                        help=f"extra rows at each grid's largest iteration count: "
                             f"{', '.join(VARIANTS)} (comma list) or none (default: all)")
    parser.add_argument("--repeat", type=options.value_type("repeat", REPEAT), default=None,
                        metavar="N",
                        help=options.spec_help(REPEAT, f"{DEFAULT_REPEAT}, 1 with --quick"))
    parser.add_argument("--quick", action="store_true",
                        help="CI-sized run: grids 8,16, iterations 2,4, 64x64 image, 64² RSM, "
                             "one timed frame (options given still win)")
    parser.add_argument("--peak-gbs", type=options.value_type("peak_gbs", PEAK_GBS), default=None,
                        metavar="X",
                        help=options.spec_help(PEAK_GBS))
    parser.add_argument("--json", type=Path, metavar="FILE.json",
                        help="also write the results as JSON here")
    options.add_setting_options(parser, exclude=("exposure", "indirect_only"),
                        sweep=("grid_size", "iterations", "cascades", "sh_order"),
                        aliases={"grid_size": ("--grids",), "grid_format": ("--format",)})


def propagation_bytes(grid: int, iterations: int, fmt: str, sh_order: int = 1) -> int:
    """Bytes one frame's propagation moves at least (module docstring); L2 (``sh_order``
    2) stores 3 texels per cell and channel."""
    groups = 3 if sh_order == 2 else 1
    return 4 * 3 * groups * TEXEL_BYTES[fmt] * grid**3 * iterations


def plan(args: argparse.Namespace, software: bool, rig: tuple[str, ...] = ("light",)
         ) -> list[tuple[str, Settings]]:
    """Every (variant, Settings) the bench times, all made (so checked by the schema)
    before the first is timed, grid by grid. Left-out sweeps use the lists for this
    device; ``rig``: the scene's light names (the lights-N rows light the first N)."""
    base = options.settings_from_args(args)
    if args.quick:
        if args.size is None:
            base = base.with_changes(width=QUICK_SIZES["width"], height=QUICK_SIZES["height"])
        if args.rsm_size is None:
            base = base.with_changes(rsm_size=QUICK_SIZES["rsm_size"])
        grids, iterations = QUICK_GRIDS, QUICK_ITERATIONS
    else:
        grids = SOFTWARE_GRIDS if software else FULL_GRIDS
        iterations = SOFTWARE_ITERATIONS if software else FULL_ITERATIONS
    grids = args.grid_size or grids
    iterations = args.iterations or iterations
    cascades = options.sweep_values(args, "cascades", base)
    orders = options.sweep_values(args, "sh_order", base)
    runs = []
    try:
        for grid in grids:
            for steps in iterations:
                for count in cascades:
                    for order in orders:
                        runs.append(("default", base.with_changes(
                            grid_size=grid, iterations=steps, cascades=count, sh_order=order)))
            for name in args.variants:
                changes = {key: value for key, value in VARIANTS[name].items()
                           if key not in RUN_OPTIONS}
                if name in NEEDS_GEOMETRY and base.geometry_volume == "off":
                    changes["geometry_volume"] = "one-sided"
                count = VARIANTS[name].get("light_count")
                if count is not None:
                    if len(rig) < count:
                        continue
                    changes["lights"] = rig[:count]
                runs.append((name, base.with_changes(grid_size=grid, iterations=max(iterations),
                                                     sh_order=orders[0], **changes)))
    except ValueError as exc:
        raise options.CommandError(exc) from None
    return runs


def run_bench(args: argparse.Namespace, pipeline, runs: list[tuple[str, Settings]],
              progress: options.Progress | None = None) -> list[dict]:
    """Time each run: a warm-up frame, then ``--repeat`` frames from the RSM on (the
    median per pass), and after each grid's runs its baseline row (module docstring);
    ``progress``: an :class:`options.Progress` showing the run and its stage."""
    from explorer.lpv.passes.propagate_baseline import BaselinePropagatePass

    repeat = args.repeat or (1 if args.quick else DEFAULT_REPEAT)
    rows: list[dict] = []
    baseline = BaselinePropagatePass(pipeline.ctx, pipeline.programs)
    baseline_row = None
    try:
        for done, (variant, settings) in enumerate(runs):
            if baseline_row is not None and baseline_row["grid"] != settings.grid_size:
                rows.append(baseline_row)
                baseline_row = None
            if progress is not None:    # the bar names the run, then its stage
                progress.prefix = f"{variant} {settings.grid_size}³ ({done + 1}/{len(runs)}) "
            row = _time_run(pipeline, baseline, variant, settings, repeat, progress)
            if "baseline_ms" in row and variant == "default" and (
                    baseline_row is None or row["iterations"] >= baseline_row["iterations"]):
                baseline_row = {"variant": "baseline", "grid": row["grid"],
                                "iterations": row["iterations"], "cascades": 1, "sh_order": 1,
                                "passes_ms": {"propagate": row["baseline_ms"]},
                                "frame_ms": row["baseline_ms"],
                                "ms_per_step": row["baseline_ms"] / row["iterations"],
                                "kernel_ratio": 1.0, "methods": {}}
            rows.append(row)
    finally:
        baseline.release()
    return rows + ([baseline_row] if baseline_row else [])


def _time_run(pipeline, baseline, variant: str, settings: Settings, repeat: int,
              progress) -> dict:
    """The row of one run: pass medians, bandwidth, and for a single-cascade L1 row the
    baseline kernel timed alternately with the pipeline's propagation."""
    need_audit = VARIANTS.get(variant, {}).get("need_audit", "off")
    moving = bool(VARIANTS.get(variant, {}).get("move_object", False))
    steps, cascades = settings.iterations, settings.cascades
    compare = steps > 0 and cascades == 1 and settings.sh_order == 1 and \
        variant in COMPARED
    run = {"need_audit": need_audit, "progress": progress}
    options.run_pipeline(pipeline, settings, **run)     # warm-up: compiles, allocates
    if compare:
        _time_baseline(pipeline, baseline, steps)
    samples: dict[str, list[float]] = {}
    for index in range(repeat):           # the pipeline and the baseline alternately
        if moving:                        # the move re-runs the scene stage and all after it
            frame_settings = _moved(settings, pipeline.base_scene, index + 1)
        else:
            frame_settings = settings
            pipeline.invalidate("rsm")
        result = options.run_pipeline(pipeline, frame_settings, **run)
        for name in result.stages_run:
            if name in result.timings_ms:
                samples.setdefault(name, []).append(result.timings_ms[name])
        if moving:
            samples.setdefault("pose", []).append(pipeline.pose_ms)
        if compare:
            samples.setdefault("baseline", []).append(
                _time_baseline(pipeline, baseline, steps))
    passes = {name: statistics.median(values) for name, values in samples.items()}
    baseline_ms = passes.pop("baseline", None)
    pairs = list(zip(samples.get("propagate", []), samples.get("baseline", [])))
    row = {"variant": variant, "grid": settings.grid_size, "iterations": steps,
           "cascades": cascades, "sh_order": settings.sh_order, "passes_ms": passes,
           "frame_ms": sum(passes.values()), "methods": dict(pipeline.timing_methods),
           "lights": len(result.light_names), "views": len(result.view_lights)}
    propagate_ms = passes.get("propagate", 0.0)
    if steps > 0 and propagate_ms > 0:
        moved = cascades * propagation_bytes(settings.grid_size, steps,
                                             settings.grid_format, settings.sh_order)
        row["propagation_gbs"] = moved / (propagate_ms * 1e-3) / 1e9
        row["ms_per_step"] = propagate_ms / steps
    if baseline_ms:
        # the median of each frame's ratio to the baseline timed right after it: on a
        # shared machine the two medians can come from different moments of its load
        row["baseline_ms"] = baseline_ms
        row["kernel_ratio"] = statistics.median(
            ms / base for ms, base in pairs if base > 0)
    return row


def _moved(settings: Settings, scene, frame: int) -> Settings:
    """``settings`` with the scene's second object (its first when it has one) moved
    ``frame``·:data:`MOVE_STEP` along x."""
    if not scene.objects:
        raise options.CommandError(f"the moving-object row needs an object that can move; "
                                   f"scene {scene.name!r} has none (--variants without "
                                   f"moving-object)")
    name = scene.objects[min(1, len(scene.objects) - 1)].name
    return settings.with_changes(object_transforms={name: (frame * MOVE_STEP, 0.0, 0.0)})


def _time_baseline(pipeline, baseline, steps: int) -> float:
    """Milliseconds of ``steps`` steps of the baseline kernel on the grid the pipeline
    just injected (cascade 0), timed like the pipeline's passes."""
    injected, spec, volume = pipeline.propagation_inputs(0)
    return pipeline.measure("baseline", lambda: baseline.run(injected, spec, steps,
                                                             volume))[1]


def format_table(rows: list[dict], peak_gbs: float | None) -> str:
    header = ["variant", "grid", "iters", "cascades", "sh", "lights", *PASS_COLUMNS, "frame",
              "ms/step", "×base", "GB/s"]
    if peak_gbs:
        header.append("% peak")
    widths = [max(10, *(len(row.get("variant", "default")) for row in rows))] + \
        [10] * (len(header) - 1)
    lines = ["  ".join(f"{h:>{w}}" for h, w in zip(header, widths))]
    for row in rows:
        cells = [row.get("variant", "default"), f"{row['grid']}³", str(row["iterations"]),
                 str(row.get("cascades", 1)), f"L{row.get('sh_order', 1)}",
                 f"{row['lights']}/{row['views']}" if "lights" in row else "-"]
        cells += [f"{row['passes_ms'][name]:.2f}" if name in row["passes_ms"] else "-"
                  for name in PASS_COLUMNS]
        cells.append(f"{row['frame_ms']:.2f}")
        cells.append(f"{row['ms_per_step']:.3f}" if "ms_per_step" in row else "-")
        cells.append(f"{row['kernel_ratio']:.2f}" if "kernel_ratio" in row else "-")
        gbs = row.get("propagation_gbs")
        cells.append(f"{gbs:.2f}" if gbs is not None else "-")
        if peak_gbs:
            cells.append(f"{100 * gbs / peak_gbs:.1f}" if gbs is not None else "-")
        lines.append("  ".join(f"{c:>{w}}" for c, w in zip(cells, widths)))
    return "\n".join(lines)


def main(args: argparse.Namespace) -> int:
    options.one_of(args, {"interactive": "--interactive", "overhead": "--overhead",
                          "soak": "--soak", "gpu_report": "--gpu-report", "units": "--units"})
    window = args.interactive or args.soak is not None
    options.only_with(args, window or args.units, "--interactive, --soak or --units",
                      {"root": "--root"})
    # the unit bench runs the window's own settings
    options.only_with(args, not args.units, "the timing bench (not --units)",
                      {"quick": "--quick", "peak_gbs": "--peak-gbs",
                       **options.setting_flags(args)})
    options.only_with(args, args.interactive, "--interactive",
                      {"finish_phases": "--finish-phases"})
    options.only_with(args, args.soak is not None, "--soak", {"soak_steps": "--soak-steps"})
    # the window bench drives the window with its own session: these would be unused
    options.only_with(args, not window, "the timing bench (not --interactive or --soak)",
                      {"repeat": "--repeat", "quick": "--quick", "peak_gbs": "--peak-gbs",
                       **options.setting_flags(args)})
    if args.gpu_report is not None:
        from explorer.commands.gpu_report import main as gpu_report

        return gpu_report(args)
    if window:
        from explorer.commands.interactive_bench import run_window_bench

        return run_window_bench(args)
    if args.units:
        from explorer.commands.interactive_bench import run_units_bench

        return run_units_bench(args)
    from explorer.gl.context import probe
    from explorer.lpv.pipeline import Pipeline
    from explorer.scene import SceneError, load_scene

    base = options.settings_from_args(args)
    options.check_scene(base.scene)
    if args.overhead:
        return _overhead(args)
    with options.Outputs("--json") as outputs:
        json_path = outputs.file(args.json, (".json",)) if args.json is not None else None
        try:
            with Pipeline(base) as pipeline, options.Progress("bench") as progress:
                pipeline.timer.queued = False   # every pass timed on its own (timing.py)
                runs = plan(args, pipeline.software_renderer, load_scene(base.scene).light_names)
                caps = probe(pipeline.ctx)
                rows = run_bench(args, pipeline, runs, progress)
                triangles = pipeline.base_scene.triangle_count
        except SceneError as exc:
            raise options.CommandError(exc) from None
        except options.render_failures() as exc:
            raise options.CommandError(exc, 1) from None
        methods = sorted({method for row in rows for method in row["methods"].values()})
        when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        print(f"device: {caps.renderer} ({caps.version}); {when}")
        print(f"scene {base.scene} ({triangles} triangles), corrections "
              f"{preset_name(base.corrections)}, format "
              f"{base.grid_format}, geometry volume {base.geometry_volume}; timing: "
              f"{', '.join(methods)}; milliseconds per pass (median)"
              f"{' [quick]' if args.quick else ''}")
        print(format_table(rows, args.peak_gbs))
        if args.peak_gbs is None:
            print("(pass --peak-gbs <device peak bandwidth in GB/s> to see the share reached)")
        if json_path is not None:
            payload = json.dumps({"device": caps.renderer, "version": caps.version,
                                  "date": when, "scene": base.scene,
                                  "triangles": triangles, "rows": rows}, indent=2)
            outputs.write(json_path, lambda p: p.write_text(payload))
            print(f"wrote {json_path}")
    return 0


def _overhead(args: argparse.Namespace) -> int:
    """``bench --overhead`` (explorer/commands/overhead_bench.py)."""
    from explorer.commands.overhead_bench import (
        DEFAULT_FRAMES,
        format_overhead,
        measure_overhead,
        measure_window_frames,
        tiny_settings,
    )
    from explorer.gl.context import probe
    from explorer.lpv.pipeline import Pipeline

    try:
        settings = tiny_settings(args)
    except ValueError as exc:
        raise options.CommandError(exc) from None
    with options.Outputs("--json") as outputs:
        json_path = outputs.file(args.json, (".json",)) if args.json is not None else None
        try:
            with Pipeline(settings) as pipeline:
                caps = probe(pipeline.ctx)
                rows = measure_overhead(pipeline, settings, args.repeat or DEFAULT_FRAMES)
                rows.append(measure_window_frames(pipeline.ctx, settings,
                                                  max(2, (args.repeat or DEFAULT_FRAMES) // 5)))
        except options.render_failures() as exc:
            raise options.CommandError(exc, 1) from None
        when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        print(f"device: {caps.renderer} ({caps.version}); {when}")
        print(f"overhead per frame: scene {settings.scene}, {settings.grid_size}³, "
              f"{settings.iterations} iterations, {settings.width}×{settings.height}, RSM "
              f"{settings.rsm_size}²; python ms = wall time outside GL calls")
        print(format_overhead(rows))
        if json_path is not None:
            payload = json.dumps({"device": caps.renderer, "version": caps.version,
                                  "date": when, "settings": settings.to_dict(),
                                  "overhead": rows}, indent=2)
            outputs.write(json_path, lambda p: p.write_text(payload))
    return 0 if all(row.get("target_met", True) for row in rows) else 1
