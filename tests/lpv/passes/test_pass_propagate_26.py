"""26-neighbour propagation (docs/MODEL.md "26 neighbours"): GPU against the numpy twin on
an odd grid, L1 and L2, with and without the geometry volume."""

from __future__ import annotations

import numpy as np
import pytest
from lpv_cases import assert_audits_match, random_grid, random_vpls, relative_error

from explorer.lpv import inject
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.geometry import inject_geometry
from explorer.lpv.passes.propagate import propagate_with_audit
from explorer.lpv.settings import Corrections
from explorer.lpv.twin import light_grid as twin

SPEC = GridSpec(origin=(0.0, 0.0, 0.0), cell_size=0.5, resolution=7)
ITERATIONS = 3


@pytest.mark.parametrize("sh_order, geometry_mode, clamp",
                         [(1, None, True), (1, "one-sided", True), (1, "double-sided", False),
                          (2, None, False), (2, "one-sided", True)])
def test_gpu_matches_the_twin_over_26_neighbours(ctx, sh_order, geometry_mode, clamp):
    corrections = Corrections(clamp_front_face=clamp)
    vpls = random_vpls(3, SPEC, 120, outside=5, texel_area=0.05)
    grid = inject(vpls, SPEC, corrections, "points", ctx=ctx, sh_order=sh_order)
    geometry = (None if geometry_mode is None
                else inject_geometry(vpls, SPEC, corrections, geometry_mode, ctx=ctx))
    steps, accumulated, audit = propagate_with_audit(grid, corrections, ITERATIONS, geometry,
                                                     ctx=ctx, neighbours=26)
    want_steps, want_accumulated, want_audit = twin.propagate_audited(
        grid, corrections, ITERATIONS, geometry, neighbours=26)
    for step, want in zip(steps, want_steps):
        assert relative_error(step, want) < 1e-4
    assert relative_error(accumulated, want_accumulated) < 1e-4
    assert_audits_match(audit, want_audit)
    six, _, _ = twin.propagate_audited(grid, corrections, ITERATIONS, geometry)
    assert relative_error(steps[1], six[1]) > 0.05        # the switch changes the step
    if geometry_mode is not None:
        assert audit.occluded.min() > 0


def test_twin_conserves_flux_exactly_where_it_should():
    """Without clamp and geometry: flux in = flux out + border loss per step (L1 and L2),
    and an interior source loses nothing."""
    corrections = Corrections(clamp_front_face=False)
    for coefficients in (4, 9):
        grid = random_grid(9, 9) if coefficients == 4 else np.random.default_rng(
            5).normal(size=(3, 9, 9, 9, 9))
        step, terms = twin.propagation_step(grid, corrections, neighbours=26)
        np.testing.assert_allclose(twin.flux(step) + terms["border_loss"], twin.flux(grid),
                                   rtol=1e-12, atol=1e-10)
        inner = np.zeros_like(grid)
        inner[:, 4, 4, 4] = grid[:, 4, 4, 4]
        step, terms = twin.propagation_step(inner, corrections, neighbours=26)
        np.testing.assert_allclose(twin.flux(step), twin.flux(inner), rtol=1e-12)
        assert np.all(terms["border_loss"] == 0)
        # all 26 neighbours receive light, nothing stays in the source
        assert np.count_nonzero(np.abs(step[0, 3:6, 3:6, 3:6, 0]) > 0) == 26


def test_switches_without_a_26_neighbour_form_say_so():
    grid = np.zeros((3, 5, 5, 5, 4))
    for name in ("ping_pong", "side_faces", "model_face_weights"):
        with pytest.raises(ValueError, match=name):
            twin.propagation_step(grid, Corrections(**{name: False}), neighbours=26)
    with pytest.raises(ValueError, match="6 or 26"):
        twin.propagation_step(grid, neighbours=18)


def test_settings_reject_26_neighbours_without_their_switches():
    from explorer.lpv.settings import SettingError, Settings

    assert Settings(neighbours=26).neighbours == 26
    with pytest.raises(SettingError, match="ping_pong"):
        Settings(neighbours=26, corrections=Corrections(ping_pong=False))
    with pytest.raises(SettingError, match="bounces 2"):
        Settings(neighbours=26, bounces=2, geometry_volume="one-sided")
