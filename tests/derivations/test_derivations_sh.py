"""SH basis, clamped cosine lobe, flux factor, energy shares; occlusion cancellation."""

from __future__ import annotations

import sympy as sp

from derivations import occlusion, sh
from derivations.registry import get

BANDS = [(0, 0), (1, -1), (1, 0), (1, 1), (2, -2), (2, -1), (2, 0), (2, 1), (2, 2)]


def test_basis_matches_the_spherical_definition():
    assert all(sh.cartesian_matches_definition(b, band, m)
               for b, (band, m) in zip(sh.L2_BASIS, BANDS))


def test_l2_basis_is_orthonormal_exactly():
    assert sh.gram_matrix(sh.L2_BASIS) == sp.eye(9)


def test_monomial_formula_agrees_with_direct_integration():
    theta, phi = sh.theta, sh.phi
    direct = sp.integrate(sp.cos(theta) ** 3 * sp.sin(theta), (theta, 0, sp.pi / 2),
                          (phi, 0, 2 * sp.pi))
    assert direct == sh.sphere_monomial_integral(0, 0, 3, hemisphere=True) == sp.pi / 2
    assert sh.sphere_monomial_integral(2, 0, 0) == 4 * sp.pi / 3


def test_clamped_cosine_coefficients():
    c0, c1, c2, c3 = sh.clamped_cosine_coefficients(sh.L1_BASIS)
    assert (c0, c1, c2, c3) == (sp.sqrt(sp.pi) / 2, 0, sp.sqrt(sp.pi / 3), 0)
    assert get("sh.l2_coslobe_c2").expr == sp.sqrt(5 * sp.pi) / 8


def test_net_flux_kernel_is_band_one_of_the_whole_cosine():
    """∫ z·Y_k dω: only Y10, twice the clamped cosine's band 1 (max(z, 0) − max(−z, 0) = z,
    and the mirrored half flips band 1's sign), and with it Gershun's identity
    E_in = −⟨n, F⟩ + M_out holds for any L1 radiance."""
    coefficients = sh.net_flux_coefficients(sh.L2_BASIS)
    assert coefficients == [0, 0, 2 * sp.sqrt(sp.pi / 3), 0, 0, 0, 0, 0, 0]
    assert sp.simplify(get("sh.net_flux_c1").expr - 2 * get("sh.coslobe_c1").expr) == 0
    s = sp.symbols("s0:4", real=True)
    radiance = sum(si * b for si, b in zip(s, sh.L1_BASIS))
    arriving = sh.integrate_over_sphere(sp.expand(radiance * -sh.z).subs(sh.z, -sh.z),
                                        hemisphere=True)   # travelling towards −z, n = +z
    leaving = sh.integrate_over_sphere(sp.expand(radiance * sh.z), hemisphere=True)
    net = sum(si * c for si, c in zip(s, coefficients[:4]))
    assert sp.simplify(arriving - (-net + leaving)) == 0


def test_lobe_around_any_normal_is_linear_in_n():
    by_rotation = sh.lobe_around_normal_spherical()
    n = (sp.sin(sh.theta) * sp.cos(sh.phi), sp.sin(sh.theta) * sp.sin(sh.phi),
         sp.cos(sh.theta))
    assert all(sp.simplify(a - b) == 0 for a, b in zip(by_rotation, sh.lobe(n)))
    lobe = get("sh.lobe").expr
    assert lobe[1] == -sp.sqrt(sp.pi / 3) * sh.n_y and lobe[3] == -sp.sqrt(sp.pi / 3) * sh.n_x


def test_flux_factor_and_energy_shares():
    assert get("sh.flux_factor").expr == 2 * sp.sqrt(sp.pi)
    assert sh.clamped_cosine_energy() == 2 * sp.pi / 3
    assert get("sh.l1_energy_fraction").expr == sp.Rational(7, 8)
    assert get("sh.l2_energy_fraction").expr == sp.Rational(127, 128)
    # A corrected VPL (Φ/π · lobe) carries exactly Φ (docs/MODEL.md, "Injection").
    phi_p = sp.Symbol("Phi_p", positive=True)
    assert sp.simplify(sh.flux_of(list(phi_p / sp.pi * sh.lobe((0, 0, 1)))) - phi_p) == 0


def test_double_sided_occlusion_cancels_band_one():
    assert occlusion.double_sided_lobe() == sp.ImmutableMatrix([sp.sqrt(sp.pi), 0, 0, 0])
    assert get("occlusion.double_sided_blocking").expr == sp.Rational(1, 2)
    assert occlusion.one_sided((0, 0, 1))[2] == sp.sqrt(sp.pi / 3)


def test_l2_lobe_around_any_normal_matches_the_rotation_integral():
    by_rotation = sh.lobe_around_normal_spherical(sh.L2_BASIS)
    n = (sp.sin(sh.theta) * sp.cos(sh.phi), sp.sin(sh.theta) * sp.sin(sh.phi),
         sp.cos(sh.theta))
    closed = sh.lobe_l2(n)
    assert all(sp.simplify(a - b) == 0 for a, b in zip(by_rotation, closed))
    # The L1 part of the L2 lobe (and basis) is exactly the L1 one.
    assert sh.lobe_l2()[:4] == list(sh.lobe())
    assert sh.L2_BASIS[:4] == sh.L1_BASIS
    assert get("sh.zonal_rotation_factors").expr == sp.ImmutableMatrix(
        [sp.pi, 2 * sp.pi / 3, sp.pi / 4])
    # Band-2 constants of the shaders' lobe: π/4 times the basis constants.
    assert sp.simplify(get("sh.l2_lobe_c2").expr - sp.pi / 4 * sh.L2_C2) == 0
    assert sp.simplify(get("sh.l2_lobe_c3").expr - sp.pi / 4 * sh.L2_C3) == 0
    assert sp.simplify(get("sh.l2_lobe_c4").expr - sp.pi / 4 * sh.L2_C4) == 0
    # A corrected VPL still carries exactly Φ with the L2 lobe (band 2 has no flux).
    phi_p = sp.Symbol("Phi_p", positive=True)
    flux = sh.integrate_over_sphere(sum(
        (phi_p / sp.pi * c * b for c, b in zip(sh.lobe_l2((0, 0, 1)), sh.L2_BASIS)),
        sp.S.Zero))
    assert sp.simplify(flux - phi_p) == 0


def test_bands_one_and_two_cancel_over_the_faces_of_a_step():
    """Flux conservation of an L2 step: only band 0 survives the face sums."""
    from derivations import propagation

    sums = get("propagation.l2_face_basis_sums").expr
    assert sums[:, 0] == sp.ImmutableMatrix([6 * sh.C0] + [0] * 8)
    assert sums[:, 1] == sp.ImmutableMatrix([24 * sh.C0] + [0] * 8)
    assert propagation.face_basis_sums(sh.L1_BASIS)["side"][1:, :] == sp.zeros(3, 1)


def test_band_energy_shares_sum_to_the_order_shares():
    """The clamped cosine's energy by band (the cosine-lobe figure's band table): 3/8,
    1/2 and 15/128, summing to the L1 and L2 shares."""
    shares = [get(f"sh.band{band}_energy_fraction").expr for band in range(3)]
    assert shares == [sp.Rational(3, 8), sp.Rational(1, 2), sp.Rational(15, 128)]
    assert shares[0] + shares[1] == get("sh.l1_energy_fraction").expr
    assert sum(shares) == get("sh.l2_energy_fraction").expr
