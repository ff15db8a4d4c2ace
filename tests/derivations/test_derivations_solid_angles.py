"""Solid angles: both methods per face agree exactly with the closed forms; tiling."""

from __future__ import annotations

import math

import pytest
import sympy as sp

from derivations import solid_angles as sa
from derivations.registry import get

FRONT = 4 * sp.atan(sp.sqrt(11) / 33)
SIDE = 2 * sp.atan(3 * sp.sqrt(11) / 11) - sp.pi / 3


def test_closed_forms_from_the_general_rectangle_formula():
    assert sa.corner_term_is_antiderivative()
    assert sa.front_face() == FRONT
    assert sa.side_face() == SIDE
    assert sa.cube_face() == 2 * sp.pi / 3
    assert get("solid_angles.front_face").expr == FRONT


def test_integration_of_cos_over_r2_gives_the_closed_forms():
    assert sa.outer_antiderivative_is_valid()
    assert sp.simplify(sa.front_face_by_integration() - FRONT) == 0
    assert sp.simplify(sa.side_face_by_integration() - SIDE) == 0


@pytest.mark.parametrize("method, closed", [
    (sa.front_face_by_spherical_trigonometry, FRONT),
    (sa.side_face_by_spherical_trigonometry, SIDE),
])
def test_spherical_excess_agrees_exactly(method, closed):
    by_triangles = method()
    assert by_triangles.has(sp.acos)  # a genuinely different closed form
    proof = sa.prove_equal(by_triangles, closed)
    assert proof.equal, proof.method


def test_both_methods_agree_with_each_other():
    proof = sa.prove_equal(sa.side_face_by_spherical_trigonometry(),
                           sa.side_face_by_integration())
    assert proof.equal


def test_prove_equal_rejects_different_angles():
    assert not sa.prove_equal(FRONT, SIDE).equal


def test_tiling_identity_is_exact():
    proof = sa.tiling_proof()
    assert proof.holds
    assert proof.front_plus_four_sides == 2 * sp.pi / 3
    tiling = get("solid_angles.tiling").expr
    assert isinstance(tiling, sp.Eq) and tiling.rhs == 4 * sp.pi
    assert math.isclose(float(tiling.lhs.doit()), 4 * math.pi, rel_tol=1e-15)


def test_twenty_digit_values():
    assert str(sp.N(FRONT, 20)) == "0.40066968464623918538"
    assert str(sp.N(SIDE, 20)) == "0.42343135443673907673"


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="d > 0"):
        sa.rectangle_solid_angle(0, 1, 0, 1, -1)
    with pytest.raises(ValueError, match="zero vector"):
        sa.unit((0, 0, 0))
    with pytest.raises(ValueError, match="at least 3"):
        sa.spherical_polygon_area([(1, 0, 0), (0, 1, 0)])


def test_rectangle_seen_from_any_point():
    # The side face from the source centre, and the front face from a shifted eye.
    assert sa.axis_aligned_rectangle_solid_angle((0, 0, 0), 0, 1, (1, -1), (3, 1)) == SIDE
    assert sa.axis_aligned_rectangle_solid_angle((5, 5, 5), 2, 8, (4, 4), (6, 6)) == FRONT
    with pytest.raises(ValueError, match="plane"):
        sa.axis_aligned_rectangle_solid_angle((0, 0, 1), 2, 1, (0, 0), (1, 1))


def test_module_examples_run():
    import doctest

    from derivations import corrections, errata, occlusion, propagation, registry, rsm, sh

    for module in (sa, sh, rsm, corrections, propagation, occlusion, errata, registry):
        assert doctest.testmod(module).failed == 0, module.__name__


def test_the_readable_texel_solid_angle_is_the_exact_one():
    """The lesson's form of Δω_ij (four corner terms F at the texel's edges) is exactly the
    rectangle formula on the texel (rsm.pixel_solid_angle_exact)."""
    import sympy as sp

    from derivations import rsm

    assert sp.simplify(rsm.corners_substituted() - rsm.pixel_solid_angle_exact()) == 0
