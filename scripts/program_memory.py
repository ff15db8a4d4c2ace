"""Resident memory llvmpipe keeps per program once it has run: one pipeline at 8³ runs
the propagation, gather and audit variants of L1/L2, with and without a geometry volume,
under each audit mode (16 programs more than a default frame's), and prints the resident
memory they added (after ``malloc_trim``, so only what stays is counted).

    PYTHONPATH=. python scripts/program_memory.py
"""

from __future__ import annotations

import ctypes

from explorer.gl.context import create_headless_context
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings


def resident_mib() -> float:
    with open("/proc/self/statm", encoding="ascii") as statm:
        return int(statm.read().split()[1]) * 4096 / 2**20


def main() -> int:
    ctx = create_headless_context()
    base = Settings(scene="cornell", grid_size=8, iterations=4, rsm_size=32, width=40,
                    height=32)
    pipeline = Pipeline(base, ctx=ctx)
    pipeline.programs.capacity = 1000          # every variant stays compiled
    pipeline.run(base)
    trim = ctypes.CDLL("libc.so.6").malloc_trim
    trim(0)
    before, programs = resident_mib(), len(pipeline.programs)
    for order in (1, 2):
        for volume in ("off", "one-sided"):
            for audit in ("off", "flux", "full"):
                pipeline.run(base.with_changes(sh_order=order, geometry_volume=volume),
                             need_audit=audit)
    trim(0)
    added, grown = resident_mib() - before, len(pipeline.programs) - programs
    print(f"programs {programs} -> {len(pipeline.programs)}: resident memory +{added:.1f} MiB, "
          f"{added / max(grown, 1):.2f} MiB a program")
    pipeline.release()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
