"""The geometry volume's statistical visibility and the flux budget (docs/MODEL.md "Geometry
volume", "Flux budget"): GPU against the numpy twin on odd grids, and what each must hold
physically (open space passes everything, visibility falls with coverage; under the budget
no step creates flux)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from lpv_cases import assert_audits_match, random_grid, random_vpls, relative_error

from explorer.lpv import inject
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.geometry import inject_geometry
from explorer.lpv.passes.propagate import propagate_with_audit
from explorer.lpv.settings import PRESETS, Corrections
from explorer.lpv.twin import light_grid as twin

SPEC = GridSpec(origin=(0.0, 0.0, 0.0), cell_size=0.5, cells=(9, 5, 7))
ITERATIONS = 3


def _frame(ctx, sh_order, geometry_mode, corrections):
    vpls = random_vpls(7, SPEC, 140, outside=5, texel_area=0.05)
    grid = inject(vpls, SPEC, corrections, "points", ctx=ctx, sh_order=sh_order)
    geometry = (None if geometry_mode is None
                else inject_geometry(vpls, SPEC, corrections, geometry_mode, ctx=ctx))
    return grid, geometry


@pytest.mark.parametrize("sh_order, geometry_mode, neighbours",
                         [(1, "one-sided", 6), (1, "double-sided", 26), (2, "one-sided", 6),
                          (2, "double-sided", 26)])
def test_gpu_matches_the_twin_with_statistical_visibility(ctx, sh_order, geometry_mode,
                                                         neighbours):
    corrections = Corrections()
    grid, geometry = _frame(ctx, sh_order, geometry_mode, corrections)
    steps, accumulated, audit = propagate_with_audit(
        grid, corrections, ITERATIONS, geometry, ctx=ctx, neighbours=neighbours,
        visibility="statistical")
    want_steps, want_accumulated, want_audit = twin.propagate_audited(
        grid, corrections, ITERATIONS, geometry, neighbours=neighbours,
        visibility="statistical")
    for step, want in zip(steps, want_steps):
        assert relative_error(step, want) < 1e-4
    assert relative_error(accumulated, want_accumulated) < 1e-4
    assert_audits_match(audit, want_audit)
    linear = twin.propagate_audited(grid, corrections, ITERATIONS, geometry,
                                    neighbours=neighbours)[2]
    # exp(−τ) ≥ 1 − clamp(τ, 0, 1): the statistical volume blocks less, never more
    assert 0 < audit.occluded[0].sum() < linear.occluded[0].sum()


@pytest.mark.parametrize("sh_order, geometry_mode, neighbours, clamp",
                         [(1, None, 6, True), (1, "one-sided", 6, False), (1, None, 26, True),
                          (2, None, 6, False), (2, "double-sided", 26, True)])
def test_gpu_matches_the_twin_under_the_flux_budget(ctx, sh_order, geometry_mode, neighbours,
                                                   clamp):
    corrections = Corrections(clamp_front_face=clamp)
    grid, geometry = _frame(ctx, sh_order, geometry_mode, corrections)
    steps, accumulated, audit = propagate_with_audit(
        grid, corrections, ITERATIONS, geometry, ctx=ctx, neighbours=neighbours,
        flux_budget=True)
    want_steps, want_accumulated, want_audit = twin.propagate_audited(
        grid, corrections, ITERATIONS, geometry, neighbours=neighbours, flux_budget=True)
    for step, want in zip(steps, want_steps):
        assert relative_error(step, want) < 1e-4
    assert relative_error(accumulated, want_accumulated) < 1e-4
    assert_audits_match(audit, want_audit)
    free = twin.propagate_audited(grid, corrections, ITERATIONS, geometry,
                                  neighbours=neighbours)[0]
    assert relative_error(steps[1], free[1]) > 1e-3        # the switch changes the step


def test_statistical_visibility_is_one_in_open_space_and_falls_with_coverage():
    """τ = 0 passes everything; V falls strictly as a surfel facing the light covers more
    of the face; two independent layers pass the product of their chances; it is never
    below the linear blocker and reaches 0 only as the coverage grows without bound."""
    towards = np.array([1.0, 0.0, 0.0])
    facing = twin.cosine_lobe(-towards)          # a surfel facing the light's travel
    blockers = np.array([0.0, 0.25, 0.5, 1.0, 2.0, 8.0, 40.0])[:, None] * facing
    tau = blockers @ twin.sh_basis(-towards)
    statistical = twin.face_visibility(blockers, towards, "statistical")
    linear = twin.face_visibility(blockers, towards, "linear")
    assert statistical[0] == 1.0 and linear[0] == 1.0
    assert np.all(np.diff(statistical) < 0)
    assert np.all(statistical >= linear) and linear[tau >= 1.0].max() == 0.0
    assert statistical[-1] < 1e-6
    np.testing.assert_allclose(twin.face_visibility(blockers[1:2] + blockers[2:3], towards,
                                                    "statistical"),
                               statistical[1] * statistical[2], rtol=1e-12)
    np.testing.assert_allclose(statistical, np.exp(-tau), rtol=1e-12)
    # a surfel facing the other way (the light runs into its back) does not block
    behind = twin.face_visibility(4.0 * twin.cosine_lobe(towards)[None], towards,
                                  "statistical")
    assert behind[0] == 1.0
    with pytest.raises(ValueError, match="linear, statistical"):
        twin.face_visibility(blockers, towards, "chebyshev")


@pytest.mark.parametrize("neighbours, coefficients", [(6, 4), (6, 9), (26, 4), (26, 9)])
def test_no_step_creates_flux_under_the_budget(neighbours, coefficients):
    """Every cell of grid t sums faces that send clamp+ intensity scaled to at most the
    source's flux: per step, flux(grid_t) + border loss + occluded ≤ flux(grid_{t−1}) and
    no cell's flux is negative. The audit books the clamp+ of every face as clamp gain and
    the factor's cut as its own term, withheld (≥ 0); with the corrected weights the
    faces sum to the cell's flux, so the budget withholds exactly what the clamp adds.
    Without the budget the same grid gains flux in its first step."""
    rng = np.random.default_rng(11)
    grid = random_grid(4, 7, band1=1.2) if coefficients == 4 else np.concatenate(
        [random_grid(4, 7, band1=1.2), 0.6 * rng.standard_normal((3, 7, 7, 7, 5))], -1)
    geometry = np.abs(rng.normal(0.0, 0.3, (8, 8, 8, 4)))
    steps, _, audit = twin.propagate_audited(grid, Corrections(), 6, geometry,
                                             neighbours=neighbours, flux_budget=True)
    for t in range(1, len(steps)):
        left = audit.per_step[t] + audit.border_loss[t - 1] + audit.occluded[t - 1]
        assert np.all(left <= audit.per_step[t - 1] * (1 + 1e-12))
        assert np.all(audit.clamp_gain[t - 1] >= 0)
        assert np.all(np.abs(audit.budget_withheld[t - 1] - audit.clamp_gain[t - 1])
                      <= 1e-10 * audit.per_step[t - 1])
        # corrected weights: the faces sum to the cell's flux, so the budget keeps it all
        np.testing.assert_allclose(left, audit.per_step[t - 1], rtol=1e-10)
        cell_flux = twin.K.SH_FLUX_FACTOR * steps[t][..., 0]
        assert cell_flux.min() >= -1e-12
    assert np.all(audit.budget_withheld[0] > 0)           # grid_0 rings: the budget cuts
    free = twin.propagate_audited(grid, Corrections(), 1, neighbours=neighbours)[2]
    assert np.all(free.per_step[1] + free.border_loss[0] > free.per_step[0])
    assert np.all(free.budget_withheld == 0)
    # published weights: the faces sum to less than the cell holds; still nothing grows
    original = Corrections(propagation_4pi=False, exact_constants=False)
    steps, _, audit = twin.propagate_audited(grid, original, 2, neighbours=neighbours,
                                             flux_budget=True)
    assert np.all(audit.per_step[1:] + audit.border_loss <= audit.per_step[:-1])
    scale = twin.flux_budget_scale(grid, Corrections(), neighbours)
    assert scale.max() <= 1.0 and scale.min() < 1.0


BUDGET_CASES = {"corrected": Corrections(), "original": PRESETS["original"],
                "original, no clamp": replace(PRESETS["original"], clamp_front_face=False)}


@pytest.mark.parametrize("name", list(BUDGET_CASES))
@pytest.mark.parametrize("flux_budget", [False, True])
def test_the_step_balances_with_the_budget_withheld_as_its_own_term(name, flux_budget):
    """flux(grid_t) = propagated + clamp gain − withheld − occluded − border loss, to
    rounding, with the budget on or off; the withheld term is exactly 0 off, and on it
    is (1 − β)·S per source cell, the flux the clamped faces would send beyond Φ."""
    corrections = BUDGET_CASES[name]
    rng = np.random.default_rng(5)
    # a strong band 1: the published faces send more than some cells hold
    grid = random_grid(9, 7, band1=3.0)
    geometry = np.abs(rng.normal(0.0, 0.3, (8, 8, 8, 4)))
    out, terms = twin.propagation_step(grid, corrections, geometry, flux_budget=flux_budget)
    balance = (terms["propagated"] + terms["clamp_gain"] - terms["budget_withheld"]
               - terms["occluded"] - terms["border_loss"])
    np.testing.assert_allclose(twin.flux(out), balance, rtol=1e-12)
    if not flux_budget:
        assert np.all(terms["budget_withheld"] == 0)
        return
    beta = twin.flux_budget_scale(grid, corrections)
    held = np.maximum(twin.K.SH_FLUX_FACTOR * grid[..., 0], 0.0)
    positive = held / np.where(beta < 1, beta, np.inf)          # S where the budget cuts
    want = np.where(beta < 1, positive - held, 0.0).reshape(3, -1).sum(1)
    np.testing.assert_allclose(terms["budget_withheld"], want, rtol=1e-10)
    assert np.all(terms["budget_withheld"] > 0)


@pytest.mark.parametrize("name", list(BUDGET_CASES))
def test_gpu_books_the_budget_withheld_as_the_twin_on_an_odd_grid(ctx, name):
    """The GPU's withheld term equals the twin's step by step (9×5×7 cells, three steps),
    and its audit closes: with the corrected weights (propagated = flux of grid t−1)
    flux(grid_t) = flux(grid_t−1) + clamp gain − withheld − occluded − border loss."""
    corrections = BUDGET_CASES[name]
    grid, geometry = _frame(ctx, 1, "one-sided", corrections)
    _, _, audit = propagate_with_audit(grid, corrections, ITERATIONS, geometry, ctx=ctx,
                                       flux_budget=True)
    _, _, want = twin.propagate_audited(grid, corrections, ITERATIONS, geometry,
                                        flux_budget=True)
    scale = float(np.abs(want.injected).max())
    assert np.abs(audit.budget_withheld - want.budget_withheld).max() <= 1e-4 * scale
    assert_audits_match(audit, want)
    if name == "corrected":
        balance = (audit.per_step[:-1] + audit.clamp_gain - audit.budget_withheld
                   - audit.occluded - audit.border_loss)
        assert np.abs(audit.per_step[1:] - balance).max() <= 1e-5 * scale
        assert np.all(audit.budget_withheld > 0)
    off = propagate_with_audit(grid, corrections, ITERATIONS, geometry, ctx=ctx)[2]
    assert np.all(off.budget_withheld == 0)


def test_flux_budget_needs_ping_pong_and_one_bounce():
    from explorer.lpv.settings import SettingError, Settings

    grid = np.zeros((3, 5, 5, 5, 4))
    with pytest.raises(ValueError, match="ping_pong"):
        twin.propagation_step(grid, Corrections(ping_pong=False), flux_budget=True)
    with pytest.raises(SettingError, match="bounces 2"):
        Settings(flux_budget=True, bounces=2, geometry_volume="one-sided")
    assert Settings(flux_budget=True).flux_budget


def test_the_budget_pass_covers_every_slab_of_a_step(ctx, monkeypatch):
    """A step dispatched in two slabs reads the factors the budget pass wrote for the
    whole grid before its first slab."""
    from explorer.lpv.passes import propagate as propagate_pass

    monkeypatch.setattr(propagate_pass, "SLAB_CELLS", 9 * 5 * 4)
    assert len(propagate_pass.slabs(SPEC.cells)) == 2
    corrections = Corrections()
    grid, _ = _frame(ctx, 1, None, corrections)
    steps, _, _ = propagate_with_audit(grid, corrections, ITERATIONS, ctx=ctx,
                                       flux_budget=True)
    want = twin.propagate(grid, corrections, ITERATIONS, flux_budget=True)
    for step, expected in zip(steps, want):
        assert relative_error(step, expected) < 1e-4


def test_the_web_pages_lpv_refuses_what_it_has_no_form_for():
    """The web course's live LPV (explorer/site/live_lpv.py) has neither switch, so it
    shows the baked frame instead of a different propagation."""
    from explorer.lpv.settings import Settings
    from explorer.site.live_lpv import unsupported

    assert unsupported(Settings()) is None
    assert unsupported(Settings(flux_budget=True)) == "flux_budget = True"
    assert unsupported(Settings(geometry_visibility="statistical")) is None   # no volume
    assert unsupported(Settings(geometry_visibility="statistical",
                                geometry_volume="one-sided")) == \
        "geometry_visibility = 'statistical'"
