"""Building blocks of a stage's work as a generator of units.

A stage method of :class:`explorer.lpv.pipeline.Pipeline` is a plain method (one unit) or
a generator that yields after every unit but its last; :class:`explorer.lpv.job.Job` calls
``next()`` once per unit within its frame budget. These helpers make the common shapes.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence

import moderngl
import numpy as np

from explorer.lpv.passes.rsm import read_texture


def countdown(units: int) -> Callable[[], bool]:
    """``more()``: True until it has been called ``units`` times, so that a stage's
    generator yields after every unit but its last."""
    left = [units]

    def more() -> bool:
        left[0] -= 1
        return left[0] > 0

    return more


def read_back(textures: Sequence[moderngl.Texture]) -> Iterator[None]:
    """Read each texture back (:func:`read_texture`), one unit each; returns the arrays
    (``yield from``). At 960×540 a read-back takes as long as a band of the gather."""
    arrays: list[np.ndarray] = []
    for index, texture in enumerate(textures):
        arrays.append(read_texture(texture))
        if index < len(textures) - 1:
            yield
    return arrays


def single_unit(work: Callable[[], None]) -> Iterator[None]:
    """A one-unit stage as a generator: ``work()`` runs at the first ``next()``."""
    work()
    return
    yield  # unreachable: makes this function a generator
