"""One cascade level's GPU resources and results in the pipeline (docs/MODEL.md
"Cascades"): the frame machinery's side of a level; the specs and blend weights are
:mod:`explorer.lpv.cascades`'s."""

from __future__ import annotations

import numpy as np

from explorer.lpv.passes.geometry import GeometryVolume
from explorer.lpv.passes.propagate import PropagatePass
from explorer.lpv.passes.textures import LpvGrid


class CascadeLevel:
    """GPU resources and results of one cascade level ``k`` in the pipeline (level 0 is
    the finest cascade, or the single grid): its injected grid, geometry volume,
    propagation (each level has its own :class:`~explorer.lpv.passes.propagate.PropagatePass`,
    because a pass owns the accumulated grid it returns) and the arrays read back."""

    def __init__(self, ctx, programs) -> None:
        self.ctx = ctx
        self.injected: LpvGrid | None = None
        self.volume: GeometryVolume | None = None
        self.propagate = PropagatePass(ctx, programs)
        self.running = None             # PropagationRun in progress
        self.output = None              # PropagationOutput of the last completed run
        self.accumulated: np.ndarray | None = None
        self.geometry: np.ndarray | None = None

    def grid(self, cells: tuple[int, int, int], fmt: str, sh_order: int = 1):
        """The injected grid, (re)allocated for ``cells`` (nx, ny, nz) in ``fmt`` with SH of
        ``sh_order`` (1 = L1, 2 = L2)."""
        if self.injected is None or self.injected.cells != tuple(cells) or \
                self.injected.format != fmt or self.injected.sh_order != sh_order:
            if self.injected is not None:
                self.injected.release()
            self.injected = LpvGrid(self.ctx, cells, fmt, sh_order)
        return self.injected

    def geometry_volume(self, cells: tuple[int, int, int], fmt: str):
        if self.volume is None or self.volume.cells != tuple(cells) or \
                self.volume.format != fmt:
            self.release_volume()
            self.volume = GeometryVolume(self.ctx, cells, fmt)
        return self.volume

    @property
    def accumulation_textures(self):
        """The r, g, b textures of the accumulation so far (the one in progress, else the
        last completed), or None before any propagation."""
        if self.running is not None:
            return self.running.accumulated.textures
        return None if self.output is None else self.output.accumulated.textures

    def release_between_runs(self) -> int:
        """Release what only a propagation in progress uses (its ping and pong grids,
        :meth:`PropagatePass.release_between_runs`) when none is; the bytes released."""
        return 0 if self.running is not None else self.propagate.release_between_runs()

    def release_volume(self) -> None:
        if self.volume is not None:
            self.volume.release()
            self.volume = None
        self.geometry = None

    def release(self) -> None:
        if self.injected is not None:
            self.injected.release()
            self.injected = None
        self.release_volume()
        self.propagate.release()
        self.running = self.output = None
