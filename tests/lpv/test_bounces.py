"""More bounces (docs/MODEL.md "More bounces"): the geometry volume reflects the light it
blocks. GPU against the numpy twin, the energy bound and the audit balance."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from lpv_cases import in_place_schedules, random_grid, random_vpls, relative_error

from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.geometry import inject_geometry
from explorer.lpv.passes.propagate import propagate_with_audit
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import PRESETS, Corrections, Settings
from explorer.lpv.twin import light_grid as twin


def random_albedo_sums(rng: np.random.Generator, size: int, top: float = 1.0,
                       empty: float = 0.3) -> np.ndarray:
    """(size³, 4) albedo sums: area w in (0, 1], zero in a fraction ``empty`` of the cells
    (no albedo known there), and rgb = w·albedo with albedo in [0, top]."""
    area = 1.0 - rng.random((size,) * 3)
    area[rng.random(area.shape) < empty] = 0.0
    albedo = top * rng.random((size,) * 3 + (3,))
    return np.concatenate([area[..., None] * albedo, area[..., None]], -1)


def one_sided_geometry(rng: np.random.Generator, size: int) -> np.ndarray:
    """Blockers with a clear normal per cell: w·lobe(n), random n and w."""
    normals = rng.standard_normal((size,) * 3 + (3,))
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    return 0.8 * rng.random((size,) * 3)[..., None] * twin.cosine_lobe(normals)


@pytest.mark.parametrize("corrections", [
    Corrections(), PRESETS["original"], Corrections(ping_pong=False),
    Corrections(side_faces=False, clamp_front_face=False)],
    ids=["corrected", "original", "in-place", "front-only"])
def test_reflection_matches_reference(ctx, corrections):
    rng = np.random.default_rng(51)
    grid = random_grid(51, 6, band1=0.6)
    geometry = one_sided_geometry(rng, 7)
    albedo = random_albedo_sums(rng, 7)
    steps, acc, audit = propagate_with_audit(grid, corrections, 3, geometry, ctx=ctx,
                                             geometry_albedo=albedo, bounces=2)
    expected, expected_acc, expected_audit = twin.propagate_audited(
        grid, corrections, 3, geometry, albedo, bounces=2)
    if corrections.ping_pong:
        for gpu, cpu in zip(steps, expected):
            assert relative_error(gpu, cpu) < 1e-5
        scale = expected_audit.injected.max()
        assert np.abs(audit.reflected - expected_audit.reflected).max() < 1e-5 * scale
        assert np.abs(audit.blocked - expected_audit.blocked).max() < 1e-5 * scale
    else:
        # In place the GPU races by design: which neighbours an invocation reads before or
        # after their update depends on the invocation order. Every cell's step must still
        # be the shader's formula for one of the 64 read schedules (twin.py,
        # in_place_step_candidates), given the GPU's own grid before and after the step.
        worst, _ = in_place_schedules(steps, corrections, geometry, albedo, bounces=2)
        assert worst < 1e-5
        assert relative_error(acc, sum(steps)) < 1e-5
        assert np.allclose(audit.per_step, [twin.flux(step) for step in steps], rtol=1e-4)
    assert expected_audit.reflected.min() > 0
    # Without reflection the same volume gives less light in flight.
    plain = twin.propagate_audited(grid, corrections, 3, geometry, albedo, bounces=1)[2]
    assert np.all(plain.reflected == 0)
    assert np.all(expected_audit.per_step[1:] > plain.per_step[1:]) or not \
        corrections.ping_pong


def test_reflection_is_bounded_by_the_blocked_flux_and_the_audit_balances(ctx):
    """Positive intensities everywhere (small band 1): every blocked flux is >= 0, so the
    flux that can bounce is the occluded flux; with albedo <= 1 the reflected flux is at
    most that, and equal for albedo 1;
    per_step[t] = per_step[t−1] + clamp_gain − occluded − border_loss + reflected."""
    rng = np.random.default_rng(52)
    grid = random_grid(52, 8, band1=0.1 / 3)
    geometry = one_sided_geometry(rng, 9)
    corrections = Corrections()
    for top in (0.7, 1.0):
        albedo = random_albedo_sums(rng, 9, top, empty=0.3 if top < 1 else 0.0)
        if top == 1.0:
            albedo[..., :3] = albedo[..., 3:]          # white: every blocked watt returns
        _, _, audit = propagate_with_audit(grid, corrections, 4, geometry, ctx=ctx,
                                           geometry_albedo=albedo, bounces=2)
        scale = audit.injected.max()
        assert audit.occluded.min() > 0
        assert np.abs(audit.blocked - audit.occluded).max() < 1e-5 * scale
        assert np.all(audit.reflected <= audit.occluded + 1e-5 * scale)
        balance = (audit.per_step[:-1] + audit.clamp_gain - audit.occluded
                   - audit.border_loss + audit.reflected)
        assert np.abs(audit.per_step[1:] - balance).max() < 1e-5 * scale
        # Albedo known on every face and white: everything blocked comes back.
        if top == 1.0:
            assert np.abs(audit.reflected - audit.occluded).max() < 1e-4 * scale
        else:
            assert audit.reflected.sum() < 0.75 * audit.occluded.sum()


def test_geometry_albedo_injection_matches_reference(ctx):
    spec = GridSpec((0.0, 0.0, 0.0), 0.5, 6)
    vpls = random_vpls(53, spec, 80)
    vpls = replace(vpls, albedo=np.random.default_rng(53).random((vpls.count, 3)))
    volume, sums = inject_geometry(vpls, spec, ctx=ctx, with_albedo=True)
    assert relative_error(volume, twin.inject_geometry(vpls, spec)) < 1e-5
    assert relative_error(sums, twin.inject_geometry_albedo(vpls, spec)) < 1e-5
    # the area sums are the geometry volume's coefficient 0 over the lobe's c0
    np.testing.assert_allclose(sums[..., 3] * twin.cosine_lobe(np.eye(3))[0, 0], volume[..., 0],
                               rtol=1e-5, atol=1e-6)


def test_bounces_need_a_geometry_volume(ctx):
    grid = random_grid(54, 4)
    with pytest.raises(ValueError, match="geometry volume"):
        propagate_with_audit(grid, Corrections(), 1, ctx=ctx, bounces=2)
    with pytest.raises(ValueError, match="geometry volume"):
        twin.propagate_audited(grid, Corrections(), 1, bounces=2)
    with pytest.raises(ValueError, match="bounces"):
        twin.propagate_audited(grid, Corrections(), 1, bounces=3)


def test_pipeline_second_bounce_adds_light_within_the_blocked_flux(ctx):
    settings = Settings(scene="cornell", width=24, height=20, rsm_size=16, grid_size=8,
                        iterations=4, geometry_volume="one-sided")
    with Pipeline(settings, ctx) as pipeline:
        one = pipeline.run()
        two = pipeline.run(settings.with_changes(bounces=2))
        assert two.stages_run == ("propagate", "gather", "display")
        # The pipeline's reflection is the reference's, from the RSM's albedo.
        vpls = one.vpls
        assert vpls.albedo is not None and vpls.albedo.max() > 0
        albedo = twin.inject_geometry_albedo(vpls, one.grid_spec)
        grid = twin.inject(vpls, one.grid_spec, offset_cells=settings.injection_offset_cells)
        _, acc, audit = twin.propagate_audited(grid, settings.corrections, 4,
                                              two.geometry_volume, albedo, bounces=2)
        assert relative_error(two.accumulated, acc) < 1e-4
    # Reflected <= blocked (albedo <= 1). The net `occluded` can be smaller than `blocked`:
    # the geometry volume also blocks the negative tails of the L1 lobes (docs/MODEL.md).
    assert np.all(two.audit.reflected <= two.audit.blocked + 1e-6)
    assert two.audit.reflected.sum() > 0.2 * two.audit.blocked.sum()
    assert two.indirect.sum() > one.indirect.sum()
