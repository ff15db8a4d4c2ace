"""Building blocks of a stage's work as a generator of units.

A stage method of :class:`explorer.lpv.pipeline.Pipeline` is a plain method (one unit) or
a generator that yields after every unit but its last; :class:`explorer.lpv.job.Job` calls
``next()`` once per unit within its frame budget. These helpers make the common shapes.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence

import moderngl

from explorer.gl.gpu_sync import DeferredRead, GpuWait, issue_together


def countdown(units: int) -> Callable[[], bool]:
    """``more()``: True until it has been called ``units`` times, so that a stage's
    generator yields after every unit but its last."""
    left = [units]

    def more() -> bool:
        left[0] -= 1
        return left[0] > 0

    return more


def read_back_later(reads: Sequence[DeferredRead], textures: Sequence[moderngl.Texture],
                    apart: bool = False) -> Iterator[GpuWait | None]:
    """Copy each float32 RGBA texture into its deferred read (one unit, no wait), then take
    them, row 0 at the top as ``rsm.read_texture`` gives them, in the next unit (``yield
    from`` returns the arrays), which a job within a budget does once the copies are done
    (explorer/lpv/job.py). ``reads``: one per texture, owned by the stage (reused).
    ``apart``: each texture taken in a unit of its own (a 960×540 image's three took
    40–60 ms together on llvmpipe), the same arrays: :func:`read_back_units` units in all."""
    issue_together(reads[:len(textures)], textures,
                   [texture.size[::-1] + (4,) for texture in textures])
    yield GpuWait(list(reads[:len(textures)]))
    arrays = []
    for read in reads[:len(textures)]:
        if apart and arrays:
            yield None
        arrays.append(read.wait()[::-1].copy())
    return arrays


def read_back_units(textures: int, apart: bool = False) -> int:
    """The units of :func:`read_back_later` of ``textures`` textures."""
    return 1 + (textures if apart else 1)


def single_unit(work: Callable[[], None]) -> Iterator[None]:
    """A one-unit stage as a generator: ``work()`` runs at the first ``next()``."""
    work()
    return
    yield  # unreachable: makes this function a generator
