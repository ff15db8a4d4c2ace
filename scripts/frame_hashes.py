"""Hashes of every array a pipeline's frames leave, for checking that a change to the
frame's CPU side keeps every output bit for bit: the grids, steps, geometry volumes,
audits (and some cells' records), images, VPLs and the display texture of several
configurations, each in the three audit modes, as a synchronous run, a queued job in
5 ms budgets and a queued job after a camera move (these keep the steps), and queued jobs
without the steps kept, run to the end and in 5 ms budgets.

    PYTHONPATH=. python scripts/frame_hashes.py > before.txt
    ... change ...
    PYTHONPATH=. python scripts/frame_hashes.py > after.txt && cmp before.txt after.txt

Timings are left out (they differ between two runs), and so are the in-place
propagation's grids on a multi-threaded llvmpipe, whose race makes them differ between
two runs too: compare with ``LP_NUM_THREADS=1`` (one rasteriser thread, every output
the same from run to run).
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import sys
from collections.abc import Iterator

import numpy as np

BASE = {"grid_size": 8, "width": 64, "height": 64, "rsm_size": 64}
AUDITS = ("full", "flux", "off")
CELLS = ((0, 0, 0), (3, 4, 2), (7, 7, 7))
"""Cells whose per-cell audit records are read (the full audit)."""
SKIPPED = {"timings_ms", "timing_methods", "settings"}


def configurations() -> dict[str, dict]:
    from explorer.lpv.corrections import PRESETS, Corrections

    return {
        "default": {},
        "geometry-2-bounces": {"geometry_volume": "one-sided", "bounces": 2},
        "flux-budget": {"flux_budget": True},
        "cascades-2": {"cascades": 2},
        "l2": {"sh_order": 2},
        "in-place": {"corrections": dataclasses.replace(Corrections(), ping_pong=False)},
        "fog": {"fog": True},
        "neighbours-26": {"neighbours": 26},
        "original": {"corrections": PRESETS["original"]},
        "grid-16-geometry": {"grid_size": 16, "geometry_volume": "one-sided"},
    }


def digest(array: np.ndarray) -> str:
    array = np.ascontiguousarray(array)
    head = f"{array.dtype.str}{array.shape}".encode()
    return hashlib.sha1(head + array.tobytes()).hexdigest()[:16]


def walk(value, path: str, seen: set[int]) -> Iterator[tuple[str, str]]:
    if isinstance(value, np.ndarray):
        yield path, digest(value)
    elif value is None or isinstance(value, (bool, int, float, str, np.generic)):
        yield path, repr(value)
    elif isinstance(value, dict):
        for key in sorted(value, key=str):
            yield from walk(value[key], f"{path}[{key!r}]", seen)
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        if id(value) in seen:
            return
        seen.add(id(value))
        for f in dataclasses.fields(value):
            if f.name in SKIPPED or f.name.startswith("_"):
                continue
            yield from walk(getattr(value, f.name), f"{path}.{f.name}", seen)
    elif hasattr(value, "read") and hasattr(value, "cells"):          # CellAuditRecords
        for cell in CELLS:
            if all(c < n for c, n in zip(cell, value.cells)):
                yield from walk(value.read(cell), f"{path}.read{cell}", seen)
    elif isinstance(value, (list, tuple)) or hasattr(value, "__len__"):
        for index, item in enumerate(value):
            yield from walk(item, f"{path}[{index}]", seen)
    else:
        yield path, type(value).__name__


def frame_lines(name: str, pipeline, result) -> Iterator[str]:
    for path, value in walk(result, name, set()):
        yield f"{path} {value}"
    yield f"{name}.final_image {digest(result.final_image)}"
    yield f"{name}.stages_run {result.stages_run}"
    texture = pipeline.final_texture
    yield f"{name}.display_texture {hashlib.sha1(texture.read()).hexdigest()[:16]}"


def queued(pipeline, settings, audit: str, budget_ms: float | None, keep_steps: bool = True):
    pipeline.timer.queued = True
    try:
        job = pipeline.start(settings, keep_steps=keep_steps, need_audit=audit)
        while not job.done:
            job.advance(budget_ms)
        return job.result
    finally:
        pipeline.timer.queued = False


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("configs", nargs="*", help="Configurations (default: all).")
    args = parser.parse_args(argv)

    from explorer.gl.context import create_headless_context
    from explorer.lpv.pipeline import Pipeline
    from explorer.lpv.settings import Settings

    ctx = create_headless_context()
    arrays = 0
    for config, changes in configurations().items():
        if args.configs and config not in args.configs:
            continue
        settings = Settings().with_changes(**{**BASE, **changes})
        pipeline = Pipeline(settings, ctx)
        for audit in AUDITS:
            tag = f"{config}/{audit}"
            result = pipeline.run(settings, keep_steps=True, need_audit=audit)
            lines = list(frame_lines(f"{tag}/run", pipeline, result))
            pipeline.invalidate("rsm")
            result = queued(pipeline, settings, audit, 5.0)
            lines += frame_lines(f"{tag}/queued", pipeline, result)
            pipeline.invalidate("inject")
            result = queued(pipeline, settings, audit, 5.0)
            lines += frame_lines(f"{tag}/light", pipeline, result)
            camera = result.camera
            eye = tuple(float(v) * 0.9 + 0.05 for v in camera.eye)
            moved = settings.with_changes(camera=(eye, tuple(map(float, camera.target))))
            result = queued(pipeline, moved, audit, 5.0)
            lines += frame_lines(f"{tag}/camera", pipeline, result)
            # without the steps kept (the window's and the bench's frames): the
            # propagation's steps in a row, in one unit and in 5 ms budgets
            for name, budget in (("whole", None), ("budgets", 5.0)):
                pipeline.invalidate("rsm")
                result = queued(pipeline, settings, audit, budget, keep_steps=False)
                lines += frame_lines(f"{tag}/{name}", pipeline, result)
            arrays += sum(1 for line in lines if len(line.rsplit(" ", 1)[-1]) == 16)
            print("\n".join(lines))
        pipeline.release()
    print(f"# {arrays} hashes", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
