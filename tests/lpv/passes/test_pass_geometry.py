"""Geometry-volume injection on the GPU against the numpy twin."""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import pytest
from lpv_cases import random_vpls, relative_error

from explorer.gl.program import ProgramCache
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.geometry import GeometryPass, GeometryVolume, inject_geometry
from explorer.lpv.settings import Corrections
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.vpl import VplArrays, VplTextures

SPEC = GridSpec(origin=(0.5, -1.0, 0.0), cell_size=0.5, resolution=8)


@pytest.mark.parametrize("mode, squared, projection", list(itertools.product(
    ("one-sided", "double-sided"), (True, False), ("perspective", "orthographic"))))
def test_geometry_volume_matches_the_reference(ctx, mode, squared, projection):
    vpls = replace(random_vpls(7, SPEC, 300, outside=10), projection=projection)
    corrections = Corrections(surfel_area_squared=squared)
    expected = twin.inject_geometry(vpls, SPEC, corrections, mode)
    actual = inject_geometry(vpls, SPEC, corrections, mode, ctx=ctx)
    assert actual.shape == (9, 9, 9, 4)
    assert relative_error(actual, expected) < 1e-5


def test_surfel_sits_on_the_nearest_corner_with_its_area():
    """A surfel just past light-grid corner (2, 3, 4) lands in geometry cell (2, 3, 4);
    at depth 2 its area is texel_area·4 (squared) or texel_area·2 (the published bug)."""
    spec = GridSpec((0.0, 0.0, 0.0), 0.5, 4)
    vpls = VplArrays(np.array([[1.1, 1.4, 2.05]]), np.array([[1.0, 0.0, 0.0]]),
                     np.ones((1, 3)), np.array([2.0]), 0.01)
    for squared, area in ((True, 0.04), (False, 0.02)):
        volume = twin.inject_geometry(vpls, spec, Corrections(surfel_area_squared=squared))
        assert np.argwhere(np.abs(volume).sum(-1) > 0).tolist() == [[2, 3, 4]]
        lobe_x = np.array([np.sqrt(np.pi) / 2, 0.0, 0.0, -np.sqrt(np.pi / 3)])
        assert np.allclose(volume[2, 3, 4], area / 0.25 * lobe_x)


def test_double_sided_blockers_are_isotropic(ctx):
    vpls = random_vpls(8, SPEC, 200)
    volume = inject_geometry(vpls, SPEC, mode="double-sided", ctx=ctx)
    assert np.abs(volume[..., 1:]).max() < 1e-6 * np.abs(volume[..., 0]).max()
    assert volume[..., 0].max() > 0


def test_bad_mode_and_size_are_named(ctx):
    vpls = random_vpls(9, SPEC, 5)
    with pytest.raises(ValueError, match="geometry mode"):
        inject_geometry(vpls, SPEC, mode="off", ctx=ctx)
    with pytest.raises(ValueError, match="geometry mode"):
        twin.inject_geometry(vpls, SPEC, mode="both")
    volume = GeometryVolume(ctx, 4)
    textures = VplTextures.from_arrays(ctx, vpls)
    geometry_pass = GeometryPass(ctx, ProgramCache(ctx))
    try:
        with pytest.raises(ValueError, match="4\\^3 grid"):
            geometry_pass.run(textures, SPEC, Corrections(), "one-sided", volume)
        with pytest.raises(ValueError, match=r"\(5, 5, 5, 4\)"):
            volume.write(np.zeros((4, 4, 4, 4)))
    finally:
        geometry_pass.release()
        textures.release()
        volume.release()


@pytest.mark.parametrize("backend", ["reference", "gpu"])
def test_one_sided_blocker_stops_light_running_into_its_front_only(ctx, backend):
    """Surfels facing +x everywhere: light travelling −x runs into their front side and is
    blocked; light travelling +x leaves their front side and passes (docs/MODEL.md)."""
    from explorer.lpv import propagate

    n = 8
    geometry = np.zeros((n + 1, n + 1, n + 1, 4))
    geometry[...] = twin.cosine_lobe(np.array([1.0, 0.0, 0.0]))  # blocker lobe(+x)
    corrections = Corrections(side_faces=False, clamp_front_face=True)

    def received(direction: int) -> float:
        grid = np.zeros((3, n, n, n, 4))
        grid[:, 4, 4, 4] = twin.cosine_lobe(np.array([float(direction), 0.0, 0.0]))
        if backend == "reference":
            steps = twin.propagate(grid, corrections, 1, geometry=geometry)
        else:
            steps = propagate(grid, corrections, 1, geometry=geometry, ctx=ctx)
        return float(twin.flux(steps[1][:, 4 + direction, 4, 4])[0])

    # The L1 lobe(+x) evaluates to 1/4 + 1/2·cos: B = 3/4 for light running along −x
    # (its reconstruction peak) and clamp(1/4 − 1/2) = 0 for light running along +x.
    unblocked = received_unblocked(corrections)
    assert received(+1) == pytest.approx(unblocked, rel=1e-5)
    assert received(-1) == pytest.approx(0.25 * unblocked, rel=1e-5)


def received_unblocked(corrections: Corrections) -> float:
    n = 8
    grid = np.zeros((3, n, n, n, 4))
    grid[:, 4, 4, 4] = twin.cosine_lobe(np.array([1.0, 0.0, 0.0]))
    steps = twin.propagate(grid, corrections, 1)
    return float(twin.flux(steps[1][:, 5, 4, 4])[0])
