"""How far and how fast light travels through the grid (numpy twin,
explorer/lpv/twin/light_grid.py): the reason distant surfaces of a large scene, such as the
atrium's floor across the courtyard from the sunlit arcades, stay dark at a few
iterations (README, "Where the atrium's indirect light is wrong, and why")."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.lpv.grid import GridSpec
from explorer.lpv.settings import PRESETS
from explorer.lpv.twin import light_grid as R
from explorer.lpv.vpl import VplArrays

CORRECTED = PRESETS["corrected"]


def one_vpl(spec: GridSpec, cell: tuple[int, int, int], normal) -> VplArrays:
    """A unit-flux VPL at the centre of ``cell``."""
    centre = np.asarray(spec.origin) + (np.asarray(cell) + 0.5) * spec.cell_size
    return VplArrays(centre[None], np.asarray([normal], np.float64), np.ones((1, 3)),
                     np.ones(1), 1.0)


def test_light_reaches_only_the_cells_within_the_step_count_in_manhattan_distance():
    # each step moves flux to the six face neighbours only (docs/MODEL.md "Propagation"),
    # so after t steps grid_t is exactly zero beyond Manhattan distance t of the source
    # cell, and non-zero on the axis at distance t (the front)
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 15)
    source = (7, 7, 7)
    steps = R.propagate(R.inject(one_vpl(spec, source, (0.0, 0.0, 1.0)), spec, CORRECTED),
                        CORRECTED, iterations=6)
    index = np.indices((15, 15, 15))
    manhattan = sum(np.abs(index[a] - source[a]) for a in range(3))
    for t, grid in enumerate(steps):
        magnitude = np.abs(grid).sum(axis=(0, -1))
        assert np.all(magnitude[manhattan > t] == 0.0), t
        assert magnitude[7, 7, 7 + t] > 0.0, t


def test_the_light_arrives_long_after_the_front():
    # a VPL facing +z, an up-facing receiver 2 cells below and 4 ahead (Manhattan 6): the
    # front reaches it after 6 steps, but the accumulated irradiance is far below the exact
    # one-bounce value at 8 steps and only approaches it at 16, because the L1 transport
    # re-emits every face's flux as a broad lobe (lesson 12, "Blur from repeated steps")
    # and the bulk of the light lags the front
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 28)
    vpl = one_vpl(spec, (14, 8, 4), (0.0, 0.0, 1.0))
    steps = R.propagate(R.inject(vpl, spec, CORRECTED), CORRECTED, iterations=16)
    receiver = np.asarray(vpl.positions) + [0.0, -2.0, 4.0]
    r = np.linalg.norm(receiver - vpl.positions)
    exact = 1.0 / np.pi * (4.0 / r) * (2.0 / r) / r**2     # Φ/π cosθ_j cosθ_r / r²

    def ratio(iterations: int) -> float:
        accumulated = np.sum(steps[:iterations + 1], axis=0)
        irradiance = R.gather_irradiance(accumulated, spec, receiver, np.array([[0., 1., 0.]]))
        return float(irradiance[0, 0]) / exact

    assert ratio(5) == 0.0                 # beyond the front (trilinear reach included)
    assert 0.0 < ratio(8) < 0.3            # 0.20 measured
    assert ratio(8) < ratio(12) < ratio(16)
    assert ratio(16) == pytest.approx(0.68, abs=0.1)
