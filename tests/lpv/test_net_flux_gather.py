"""The net-flux gather (docs/MODEL.md "Net-flux gather"): GPU against the numpy twin with
the switch on, and the Settings' refusals."""

from __future__ import annotations

import numpy as np
import pytest
from lpv_cases import relative_error

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.twin.light_grid import K
from explorer.truth.gbuffer import gbuffer_from_frame

SMALL = dict(width=48, height=40, rsm_size=16, grid_size=8, iterations=2)


def _frame(ctx, **changes):
    settings = Settings(**SMALL).with_changes(**changes)
    with Pipeline(settings, ctx) as pipeline:
        return pipeline.run()


@pytest.mark.parametrize("scene, sh_order, damping", [
    ("cornell", 1, False), ("cornell", 2, False), ("room", 1, True)])
def test_net_flux_gather_matches_the_numpy_gather(ctx, scene, sh_order, damping):
    frame = _frame(ctx, scene=scene, sh_order=sh_order, gather_damping=damping,
                   gather_net_flux=True)
    gbuffer = gbuffer_from_frame(frame, ctx=ctx)
    valid = gbuffer.valid
    # The surfaces' own exitance a·E_direct: π times the GPU's direct radiance a/π·E_direct.
    exitance = K.PI * np.asarray(frame.direct, np.float64)[valid]
    positions, normals = gbuffer.position[valid], gbuffer.normal[valid]
    irradiance = twin.gather(frame.accumulated, frame.grid_spec, positions, normals,
                             damping=damping, exitance=exitance)
    expected = twin.indirect_radiance(gbuffer.albedo[valid], irradiance)
    assert expected.max() > 0
    assert relative_error(frame.indirect[valid], expected) < 1e-5   # as test_pass_gather.py
    lobe = twin.indirect_radiance(gbuffer.albedo[valid], twin.gather(
        frame.accumulated, frame.grid_spec, positions, normals, damping=damping))
    assert relative_error(lobe, expected) > 0.05      # the switch changes the gather


def test_net_flux_kernel_is_the_light_vector():
    """A unit of radiance along ω₀ projects to s = Y(ω₀), and ⟨s, kernel(d)⟩ must be its
    first moment ⟨d, ω₀⟩ exactly: the kernel integrates ⟨d, ω⟩ against the radiance."""
    rng = np.random.default_rng(3)
    directions = rng.normal(size=(20, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    for order in (1, 2):
        kernel = twin.net_flux_kernel(directions, order)
        basis = twin.sh_basis(directions[::-1], order)
        got = np.einsum("pk,pk->p", basis, kernel)
        cosines = np.einsum("pk,pk->p", directions[::-1], directions)
        assert np.allclose(got, cosines, rtol=0, atol=1e-12)


@pytest.mark.parametrize("changes", [
    {"cascades": 2}, {"corrections": {"irradiance_gather": False}}])
def test_settings_refuse_the_net_flux_gather_where_it_has_no_meaning(changes):
    with pytest.raises(ValueError, match="gather_net_flux needs cascades 1"):
        Settings(gather_net_flux=True).with_changes(**changes)
    with pytest.raises(ValueError, match="gather_net_flux"):
        Settings(gather_net_flux=1)
