r"""Real spherical harmonics up to band 2, the clamped cosine lobe, and flux.

Basis (annotations §4.2, docs/MODEL.md), for a unit direction ``ω = (x, y, z)``:

.. math:: Y = \Bigl(c_0,\; -c_1 y,\; c_1 z,\; -c_1 x\Bigr), \qquad
          c_0 = \frac{1}{2\sqrt\pi},\; c_1 = \frac{\sqrt3}{2\sqrt\pi}

and band 2 in the same (Condon–Shortley) convention, derived from the definition
:math:`Y_l^m = \Phi^m(\phi) N_l^{|m|} P_l^{|m|}(\cos\theta)` (DX12 blog):
``(c2·xy, −c2·yz, c3·(3z²−1), −c2·xz, c4·(x²−y²))`` with ``c2 = √15/(2√π)``,
``c3 = √5/(4√π)``, ``c4 = √15/(4√π)``.

Integrals over the sphere are exact: a polynomial in ``x, y, z`` integrates monomial by
monomial with (Folland 2001)

.. math:: \int_{S^2} x^a y^b z^c\,d\omega = \frac{2\,\Gamma(\alpha)\Gamma(\beta)\Gamma(\gamma)}
          {\Gamma(\alpha+\beta+\gamma)},\quad \alpha = \tfrac{a+1}{2},\ \ldots

(0 unless a, b, c are all even); over the upper hemisphere ``z > 0`` the factor 2 drops
and ``c`` may be odd. This makes orthonormality, the lobe coefficients and energies
instant and exact.

Clamped cosine lobe around ``+z``: ``(√π/2, 0, √(π/3), 0)``; around any unit ``n``
(rotate: ``∫ clamp⁺⟨n,ω⟩ Y(ω) dω = ∫ clamp⁺(z') Y(R ω') dω'`` with ``R e_z = n``):
``(√π/2, −√(π/3) n_y, √(π/3) n_z, −√(π/3) n_x)``, linear in ``n`` (annotations §4.3).
With band 2 (:func:`lobe_l2`) the lobe is ``A_l·Y_k(n)``, ``A = (π, 2π/3, π/4)``, and its
first four coefficients are the L1 lobe. Its energy ``∫ clamp⁺(cos)² dω = 2π/3``; L1
keeps ``7/8`` of it and L2 ``127/128``.
The flux of an intensity SH vector ``f`` is ``∫ f·Y dω = 2√π·f_0``.

Examples
--------
>>> from derivations.sh import clamped_cosine_coefficients, L1_BASIS
>>> clamped_cosine_coefficients(L1_BASIS)
(sqrt(pi)/2, 0, sqrt(3)*sqrt(pi)/3, 0)

References
----------
A. Kirsch, "Light Propagation Volumes — Annotations" (2010), §4.2–4.3.
P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks" (GDC 2008).
G. B. Folland, "How to integrate a polynomial over a sphere", Amer. Math. Monthly 108 (2001).
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache

import sympy as sp

from derivations.registry import Result, result

MODULE = "sh"

x, y, z = sp.symbols("x y z", real=True)
theta, phi = sp.symbols("theta phi", real=True)
n_x, n_y, n_z = sp.symbols("n_x n_y n_z", real=True)

C0 = 1 / (2 * sp.sqrt(sp.pi))
C1 = sp.sqrt(3) / (2 * sp.sqrt(sp.pi))
L2_C2 = sp.sqrt(15) / (2 * sp.sqrt(sp.pi))
L2_C3 = sp.sqrt(5) / (4 * sp.sqrt(sp.pi))
L2_C4 = sp.sqrt(15) / (4 * sp.sqrt(sp.pi))

L1_BASIS: tuple[sp.Expr, ...] = (C0, -C1 * y, C1 * z, -C1 * x)
"""L1 basis in the annotations' order and signs: (Y00, Y1-1, Y10, Y11)."""
L2_BAND: tuple[sp.Expr, ...] = (
    L2_C2 * x * y, -L2_C2 * y * z, L2_C3 * (3 * z**2 - 1), -L2_C2 * x * z,
    L2_C4 * (x**2 - y**2))
"""Band 2, m = -2..2, same convention."""
L2_BASIS: tuple[sp.Expr, ...] = L1_BASIS + L2_BAND
"""The 9 real SH up to band 2."""

_SPHERICAL = {x: sp.sin(theta) * sp.cos(phi), y: sp.sin(theta) * sp.sin(phi), z: sp.cos(theta)}


def real_sh_spherical(band: int, m: int) -> sp.Expr:
    """``Y_l^m(θ, φ) = Φ^m(φ)·N_l^{|m|}·P_l^{|m|}(cos θ)`` (DX12 blog's definition; sympy's
    ``assoc_legendre`` carries the Condon–Shortley phase)."""
    if not (band >= 0 and -band <= m <= band):
        raise ValueError(f"need band l >= 0 and -l <= m <= l, got l={band}, m={m}")
    k = abs(m)
    norm = sp.sqrt(sp.Rational(2 * band + 1, 4) / sp.pi * sp.factorial(band - k)
                   / sp.factorial(band + k))
    azimuth = (sp.sqrt(2) * sp.cos(k * phi) if m > 0 else
               sp.sqrt(2) * sp.sin(k * phi) if m < 0 else sp.S.One)
    return azimuth * norm * sp.assoc_legendre(band, k, sp.cos(theta))


def cartesian_matches_definition(cartesian: sp.Expr, band: int, m: int) -> bool:
    """Exact check that a Cartesian basis polynomial is :func:`real_sh_spherical` (band, m)."""
    on_sphere = cartesian.subs(_SPHERICAL, simultaneous=True)
    # sin θ = √(1 − cos²θ) holds for the polar angle θ ∈ [0, π].
    definition = real_sh_spherical(band, m).subs(sp.sqrt(1 - sp.cos(theta)**2), sp.sin(theta))
    gap = sp.simplify(sp.expand_trig(on_sphere - definition))
    return gap == 0


def sphere_monomial_integral(a: int, b: int, c: int, hemisphere: bool = False) -> sp.Expr:
    """``∫ x^a y^b z^c dω`` over the unit sphere, or the hemisphere ``z > 0`` (Folland)."""
    if min(a, b, c) < 0:
        raise ValueError(f"exponents must be >= 0, got {(a, b, c)}")
    if a % 2 or b % 2 or (c % 2 and not hemisphere):
        return sp.S.Zero
    alpha, beta, gamma = (sp.Rational(e + 1, 2) for e in (a, b, c))
    value = sp.gamma(alpha) * sp.gamma(beta) * sp.gamma(gamma) / sp.gamma(alpha + beta + gamma)
    return sp.simplify(value if hemisphere else 2 * value)


@cache
def integrate_over_sphere(polynomial: sp.Expr, hemisphere: bool = False) -> sp.Expr:
    """Exact ``∫ p(ω) dω`` of a polynomial in ``x, y, z`` (coefficients may be symbolic);
    kept by its polynomial (expressions are immutable): the derivations integrate the
    same lobes again and again (``constants --json`` spent 9 of its 31 s here)."""
    poly = sp.Poly(sp.expand(polynomial), x, y, z)
    total = sp.S.Zero
    for (a, b, c), coefficient in poly.terms():
        total += coefficient * sphere_monomial_integral(a, b, c, hemisphere)
    return sp.simplify(total)


def gram_matrix(basis: Sequence[sp.Expr]) -> sp.Matrix:
    """``G_ij = ∫ Y_i Y_j dω``; the identity for an orthonormal basis."""
    n = len(basis)
    return sp.Matrix(n, n, lambda i, j: integrate_over_sphere(basis[i] * basis[j]))


def clamped_cosine_coefficients(basis: Sequence[sp.Expr]) -> tuple[sp.Expr, ...]:
    """SH projection of ``clamp⁺(z)``: ``∫_{z>0} z·Y_k dω`` for each basis function."""
    return _clamped_cosine(tuple(basis))


@cache
def _clamped_cosine(basis: tuple[sp.Expr, ...]) -> tuple[sp.Expr, ...]:
    return tuple(integrate_over_sphere(z * b, hemisphere=True) for b in basis)


@cache
def lobe_around_normal_spherical(basis: tuple[sp.Expr, ...] = L1_BASIS) -> tuple[sp.Expr, ...]:
    """Projection of ``clamp⁺⟨n, ω⟩`` onto ``basis`` (default L1) for
    ``n = (sinθ cosφ, sinθ sinφ, cosθ)`` (all unit n).

    Change of variables ``ω = R ω'`` with ``R = R_z(φ) R_y(θ)`` (so ``R e_z = n``; the
    measure is rotation invariant): ``∫ clamp⁺(z') Y_k(R ω') dω'`` is a hemisphere integral
    of a polynomial in ``ω'``.
    """
    rot_y = sp.Matrix([[sp.cos(theta), 0, sp.sin(theta)], [0, 1, 0],
                       [-sp.sin(theta), 0, sp.cos(theta)]])
    rot_z = sp.Matrix([[sp.cos(phi), -sp.sin(phi), 0], [sp.sin(phi), sp.cos(phi), 0],
                       [0, 0, 1]])
    rotated = (rot_z * rot_y) * sp.Matrix([x, y, z])
    subs = {x: rotated[0], y: rotated[1], z: rotated[2]}
    return tuple(sp.simplify(integrate_over_sphere(z * b.subs(subs, simultaneous=True),
                                                   hemisphere=True))
                 for b in basis)


def lobe(normal: Sequence[sp.Expr] = (n_x, n_y, n_z)) -> sp.ImmutableMatrix:
    """``lobe(n) = (√π/2, −√(π/3)·n_y, √(π/3)·n_z, −√(π/3)·n_x)`` for a unit ``n``."""
    c0, _, c1, _ = clamped_cosine_coefficients(L1_BASIS)
    nx, ny, nz = normal
    return sp.ImmutableMatrix([c0, -c1 * ny, c1 * nz, -c1 * nx])


def zonal_rotation_factors(basis: Sequence[sp.Expr] = L2_BASIS) -> tuple[sp.Expr, ...]:
    """Per coefficient, the factor ``A_l`` with ``lobe_k(n) = A_l·Y_k(n)``: the zonal
    coefficient of band ``l`` around ``+z`` divided by ``Y_l0(+z)`` (rotating a function
    symmetric about its axis multiplies band ``l`` by ``√(4π/(2l+1))·Y_lm(n)``, and
    ``Y_l0(+z) = √((2l+1)/(4π))``). For the clamped cosine: ``(π, 2π/3, π/4)``."""
    return _zonal_rotation_factors(tuple(basis))


@cache
def _zonal_rotation_factors(basis: tuple[sp.Expr, ...]) -> tuple[sp.Expr, ...]:
    bands = [0] + [1] * 3 + [2] * 5
    zonal = clamped_cosine_coefficients(basis)
    at_pole = {x: 0, y: 0, z: 1}
    per_band = {0: zonal[0] / basis[0].subs(at_pole), 1: zonal[2] / basis[2].subs(at_pole),
                2: zonal[6] / basis[6].subs(at_pole)}
    return tuple(sp.simplify(per_band[band]) for band in bands[:len(basis)])


def lobe_l2(normal: Sequence[sp.Expr] = (n_x, n_y, n_z)) -> sp.ImmutableMatrix:
    """L2 projection of ``clamp⁺⟨n, ω⟩`` for a unit ``n``: ``A_l·Y_k(n)`` with
    ``A = (π, 2π/3, π/4)``; its first four coefficients are exactly :func:`lobe`."""
    subs = dict(zip((x, y, z), normal))
    return sp.ImmutableMatrix([sp.expand(a * b.subs(subs, simultaneous=True))
                               for a, b in zip(zonal_rotation_factors(L2_BASIS), L2_BASIS)])


def evaluate(coefficients: Sequence[sp.Expr], direction: Sequence[sp.Expr]) -> sp.Expr:
    """``dot(f, Y(ω))`` with the L1 basis at a direction (not normalised here)."""
    subs = dict(zip((x, y, z), direction))
    return sum((f * b.subs(subs) for f, b in zip(coefficients, L1_BASIS)), sp.S.Zero)


def flux_of(coefficients: Sequence[sp.Expr]) -> sp.Expr:
    """Flux ``∫ Σ f_k Y_k dω`` of an intensity SH vector (only band 0 survives)."""
    return integrate_over_sphere(sum((f * b for f, b in zip(coefficients, L1_BASIS)),
                                     sp.S.Zero))


def clamped_cosine_energy() -> sp.Expr:
    """``∫ clamp⁺(cos θ)² dω = 2π/3``."""
    return integrate_over_sphere(z**2, hemisphere=True)


def captured_energy_fraction(basis: Sequence[sp.Expr]) -> sp.Expr:
    """Share of the clamped cosine's energy its projection keeps (Parseval):
    ``Σ_k s_k² / (2π/3)``."""
    return sp.nsimplify(sp.simplify(sum(s**2 for s in clamped_cosine_coefficients(basis))
                                    / clamped_cosine_energy()))


def band_energy_fraction(band: int) -> sp.Expr:
    """Share of the clamped cosine's energy in SH band ``band`` (0, 1 or 2) alone
    (Parseval: the band's ``Σ s_k²`` over ``2π/3``); the bands up to l sum to the L1 and
    L2 shares."""
    coefficients = clamped_cosine_coefficients(L2_BASIS)[band ** 2:(band + 1) ** 2]
    return sp.nsimplify(sp.simplify(sum(s**2 for s in coefficients)
                                    / clamped_cosine_energy()))


def net_flux_coefficients(basis: Sequence[sp.Expr]) -> list[sp.Expr]:
    """Projection of ``⟨e_z, ω⟩ = z`` (the whole cosine, both signs) onto ``basis``:
    ``∫ z·Y_k dω`` over the sphere. Its dot product with a radiance vector is Gershun's
    light vector along z, the net flux through a plane facing z (docs/MODEL.md
    "Net-flux gather")."""
    return [sp.simplify(integrate_over_sphere(sp.expand(z * b))) for b in basis]


def results() -> list[Result]:
    net_l2 = net_flux_coefficients(L2_BASIS)
    cos_l1 = clamped_cosine_coefficients(L1_BASIS)
    cos_l2 = clamped_cosine_coefficients(L2_BASIS)
    f0, f1, f2, f3 = sp.symbols("f_0 f_1 f_2 f_3")
    flux_factor = sp.simplify(flux_of((f0, f1, f2, f3)) / f0)
    r = [
        result(MODULE, "c0", C0,
               "Band-0 SH constant: the band-0 basis function is 1/(2√π) everywhere.",
               glsl_name="SH_C0"),
        result(MODULE, "c1", C1, "Band-1 SH constant: Y1m = ±√3/(2√π)·(y, z, x).",
               glsl_name="SH_C1"),
        result(MODULE, "basis_l1", sp.ImmutableMatrix(L1_BASIS),
               "L1 real SH basis in the annotations' order and signs."),
        result(MODULE, "coslobe_c0", cos_l1[0],
               "Band-0 coefficient of the clamped cosine lobe: the integral of cos θ times "
               "the band-0 basis function dω over the hemisphere.",
               glsl_name="SH_COSLOBE_C0"),
        result(MODULE, "coslobe_c1", cos_l1[2],
               "Band-1 coefficient of the clamped cosine lobe around z: the integral of "
               "cos θ · Y10 dω over the hemisphere.",
               glsl_name="SH_COSLOBE_C1"),
        result(MODULE, "net_flux_c1", net_l2[2],
               "Band-1 coefficient of ⟨e_z, ω⟩ (the light vector's kernel): the integral of "
               "z · Y10 dω over the sphere, √(4π/3) = 2·SH_COSLOBE_C1; every other L2 "
               "coefficient is 0.",
               glsl_name="SH_NET_FLUX_C1"),
        result(MODULE, "lobe", lobe(),
               "SH projection of max(0, ⟨n, ω⟩) around a unit normal n: linear in n."),
        result(MODULE, "flux_factor", flux_factor,
               "Flux of an intensity SH vector f: ∫ f·Y dω = 2√π·f0.",
               glsl_name="SH_FLUX_FACTOR"),
        result(MODULE, "clamped_cosine_energy", clamped_cosine_energy(),
               "Energy of the clamped cosine: ∫ max(0, cos θ)² dω = 2π/3."),
        result(MODULE, "l1_energy_fraction", captured_energy_fraction(L1_BASIS),
               "Share of the clamped cosine's energy kept by its L1 (4-coefficient) "
               "projection."),
        result(MODULE, "l2_energy_fraction", captured_energy_fraction(L2_BASIS),
               "Share of the clamped cosine's energy kept by its L2 (9-coefficient) "
               "projection."),
        *(result(MODULE, f"band{band}_energy_fraction", band_energy_fraction(band),
                 f"Share of the clamped cosine's energy in SH band {band} alone.")
          for band in range(3)),
        result(MODULE, "basis_l2", sp.ImmutableMatrix(L2_BASIS),
               "L2 (9-coefficient) real SH basis, same convention."),
        result(MODULE, "l2_c0", C0, "L2 basis: Y00 constant.", glsl_name="SH_L2_C0"),
        result(MODULE, "l2_c1", C1, "L2 basis: band-1 constant.", glsl_name="SH_L2_C1"),
        result(MODULE, "l2_c2", L2_C2, "L2 basis: constant of xy, yz, xz (√15/(2√π)).",
               glsl_name="SH_L2_C2"),
        result(MODULE, "l2_c3", L2_C3, "L2 basis: constant of 3z²−1 (√5/(4√π)).",
               glsl_name="SH_L2_C3"),
        result(MODULE, "l2_c4", L2_C4, "L2 basis: constant of x²−y² (√15/(4√π)).",
               glsl_name="SH_L2_C4"),
        result(MODULE, "l2_coslobe_c0", cos_l2[0], "Clamped cosine lobe, band 0 (L2 basis).",
               glsl_name="SH_L2_COSLOBE_C0"),
        result(MODULE, "l2_coslobe_c1", cos_l2[2], "Clamped cosine lobe, band 1 (L2 basis).",
               glsl_name="SH_L2_COSLOBE_C1"),
        result(MODULE, "l2_coslobe_c2", cos_l2[6],
               "Clamped cosine lobe around z, band 2: the integral of cos θ · Y20 dω over the "
               "hemisphere, √(5π)/8.",
               glsl_name="SH_L2_COSLOBE_C2"),
        result(MODULE, "zonal_rotation_factors", sp.ImmutableMatrix(
            [zonal_rotation_factors()[k] for k in (0, 1, 4)]),
               "Clamped cosine, band factors A_l (l = 0, 1, 2) of lobe_k(n) = A_l·Y_k(n)."),
        result(MODULE, "lobe_l2", lobe_l2(),
               "L2 projection of max(0, ⟨n, ω⟩) around a unit normal n (9 coefficients); the "
               "first four are the L1 lobe."),
        result(MODULE, "l2_lobe_c2", lobe_l2()[4].coeff(n_x * n_y),
               "L2 lobe around n, coefficient of n_x·n_y in band 2 (m = −2): π/4·√15/(2√π).",
               glsl_name="SH_L2_LOBE_C2"),
        result(MODULE, "l2_lobe_c3", -lobe_l2()[6].subs({n_x: 0, n_y: 0, n_z: 0}),
               "L2 lobe around n, m = 0 term: SH_L2_LOBE_C3·(3n_z² − 1), π/4·√5/(4√π).",
               glsl_name="SH_L2_LOBE_C3"),
        result(MODULE, "l2_lobe_c4", lobe_l2()[8].coeff(n_x**2),
               "L2 lobe around n, coefficient of n_x² − n_y² (m = 2): π/4·√15/(4√π).",
               glsl_name="SH_L2_LOBE_C4"),
    ]
    return r
