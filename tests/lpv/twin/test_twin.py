"""The numpy twin against hand-derived values of docs/MODEL.md."""

from __future__ import annotations

import itertools
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from lpv_cases import random_grid, random_vpls

from explorer.lpv import constants as K
from explorer.lpv.grid import GridSpec
from explorer.lpv.settings import PRESETS, Corrections
from explorer.lpv.twin import light_grid as R

SPEC = GridSpec((0.0, 0.0, 0.0), 1.0, 8)


def test_injected_flux_is_phi_corrected_and_pi_phi_published():
    vpls = random_vpls(31, SPEC, 50)
    total = vpls.flux.sum(axis=0)
    assert np.allclose(R.flux(R.inject(vpls, SPEC, PRESETS["corrected"])), total)
    assert np.allclose(R.flux(R.inject(vpls, SPEC, PRESETS["original"])), np.pi * total)


def test_one_step_from_an_isotropic_cell_by_hand():
    """Target x+e_x of a lone isotropic source (f0, 0, 0, 0) receives, from direction +x,
    (1/π)·c0·f0·[Δω_front·lobe(+x) + Δω_side·Σ lobe(±y, ±z)]; the four side lobes sum to
    (4·√π/2, 0, 0, 0)."""
    grid = np.zeros((3, 5, 5, 5, 4))
    grid[:, 2, 2, 2, 0] = [1.0, 2.0, 3.0]
    out, _ = R.propagation_step(grid, Corrections())
    intensity = K.SH_C0 * np.array([1.0, 2.0, 3.0])
    lobe_x = np.array([np.sqrt(np.pi) / 2, 0.0, 0.0, -np.sqrt(np.pi / 3)])
    sides = np.array([4 * np.sqrt(np.pi) / 2, 0.0, 0.0, 0.0])
    expected = np.outer(intensity / np.pi,
                        K.FRONT_FACE_SOLID_ANGLE * lobe_x + K.SIDE_FACE_SOLID_ANGLE * sides)
    assert np.allclose(out[:, 3, 2, 2], expected, rtol=1e-12)
    assert np.all(out[:, 2, 2, 2] == 0)     # nothing comes back in one step
    assert np.count_nonzero(np.abs(out).sum(axis=(0, 4))) == 6


@pytest.mark.parametrize("side_faces, propagation_4pi, expected", [
    (True, True, 1.0),
    (True, False, 1.0 / (4 * np.pi)),
    (False, True, 6 * K.FRONT_FACE_SOLID_ANGLE / (4 * np.pi)),
])
def test_flux_factor_of_one_step(side_faces, propagation_4pi, expected):
    grid = np.zeros((3, 10, 10, 10, 4))
    grid[:, 3:7, 3:7, 3:7] = random_grid(32, 4, band1=0.5)
    corrections = Corrections(side_faces=side_faces, propagation_4pi=propagation_4pi,
                              clamp_front_face=False)
    out, terms = R.propagation_step(grid, corrections)
    assert np.allclose(R.flux(out), expected * R.flux(grid), rtol=1e-12)
    assert np.allclose(terms["propagated"], R.flux(out), rtol=1e-12)


def test_reprojection_and_injection_corrections_only_matter_together():
    """k_R·k_I = 1/π in both presets: flipping both leaves a step unchanged, flipping the
    reprojection alone scales it by 1/π."""
    grid = random_grid(33, 6)
    corrected, _ = R.propagation_step(grid, Corrections())
    both, _ = R.propagation_step(grid, Corrections(reprojection_pi=False, injection_pi=False))
    alone, _ = R.propagation_step(grid, Corrections(reprojection_pi=False))
    assert np.allclose(both, corrected, rtol=1e-12, atol=1e-14)
    assert np.allclose(alone, corrected / np.pi, rtol=1e-12, atol=1e-14)


def test_a_blocking_wall_stops_the_light_and_the_audit_counts_it():
    grid = np.zeros((3, 8, 8, 8, 4))
    grid[:, 1:3, 2:6, 2:6] = random_grid(34, 4, band1=0.3)[:, :2]
    wall = np.zeros((9, 9, 9, 4))
    wall[4, ..., 0] = 10.0                      # isotropic blockers on the plane x = 4
    steps, _, audit = R.propagate_audited(grid, Corrections(), 6, wall)
    assert all(np.all(step[:, 4:] == 0) for step in steps)
    assert np.any(steps[2][:, 3] != 0) and audit.occluded[2:].min() > 0
    open_steps = R.propagate(grid, Corrections(), 6)
    assert np.any(open_steps[-1][:, 4:] != 0)


@pytest.mark.parametrize("switches", list(itertools.product((True, False), repeat=4)))
def test_step_balance_for_any_switches(switches):
    names = ("side_faces", "clamp_front_face", "exact_constants", "propagation_4pi")
    corrections = replace(Corrections(), **dict(zip(names, switches)))
    rng = np.random.default_rng(35)
    grid = random_grid(35, 6, band1=1.0)
    geometry = 0.2 * rng.random((7, 7, 7, 4))
    out, terms = R.propagation_step(grid, corrections, geometry)
    balance = terms["propagated"] + terms["clamp_gain"] - terms["occluded"] \
        - terms["border_loss"]
    assert np.allclose(R.flux(out), balance, rtol=1e-12)


def test_in_place_reading_double_counts():
    grid = random_grid(36, 6)
    steps = R.propagate(grid, Corrections(ping_pong=False), 2)
    first, _ = R.propagation_step(grid, Corrections())
    second, _ = R.propagation_step(grid + first, Corrections())
    assert np.allclose(steps[1], first) and np.allclose(steps[2], second)


def test_sh_helpers_hold_the_documented_values():
    direction = np.array([0.0, 0.6, 0.8])
    assert np.allclose(R.sh_basis(direction), [K.SH_C0, -K.SH_C1 * 0.6, K.SH_C1 * 0.8, 0])
    # flux of a unit cosine lobe: ∫ clamp+(cos) dω = π
    lobe = R.cosine_lobe(direction)
    assert np.isclose(R.flux(lobe[None, None, None, None])[0], np.pi)
    # the L1 lobe on its own axis: 1/4 + 1/2 (band 0 + band 1; the exact function gives 1)
    assert np.isclose(lobe @ R.sh_basis(direction), 0.25 + 0.5)


def test_constants_are_the_derivations_not_the_generated_mirror():
    """The reference evaluates its constants from the sympy derivations, so a constant the
    codegen wrote wrongly into both mirrors (explorer/lpv/constants.py and the GLSL) makes
    every GPU-against-reference test fail. It never imports the generated module."""
    script = ("import sys; from explorer.lpv.twin import light_grid as R; "
              "[getattr(R.K, name) for name in R.DerivedConstants.DERIVATIONS]; "
              "print('explorer.lpv.constants' in sys.modules)")
    loaded = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            check=True, cwd=Path(__file__).resolve().parents[3])
    assert loaded.stdout.strip() == "False"
    for name in R.DerivedConstants.DERIVATIONS:   # today both agree to the last bit or two
        assert getattr(R.K, name) == pytest.approx(getattr(K, name), rel=1e-15, abs=0)
    with pytest.raises(AttributeError, match="no derived constant"):
        R.K.SH_C9  # noqa: B018 (reading it is what raises)
