"""Physical and geometric invariants of the GPU injection and propagation."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from lpv_cases import cube_symmetries, random_grid, random_vpls, relative_error, transform_grid

from explorer.lpv import inject, propagate
from explorer.lpv.audit import check_finite
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.propagate import propagate_with_audit
from explorer.lpv.settings import PRESETS, Corrections
from explorer.lpv.vpl import VplArrays


def centred_source(resolution: int, block: int, seed: int, band1: float) -> np.ndarray:
    grid = np.zeros((3,) + (resolution,) * 3 + (4,))
    lo = (resolution - block) // 2
    grid[:, lo:lo + block, lo:lo + block, lo:lo + block] = random_grid(seed, block, band1)
    return grid


def test_corrected_propagation_conserves_flux_away_from_the_border(ctx):
    # band 1 at most 0.1·f0: the intensity is positive in every direction.
    grid = centred_source(16, 4, 21, band1=0.1 / 3)
    corrections = Corrections(clamp_front_face=False)
    _, _, audit = propagate_with_audit(grid, corrections, 4, ctx=ctx)
    assert np.all(audit.border_loss == 0) and np.all(audit.clamp_gain == 0)
    assert np.abs(audit.per_step / audit.injected - 1.0).max() < 1e-5


def test_audit_balances_with_clamp_occlusion_and_border(ctx):
    """per_step[t] = per_step[t−1] + clamp_gain − occluded − border_loss (corrected: the
    30 faces of a step carry exactly the flux of the grid they read)."""
    rng = np.random.default_rng(22)
    grid = random_grid(22, 8, band1=1.0)
    geometry = 0.3 * rng.random((9, 9, 9, 4))
    _, _, audit = propagate_with_audit(grid, Corrections(), 4, geometry, ctx=ctx)
    balance = (audit.per_step[:-1] + audit.clamp_gain - audit.occluded - audit.border_loss)
    assert np.abs(audit.per_step[1:] - balance).max() < 1e-5 * audit.injected.max()
    # Every term is at work in the first step (the clamp acts while band 1 is strong).
    assert audit.clamp_gain[0].min() > 0 and audit.occluded[0].min() > 0
    assert audit.border_loss[0].min() > 0


def test_isotropic_centre_source_is_invariant_under_the_48_cube_symmetries(ctx):
    grid = np.zeros((3, 9, 9, 9, 4))
    grid[:, 4, 4, 4, 0] = [1.0, 2.0, 3.0]
    result = sum(propagate(grid, Corrections(), 4, ctx=ctx))
    symmetries = cube_symmetries()
    assert len({matrix.tobytes() for matrix in symmetries}) == 48
    for matrix in symmetries:
        assert relative_error(transform_grid(result, matrix), result) < 1e-5


@pytest.mark.parametrize("preset", ["corrected", "original"])
def test_propagation_commutes_with_the_48_cube_symmetries(ctx, preset):
    """A directional source at the centre: rotating or mirroring the source (band 1 turns
    like the vector (−f3, −f1, f2)) rotates or mirrors the propagated result."""
    grid = centred_source(8, 2, 23, band1=0.6)
    corrections = PRESETS[preset]
    result = sum(propagate(grid, corrections, 3, ctx=ctx))
    for matrix in cube_symmetries():
        moved = sum(propagate(transform_grid(grid, matrix), corrections, 3, ctx=ctx))
        assert relative_error(moved, transform_grid(result, matrix)) < 1e-5


def test_transform_helper_rotates_a_cosine_lobe_like_its_normal():
    """The symmetry helper itself: a lobe around n, moved by R, is the lobe around R·n."""
    grid = np.zeros((3, 4, 4, 4, 4))
    normal = np.array([0.6, 0.0, 0.8])
    lobe = np.array([np.sqrt(np.pi) / 2, *(np.sqrt(np.pi / 3) * np.array(
        [-normal[1], normal[2], -normal[0]]))])
    grid[:, 0, 1, 2] = lobe
    matrix = cube_symmetries()[17]
    moved = transform_grid(grid, matrix)
    target = np.rint(matrix @ (np.array([0, 1, 2]) - 1.5) + 1.5).astype(int)
    turned = matrix @ normal
    assert np.allclose(moved[0, target[0], target[1], target[2]], [
        np.sqrt(np.pi) / 2, *(np.sqrt(np.pi / 3) * np.array([-turned[1], turned[2], -turned[0]]))])


def test_linear_in_the_injected_flux(ctx):
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 8)
    vpls = random_vpls(24, spec, 100)
    brighter = replace(vpls, flux=2.5 * vpls.flux)
    for corrections in (Corrections(), PRESETS["original"]):
        # Positive scaling commutes with the front-face clamp ...
        base = sum(propagate(inject(vpls, spec, corrections, ctx=ctx), corrections, 3,
                             ctx=ctx))
        scaled = sum(propagate(inject(brighter, spec, corrections, ctx=ctx), corrections, 3,
                               ctx=ctx))
        assert relative_error(scaled, 2.5 * base) < 1e-5
    # ... sums of sources superpose only without it.
    unclamped = Corrections(clamp_front_face=False)
    other = random_vpls(25, spec, 100)
    both = VplArrays(np.vstack([vpls.positions, other.positions]),
                     np.vstack([vpls.normals, other.normals]),
                     np.vstack([vpls.flux, other.flux]),
                     np.concatenate([vpls.depth, other.depth]), vpls.texel_area)
    separate = [sum(propagate(inject(v, spec, unclamped, ctx=ctx), unclamped, 3, ctx=ctx))
                for v in (vpls, other)]
    together = sum(propagate(inject(both, spec, unclamped, ctx=ctx), unclamped, 3, ctx=ctx))
    assert relative_error(together, separate[0] + separate[1]) < 1e-5


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_translating_a_source_by_one_cell_translates_the_result(ctx, axis):
    grid = np.zeros((3, 12, 12, 12, 4))
    grid[:, 4:6, 5, 4:7] = random_grid(26, 3, band1=0.6)[:, :2, 0, :3]
    shifted_source = np.roll(grid, 1, axis=1 + axis)
    # 2 steps spread light 2 cells: from cells 4..6 to 2..8 (3..9 shifted), clear of the
    # border, so the roll does not wrap anything.
    result = sum(propagate(grid, Corrections(), 2, ctx=ctx))
    shifted = sum(propagate(shifted_source, Corrections(), 2, ctx=ctx))
    assert relative_error(shifted, np.roll(result, 1, axis=1 + axis)) < 1e-5


@pytest.mark.parametrize("exact", [True, False])
def test_original_formulas_differ_by_pi_at_injection_and_4pi_per_step(ctx, exact):
    """Original/corrected flux: π at injection (k_I), then a further 1/(4π) per step
    (k_P·k_R·k_I); per_step_original[t] / per_step_corrected[t] = π/(4π)^t. Exactly with the
    same constants; within the published decimals' error (≈3e-5) with the real presets."""
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 8)
    vpls = random_vpls(27, spec, 150)
    corrected = PRESETS["corrected"]
    original = PRESETS["original"]
    if exact:
        original = replace(original, exact_constants=True)
    audits = []
    for corrections in (corrected, original):
        grid = inject(vpls, spec, corrections, ctx=ctx)
        audits.append(propagate_with_audit(grid, corrections, 4, ctx=ctx)[2])
    ratio = audits[1].per_step / audits[0].per_step
    expected = np.pi / (4 * np.pi) ** np.arange(5)[:, None]
    assert np.abs(ratio / expected - 1).max() < (1e-5 if exact else 2e-4)


def test_check_finite_names_the_pass():
    values = np.ones((3, 4, 4, 4, 4), np.float32)
    assert check_finite(values, "propagate") is values
    values[1, 2, 3, 0, 1] = np.nan
    values[2, 0, 0, 0, 0] = np.inf
    with pytest.raises(FloatingPointError, match=r"propagate produced 1 NaN and 1 infinite"
                                                 r".*\(1, 2, 3, 0, 1\)"):
        check_finite(values, "propagate")
