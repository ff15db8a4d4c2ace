"""The propagation steps a frame keeps (grid_0..grid_N, ``keep_steps``), each held as the
box of cells that are not all zero bits, the rest given back: light in flight from a small
source fills a box that grows one cell a side per step, so a 64³ grid's early steps are a
few cells, not 12.6 MiB each. Exact: a step read back is the array recorded, bit for bit
(a cell outside its box held only +0.0; -0.0 and NaN are not zero bits and stay inside).

:class:`KeptSteps` is the sequence of arrays the consumers index (the in-flight overlay,
the Inspect panel, the lesson figures: one step at a time, the last one read kept);
:meth:`KeptSteps.cell` reads one cell of every step without building any whole step (the
picked cell's light in flight)."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import overload

import numpy as np


class _Step:
    """One step as its box of cells ``(lo, hi)`` on axes 1..3 and the array inside it (the
    recorded array itself when the box is the whole grid)."""

    __slots__ = ("shape", "dtype", "lo", "hi", "inside")

    def __init__(self, array: np.ndarray) -> None:
        self.shape, self.dtype = array.shape, array.dtype
        bits = np.ascontiguousarray(array).view(f"u{array.dtype.itemsize}")
        filled = np.any(bits != 0, axis=(0, 4))                 # (nx, ny, nz)
        lo, hi = [], []
        for axis in range(3):
            along = np.flatnonzero(np.any(filled, axis=tuple(a for a in range(3) if a != axis)))
            lo.append(int(along[0]) if along.size else 0)
            hi.append(int(along[-1]) + 1 if along.size else 0)
        self.lo, self.hi = tuple(lo), tuple(hi)
        if self.whole:
            self.inside = array
        else:
            self.inside = np.ascontiguousarray(array[self._box])
        self.inside.flags.writeable = False

    @property
    def whole(self) -> bool:
        return self.lo == (0, 0, 0) and self.hi == tuple(self.shape[1:4])

    @property
    def _box(self) -> tuple[slice, ...]:
        return (slice(None),) + tuple(slice(a, b) for a, b in zip(self.lo, self.hi))

    @property
    def nbytes(self) -> int:
        return int(self.inside.nbytes)

    def array(self) -> np.ndarray:
        if self.whole:
            return self.inside
        full = np.zeros(self.shape, self.dtype)
        full[self._box] = self.inside
        full.flags.writeable = False
        return full

    def cell(self, index: tuple[int, int, int]) -> np.ndarray:
        """``(3, C)``: the cell's coefficients of every colour channel."""
        if all(a <= i < b for i, a, b in zip(index, self.lo, self.hi)):
            local = tuple(i - a for i, a in zip(index, self.lo))
            return self.inside[(slice(None),) + local]
        return np.zeros((self.shape[0], self.shape[4]), self.dtype)


class KeptSteps(Sequence[np.ndarray]):
    """grid_0..grid_N as a read-only sequence of ``(3, N, N, N, C)`` arrays (module
    docstring): :meth:`append` while the propagation records, then index it. The arrays
    it gives are read-only; the last one indexed is kept, so reading the same step again
    (a panel every frame) builds nothing."""

    def __init__(self, arrays: Sequence[np.ndarray] = ()) -> None:
        self._steps: list[_Step] = []
        self._last: tuple[int, np.ndarray] | None = None
        for array in arrays:
            self.append(array)

    def append(self, array: np.ndarray) -> None:
        self._steps.append(_Step(np.asarray(array)))

    def __len__(self) -> int:
        return len(self._steps)

    @overload
    def __getitem__(self, index: int) -> np.ndarray: ...
    @overload
    def __getitem__(self, index: slice) -> list[np.ndarray]: ...

    def __getitem__(self, index):
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self)))]
        t = range(len(self))[index]                     # IndexError as a list's
        if self._last is None or self._last[0] != t:
            self._last = (t, self._steps[t].array())
        return self._last[1]

    def __iter__(self) -> Iterator[np.ndarray]:
        for t in range(len(self)):
            yield self._steps[t].array()

    def cell(self, index: tuple[int, int, int]) -> np.ndarray:
        """``(steps, 3, C)``: cell ``index``'s coefficients in every step."""
        return np.stack([step.cell(index) for step in self._steps])

    @property
    def nbytes(self) -> int:
        """The bytes the steps hold (their boxes)."""
        return sum(step.nbytes for step in self._steps)
