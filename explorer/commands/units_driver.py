"""The unit benchmark's driver (``lpv-explorer bench --units``): the window's settings
(its render size, the grid at 64³) through a few changes, each job run one unit a call as
the window's frames run them, every unit timed with the GL work it queued finished
(``glFinish``): wall and CPU (the process's, all threads: llvmpipe's too) milliseconds.
Per change and stage the units and the longest unit, the figure a frame's budget has to
hold (issue #32 item 3). Run as a script in a child process, so that the same driver
measures an older checkout too (``--root``): it uses only ``Pipeline.start``,
``Job.advance``, ``Job.done``, ``Job.stage`` and ``Job._run_unit``, which every version
has (:func:`measure`, :func:`format_units`).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import statistics
import sys
import time


def changes(settings, grid: int = 64, rsm: int = 1024) -> list[tuple[str, object]]:
    """The changes timed, in order (each from the one before): the grid to ``grid``³, a
    correction toggled there (the injection's π), the geometry volume on, two lights (and
    two bounces), then from the toggle L2 and 26 neighbours (the heavier kernels), and the
    geometry volume with an RSM of ``rsm``² and camera occluders (the most points)."""
    big = settings.with_changes(grid_size=grid)
    corrections = dataclasses.replace(settings.corrections,
                                      injection_pi=not settings.corrections.injection_pi)
    toggled = big.with_changes(corrections=corrections)
    volume = toggled.with_changes(geometry_volume="one-sided")
    return [(f"{grid}³ grid", big), (f"{grid}³ toggle", toggled),
            (f"{grid}³ geometry volume", volume),
            (f"{grid}³ volume, two lights", volume.with_changes(lights=("spot", "lamp"),
                                                                bounces=2)),
            (f"{grid}³ L2", toggled.with_changes(sh_order=2)),
            (f"{grid}³ 26 neighbours", toggled.with_changes(neighbours=26)),
            (f"{grid}³ RSM {rsm}², occluders", volume.with_changes(rsm_size=rsm,
                                                                  camera_occluders=True))]


def timed_job(pipeline, settings, finish) -> list[tuple[str, float, float]]:
    """(stage, wall ms, CPU ms) of each unit of the job for ``settings``, one a call."""
    job = pipeline.start(settings, need_audit="off")
    units: list[tuple[str, float, float]] = []
    Job = type(job)
    run_unit = Job._run_unit

    def timed(self) -> None:
        if self is not job:
            return run_unit(self)
        stage = job.stage
        finish()
        wall, cpu = time.perf_counter(), time.process_time()
        run_unit(job)
        finish()
        units.append((stage, (time.perf_counter() - wall) * 1e3,
                      (time.process_time() - cpu) * 1e3))
        return None

    Job._run_unit = timed                # this job's units timed, then put back
    try:
        while not job.done:
            job.advance(0.0)             # one unit a call
    finally:
        Job._run_unit = run_unit
    return units


def measure(grid: int = 32, size: tuple[int, int] = (960, 540), repeat: int = 2,
            to_grid: int = 64, rsm: int = 1024) -> dict:
    """Per change (:func:`changes` of the window's settings at ``grid`` and ``size`` to
    ``to_grid``, the large RSM ``rsm``²) and stage that ran (in ``STAGES`` order): units,
    the longest unit's wall and CPU ms (the median over ``repeat`` runs, each from the
    change before it and the first from the start)."""
    from explorer.lpv.pipeline import Pipeline
    from explorer.lpv.settings import Settings
    from explorer.lpv.stage_list import STAGES
    from explorer.ui.state import AppState

    start = AppState(settings=Settings(grid_size=grid, width=size[0],
                                       height=size[1])).settings
    plan = changes(start, to_grid, rsm)
    rows: list[dict] = []
    with Pipeline(start) as pipeline:
        pipeline.run(start)
        runs: dict[str, list[list[tuple[str, float, float]]]] = {}
        for _ in range(repeat):
            pipeline.run(start)
            for name, settings in plan:
                runs.setdefault(name, []).append(timed_job(pipeline, settings,
                                                           pipeline.ctx.finish))
        renderer = pipeline.ctx.info.get("GL_RENDERER", "")
    for name, _ in plan:
        for stage in STAGES:
            per_run = [[unit for unit in units if unit[0] == stage] for units in runs[name]]
            if not all(per_run):
                continue
            rows.append({"change": name, "stage": stage,
                         "units": max(len(units) for units in per_run),
                         "longest_wall_ms": statistics.median(
                             max(unit[1] for unit in units) for units in per_run),
                         "longest_cpu_ms": statistics.median(
                             max(unit[2] for unit in units) for units in per_run),
                         "cpu_ms": statistics.median(
                             sum(unit[2] for unit in units) for units in per_run)})
    return {"renderer": renderer, "repeat": repeat, "grid": grid, "size": list(size),
            "rows": rows}


def format_units(figures: dict) -> str:
    lines = [f"{'change':<24}{'stage':<11}{'units':>6}{'longest wall':>14}"
             f"{'longest cpu':>13}{'stage cpu':>11}"]
    for row in figures["rows"]:
        lines.append(f"{row['change']:<24}{row['stage']:<11}{row['units']:>6}"
                     f"{row['longest_wall_ms']:>14.1f}{row['longest_cpu_ms']:>13.1f}"
                     f"{row['cpu_ms']:>11.1f}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--json", required=True)
    args = parser.parse_args(argv)
    figures = measure(repeat=args.repeat)
    with open(args.json, "w", encoding="utf-8") as out:
        json.dump(figures, out, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
