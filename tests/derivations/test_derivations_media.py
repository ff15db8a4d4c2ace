"""Exact results of derivations/media.py (phase functions, SH factors, single scattering)
and the camera-surfel results of derivations/occlusion.py."""

from __future__ import annotations

import numpy as np
import sympy as sp

from derivations import media, occlusion, rsm
from derivations.registry import get


def test_phase_functions_are_normalised_over_the_sphere():
    assert get("media.isotropic_normalisation").expr == 1
    assert get("media.hg_normalisation").expr == 1
    assert sp.simplify(get("media.isotropic_phase").expr - 1 / (4 * sp.pi)) == 0


def test_hg_band_factors_are_powers_of_g():
    factors = get("media.hg_band_factors").expr
    for band, factor in enumerate(factors):
        assert sp.simplify(factor - media.g**band) == 0
    assert list(get("media.isotropic_band_factors").expr) == [1, 0, 0, 0]
    zonal = get("media.hg_zonal_coefficients").expr
    for band, value in enumerate(zonal):
        expected = media.g**band * sp.sqrt(sp.Rational(2 * band + 1, 4) / sp.pi)
        assert sp.simplify(value - expected) == 0


def test_hg_factors_hold_for_negative_g_numerically():
    """The derivation integrates for 0 < g < 1 and argues the sign by symmetry; check the
    factors for negative g by quadrature (Gauss–Legendre in the cosine)."""
    nodes, weights = np.polynomial.legendre.leggauss(400)
    for g in (-0.7, -0.3, 0.0, 0.45):
        phase = (1 - g * g) / (4 * np.pi * (1 + g * g - 2 * g * nodes) ** 1.5)
        for band in range(4):
            legendre = np.polynomial.legendre.Legendre.basis(band)(nodes)
            factor = 2 * np.pi * np.sum(weights * phase * legendre)
            assert abs(factor - g**band) < 1e-9


def test_single_scattering_of_a_constant_field():
    eq = get("media.segment_inscatter").expr
    expected = media.alpha * media.L_p * (1 - sp.exp(-media.sigma_t * media.ell))
    assert sp.simplify(eq.rhs - expected) == 0
    assert sp.simplify(get("media.transmittance").expr.rhs
                       - sp.exp(-media.sigma_t * media.ell)) == 0


def test_camera_pixel_area_follows_the_rsm_texel_rule():
    """At a 90° field of view and a square image the camera pixel covers exactly what an
    RSM texel of the same resolution covers: 4w²/(W·H)."""
    area = get("occlusion.camera_surfel_area").expr
    at_90 = area.subs({occlusion.fov_y: sp.pi / 2, occlusion.depth: rsm.w,
                       occlusion.height: rsm.H})
    assert sp.simplify(at_90 - rsm.surfel_area().subs(rsm.W, rsm.H)) == 0
    bound = get("occlusion.reprojection_depth_bound").expr
    assert sp.simplify(bound.subs(occlusion.tilt, sp.pi / 4)
                       - sp.sqrt(2) / 2 * occlusion.texel) == 0


def test_statistical_visibility_is_the_limit_of_independent_surfels():
    """exp(−τ) exactly; first order the linear blocker 1 − τ; independent layers multiply;
    never below 1 − τ (their difference is convex with its minimum 0 at τ = 0)."""
    tau = occlusion.coverage
    visibility = get("occlusion.statistical_visibility").expr
    assert sp.simplify(visibility - sp.exp(-tau)) == 0
    assert sp.simplify(get("occlusion.statistical_first_order").expr - (1 - tau)) == 0
    other = sp.Symbol("tau_2", nonnegative=True)
    assert sp.simplify(visibility * visibility.subs(tau, other)
                       - visibility.subs(tau, tau + other)) == 0
    excess = visibility - (1 - tau)
    assert excess.subs(tau, 0) == 0 and sp.diff(excess, tau).subs(tau, 0) == 0
    assert sp.simplify(sp.diff(excess, tau, 2) - sp.exp(-tau)) == 0
