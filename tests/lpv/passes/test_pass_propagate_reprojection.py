"""Face-centre reprojection (``Settings.reprojection``, docs/MODEL.md "Propagation"): GPU
against the numpy twin on an odd grid, and what it must hold (the same flux per neighbour
as the face-normal lobes, more of it kept along the way it travels)."""

from __future__ import annotations

import numpy as np
import pytest
from lpv_cases import assert_audits_match, in_place_schedules, random_vpls, relative_error

from explorer.lpv import inject
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.geometry import inject_geometry
from explorer.lpv.passes.propagate import propagate_with_audit
from explorer.lpv.settings import Corrections
from explorer.lpv.twin import light_grid as twin

SPEC = GridSpec(origin=(0.0, 0.0, 0.0), cell_size=0.5, cells=(9, 5, 7))
ITERATIONS = 3


@pytest.mark.parametrize("sh_order, geometry_mode, neighbours, budget",
                         [(1, None, 6, False), (1, "one-sided", 26, False),
                          (2, None, 26, False), (2, "double-sided", 6, False),
                          (2, "one-sided", 26, True)])
def test_gpu_matches_the_twin_with_face_centre_reprojection(ctx, sh_order, geometry_mode,
                                                           neighbours, budget):
    corrections = Corrections()
    vpls = random_vpls(7, SPEC, 140, outside=5, texel_area=0.05)
    grid = inject(vpls, SPEC, corrections, "points", ctx=ctx, sh_order=sh_order)
    geometry = (None if geometry_mode is None
                else inject_geometry(vpls, SPEC, corrections, geometry_mode, ctx=ctx))
    steps, accumulated, audit = propagate_with_audit(
        grid, corrections, ITERATIONS, geometry, ctx=ctx, neighbours=neighbours,
        visibility="statistical", flux_budget=budget, reprojection="face-centre")
    want_steps, want_accumulated, want_audit = twin.propagate_audited(
        grid, corrections, ITERATIONS, geometry, neighbours=neighbours,
        visibility="statistical", flux_budget=budget, reprojection="face-centre")
    for step, want in zip(steps, want_steps):
        assert relative_error(step, want) < 1e-4
    assert relative_error(accumulated, want_accumulated) < 1e-4
    assert_audits_match(audit, want_audit)
    normal = twin.propagate(grid, corrections, 1, geometry, neighbours=neighbours,
                            visibility="statistical", flux_budget=budget)
    assert relative_error(steps[1], normal[1]) > 1e-3       # the switch changes the step
    # a cosine lobe's flux does not depend on its axis: the step's flux is the same
    np.testing.assert_allclose(twin.flux(want_steps[1]), twin.flux(normal[1]), rtol=1e-10)


def test_in_place_steps_are_face_centre_schedules(ctx):
    """In place (the DX11 race) every cell's step is the face-centre formula for one of the
    64 read schedules, and not the face-normal one's."""
    corrections = Corrections(ping_pong=False)
    vpls = random_vpls(7, SPEC, 140, outside=5, texel_area=0.05)
    grid = inject(vpls, SPEC, corrections, "points", ctx=ctx)
    steps, _, _ = propagate_with_audit(grid, corrections, 2, ctx=ctx,
                                       reprojection="face-centre")
    assert in_place_schedules(steps, corrections, reprojection="face-centre")[0] < 1e-5
    assert in_place_schedules(steps, corrections)[0] > 1e-3


@pytest.mark.parametrize("neighbours, sh_order", [(6, 1), (26, 1), (26, 2)])
def test_each_neighbour_gets_the_same_flux_kept_more_along_its_way(neighbours, sh_order):
    """One isotropic source cell, one step: every neighbour receives the flux it receives
    with face-normal lobes, its light's mean direction (band 1) points away from the source
    along the offset, and it is more directional (a longer light vector per watt) where the
    faces' centre directions differ from their normals (side, edge and corner faces), the
    same where they agree (a face neighbour's front face)."""
    grid = np.zeros((3, 5, 5, 5, (sh_order + 1) ** 2))
    grid[:, 2, 2, 2, 0] = 1.0
    corrections = Corrections()
    normal = twin.propagation_step(grid, corrections, neighbours=neighbours)[0]
    centre = twin.propagation_step(grid, corrections, neighbours=neighbours,
                                   reprojection="face-centre")[0]
    np.testing.assert_allclose(twin.flux(centre), twin.flux(grid), rtol=1e-12)
    offsets = twin.OFFSETS_26 if neighbours == 26 else [
        o for o in twin.OFFSETS_26 if sum(map(abs, o)) == 1]
    for offset in offsets:
        cell = tuple(2 + o for o in offset)
        got, want = centre[(0, *cell)], normal[(0, *cell)]
        np.testing.assert_allclose(got[0], want[0], rtol=1e-12)       # same flux
        # band 1 is stored (y, z, x) up to sign: sh_basis gives the light vector's axes
        vector = np.array([-got[3], -got[1], got[2]])
        reference = np.array([-want[3], -want[1], want[2]])
        along = np.asarray(offset, np.float64) / np.linalg.norm(offset)
        np.testing.assert_allclose(vector, np.dot(vector, along) * along, atol=1e-12)
        kept, before = np.dot(vector, along) / got[0], np.dot(reference, along) / want[0]
        if neighbours == 6 or sum(map(abs, offset)) > 1:
            assert kept > before * 1.01
        else:
            np.testing.assert_allclose(kept, before, rtol=1e-12)


def test_reprojection_names_its_modes():
    from explorer.lpv.settings import SettingError, Settings

    with pytest.raises(ValueError, match="face-normal, face-centre"):
        twin.reprojection_axis(np.array([1.0, 0.0, 0.0]), np.array([1.0, 0.0, 0.0]), "ray")
    with pytest.raises(SettingError):
        Settings(reprojection="ray")
    assert Settings(reprojection="face-centre").reprojection == "face-centre"


def test_the_web_pages_lpv_refuses_face_centre_reprojection():
    """The web course's live LPV reprojects along face normals only: it shows the baked
    frame instead of a different propagation."""
    from explorer.lpv.settings import Settings
    from explorer.site.live_lpv import unsupported

    assert unsupported(Settings()) is None
    assert unsupported(Settings(reprojection="face-centre")) == "reprojection = 'face-centre'"
