"""The numpy leak-reduction prototype: its gather is the GPU's, its damping does what
the formula says."""

from __future__ import annotations

import numpy as np
import pytest
from lpv_cases import relative_error

from explorer.lpv.grid import GridSpec
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.vpl import VplArrays
from explorer.truth.gbuffer import gbuffer_from_frame
from explorer.truth.leaks import (
    derivative_damping,
    gather_irradiance,
    offset_vpls,
    variant_irradiance,
)


def test_numpy_gather_reproduces_the_pipeline_indirect(ctx):
    settings = Settings(scene="room", width=24, height=20, rsm_size=16, grid_size=8,
                        iterations=2)
    with Pipeline(settings, ctx) as pipeline:
        frame = pipeline.run()
    gbuffer = gbuffer_from_frame(frame, ctx=ctx)
    valid = gbuffer.valid
    irradiance = gather_irradiance(frame.accumulated, frame.grid_spec,
                                   gbuffer.position[valid], gbuffer.normal[valid])
    expected = frame.indirect[valid]
    assert expected.max() > 0
    # relative to the largest value, as tests/lpv/passes/test_pass_gather.py
    assert relative_error(gbuffer.albedo[valid] / np.pi * irradiance, expected) < 1e-5


def test_damping_follows_the_gradient_along_the_normal():
    """An isotropic field growing along +x: no damping for a normal facing +x (light from
    the front), the ratio E(p − ½h·x̂)/E(p + ½h·x̂) for a normal facing −x."""
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 8)
    grid = np.zeros((3, 8, 8, 8, 4))
    # value i + 1 at the centre g = i + ½, so g + ½ anywhere between the edge centres
    grid[..., 0] = (np.arange(8) + 1.0)[None, :, None, None]
    point = np.array([[4.0, 4.0, 4.0]])  # 4.5 here, 4 half a cell towards −x, 5 towards +x
    facing_up = derivative_damping(grid, spec, point, np.array([[1.0, 0.0, 0.0]]))
    facing_down = derivative_damping(grid, spec, point, np.array([[-1.0, 0.0, 0.0]]))
    np.testing.assert_allclose(facing_up, 1.0)
    np.testing.assert_allclose(facing_down, 4.0 / 5.0)


def test_offset_and_variant_checks():
    vpls = VplArrays(np.zeros((1, 3)), np.array([[0.0, 1.0, 0.0]]), np.ones((1, 3)),
                     np.ones(1), 0.01)
    np.testing.assert_allclose(offset_vpls(vpls, 0.25).positions, [[0.0, 0.25, 0.0]])
    with pytest.raises(ValueError, match="variant"):
        variant_irradiance("nope", vpls, GridSpec((0, 0, 0), 1.0, 4), None, 1,
                           np.zeros((1, 3)), np.ones((1, 3)))
