"""Each correction's flux identity, the step flux factor, faces and RSM results."""

from __future__ import annotations

import math

import pytest
import sympy as sp

from derivations import corrections as cr
from derivations import propagation as pr
from derivations import rsm
from derivations.registry import all_results, get, latex


def test_required_names_exist_with_formulas():
    for key in cr.KEYS:
        original = get(f"corrections.{key}.original").expr
        corrected = get(f"corrections.{key}.corrected").expr
        assert isinstance(original, sp.Eq) and isinstance(corrected, sp.Eq)
        assert original.lhs == corrected.lhs
        assert "=" in latex(f"corrections.{key}.corrected")
    assert get("corrections.injection_pi.flux_factor").expr == 1 / sp.pi
    assert get("corrections.propagation_4pi.flux_factor").expr == 4 * sp.pi
    assert get("corrections.reprojection_pi.flux_factor").expr == sp.pi


def test_flux_identities():
    ids = cr.flux_identities()
    inj = ids["injection_pi"]
    assert inj["emitted_original"] == sp.pi * cr.Phi_p
    assert inj["emitted_corrected"] == inj["should_be"] == cr.Phi_p
    prop = ids["propagation_4pi"]
    assert prop["through_face_corrected"] == prop["should_be"]
    assert sp.simplify(prop["through_face_original"] / prop["should_be"]) == 1 / (4 * sp.pi)
    rep = ids["reprojection_pi"]
    assert rep["reprojected_corrected"] == rep["should_be"] == cr.Phi_f
    assert rep["reprojected_original"] == cr.Phi_f / sp.pi


def test_step_flux_factor():
    assert get("propagation.step_flux_factor").expr == sp.pi * pr.k_R * pr.k_I * pr.k_P
    assert get("propagation.step_flux_factor_original").expr == 1 / (4 * sp.pi)
    assert get("propagation.step_flux_factor_corrected").expr == 1
    # The reprojection fix alone changes the result by π (docs/MODEL.md).
    assert pr.step_flux_factor_for(True, True, False) == 1 / sp.pi
    dx11 = get("propagation.step_flux_factor_dx11").expr
    assert float(dx11) == pytest.approx(0.3652176137625, rel=1e-12)


def test_faces_and_directions():
    assert get("propagation.side_eval_direction").expr == sp.ImmutableMatrix(
        [1 / sp.sqrt(5), 2 / sp.sqrt(5), 0])
    faces = pr.faces((0, 0, 1))
    assert [f.kind for f in faces] == ["front"] + ["side"] * 4
    for face in faces[1:]:
        assert face.evaluation.norm() == 1 and face.reprojection.dot(sp.Matrix([0, 0, 1])) == 0
        assert face.evaluation.dot(face.reprojection) == 1 / sp.sqrt(5)
    with pytest.raises(ValueError, match="perpendicular"):
        pr.side_evaluation_direction((0, 1, 0), (0, 1, 0))


def test_rsm_texel_flux_erratum_cancels_the_cosine():
    """A texel of solid angle ρ sees a surfel of area ρr²/cos θ_i: its flux has no cosine,
    and the published form is off by exactly cos θ_i (docs/MODEL.md, RSM erratum)."""
    theta = sp.Symbol("theta_i", nonnegative=True)
    per_texel = rsm.texel_flux_steps()[-1].rhs
    assert sp.simplify(per_texel - rsm.c_diff * rsm.texel_omega * rsm.Phi_L / (4 * sp.pi)) == 0
    assert sp.simplify(get("rsm.texel_flux_published_over_correct").expr - sp.cos(theta)) == 0


def test_rsm_outgoing_flux_chain():
    steps = rsm.outgoing_flux_steps()
    assert steps[2].rhs == sp.pi * steps[1].rhs  # M = π L_o
    expected = rsm.c_diff * rsm.texel_omega / (4 * sp.pi) * rsm.Phi_L * rsm.clamped_cos_i
    assert sp.simplify(steps[-1].rhs - expected) == 0
    assert get("rsm.surfel_area").expr == 4 * rsm.w**2 / (rsm.W * rsm.H)


def test_pixel_solid_angle_errors_on_a_512_map():
    errors = rsm.pixel_solid_angle_errors(512)
    assert errors.total_exact == pytest.approx(2 * math.pi / 3, rel=1e-12)
    assert errors.min_ratio == pytest.approx(math.pi / 6, rel=1e-3)      # centre
    assert errors.max_ratio == pytest.approx(math.sqrt(3) * math.pi / 2, rel=1e-2)  # corner
    assert errors.max_relative_error == pytest.approx(1.7101, abs=1e-3)
    assert errors.mean_relative_error == pytest.approx(0.3624, abs=1e-3)
    assert get("rsm.pixel_ratio_centre").expr == sp.pi / 6
    assert get("rsm.pixel_ratio_corner").expr == sp.sqrt(3) * sp.pi / 2
    with pytest.raises(ValueError, match="size"):
        rsm.pixel_solid_angle_errors(0)


def test_registry_names_and_unknown_name():
    names = [r.name for r in all_results()]
    assert len(names) == len(set(names))
    assert all(r.statement and r.name.startswith(r.module + ".") for r in all_results())
    with pytest.raises(KeyError, match="solid_angles.front_face"):
        get("solid_angles.front_fac")
