"""Deterministic proxies of a frame's CPU side: the Python calls a frame makes (every call
and C call ``sys.setprofile`` sees) and its GL calls by kind (explorer/gl/call_counter.py),
for the frames of ``lpv-explorer bench --overhead`` (8³, 16 iterations, 64², RSM 64²,
timers queued). Wall-clock milliseconds on a loaded shared machine are noise; these counts
are not.

    PYTHONPATH=. python scripts/frame_calls.py            # all four frame kinds
    PYTHONPATH=. python scripts/frame_calls.py full camera

The propagation groups its slabs into units of ``GROUP_MS`` wall-clock milliseconds
(explorer/lpv/stages/propagate.py): under load a frame has more units, each with its
bookkeeping and timer query. The counts are taken with one unit for all the steps
(``GROUP_MS`` raised), so that they do not depend on the load.
"""

from __future__ import annotations

import argparse
import sys

FRAMES = {"full": "rsm", "light": "inject", "camera": "gbuffer", "display": "display"}
"""Frame kind -> the first stage it re-runs (as ``bench --overhead``)."""
WARM_UP, MEASURED = 5, 10


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("frames", nargs="*", metavar="FRAME",
                        help=f"Frame kinds to count: {', '.join(FRAMES)} (default: all).")
    args = parser.parse_args(argv)
    unknown = [name for name in args.frames if name not in FRAMES]
    if unknown:
        parser.error(f"unknown frame kind(s) {', '.join(unknown)}; choose from "
                     f"{', '.join(FRAMES)}")

    import explorer.lpv.stages.propagate as propagate_stage
    from explorer.commands import options
    from explorer.commands.overhead_bench import TINY
    from explorer.gl.call_counter import GlCallCounter
    from explorer.gl.context import create_headless_context
    from explorer.lpv.pipeline import Pipeline
    from explorer.lpv.settings import Settings

    propagate_stage.GROUP_MS = 1e9          # one unit for all the steps (docstring)
    ctx = create_headless_context()
    settings = Settings().with_changes(**TINY)
    pipeline = Pipeline(ctx)
    options.run_pipeline(pipeline, settings)
    options.run_pipeline(pipeline, settings)
    pipeline.timer.queued = True

    def frame(first: str) -> None:
        pipeline.invalidate(first)
        pipeline.start(settings).advance(None)

    calls = [0]

    def count(_frame, event, _arg) -> None:
        if event == "call" or event == "c_call":
            calls[0] += 1

    print("frame     python calls   GL calls by kind (per frame)")
    for name in args.frames or FRAMES:
        first = FRAMES[name]
        for _ in range(WARM_UP):
            frame(first)
        calls[0] = 0
        sys.setprofile(count)
        try:
            for _ in range(MEASURED):
                frame(first)
        finally:
            sys.setprofile(None)
        with GlCallCounter() as counter:
            for _ in range(MEASURED):
                frame(first)
        kinds = ", ".join(f"{kind} {value:g}" for kind, value in
                          counter.tally.per(MEASURED).items())
        print(f"{name:<9} {calls[0] / MEASURED:12.1f}   {kinds}")
    pipeline.release()
    return 0


if __name__ == "__main__":
    sys.exit(main())
