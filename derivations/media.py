r"""Participating media and the glossy lobe: phase functions, their SH convolution factors,
and the single-scattering integral of a homogeneous medium (docs/MODEL.md "Fog").

**Phase functions** (normalised over the sphere, ``∫ p dω = 1``), as a function of the
cosine ``t`` of the angle between the light's direction of travel before and after the
scattering event:

.. math:: p_{\mathrm{iso}} = \frac{1}{4\pi}, \qquad
          p_{\mathrm{HG}}(t) = \frac{1 - g^2}{4\pi\,(1 + g^2 - 2 g t)^{3/2}}

(Henyey–Greenstein, ``−1 < g < 1``; ``g = 0`` is the isotropic phase function).

**SH convolution factors.** For a function ``h(⟨ω, ω_o⟩)`` symmetric about ``ω_o``, the
Funk–Hecke theorem gives ``∫ h(⟨ω, ω_o⟩) Y_lm(ω) dω = a_l Y_lm(ω_o)`` with
``a_l = 2π ∫_{−1}^{1} h(t) P_l(t) dt``. So scattering a radiance field stored as SH
coefficients ``L_lm`` towards ``ω_o`` is ``Σ a_l L_lm Y_lm(ω_o)``: multiply band ``l`` by
``a_l`` and evaluate. For HG, ``a_l = g^l`` exactly (derived below for ``l ≤ 3``); the
isotropic function keeps band 0 only (``a_0 = 1``, the mean radiance). The zonal SH
coefficients of the HG lobe around ``+z`` are ``a_l·√((2l+1)/(4π))``.

*Derivation of a_l.* The substitution ``u = √(1 + g² − 2gt)`` (``t = (1 + g² − u²)/(2g)``,
``dt = −u/g du``; ``t = −1 ↦ u = 1 + g``, ``t = 1 ↦ u = 1 − g`` for ``0 < g < 1``) makes
``p_HG(t) P_l(t) dt`` a rational function of ``u``, which sympy integrates exactly. For
``−1 < g < 0``, ``p_g(t) = p_{−g}(−t)`` and ``P_l(−t) = (−1)^l P_l(t)``, so
``a_l(g) = (−1)^l a_l(−g) = g^l`` too; ``g = 0`` is the isotropic case.

**Homogeneous medium** of extinction ``σ_t`` and single-scattering albedo ``α``
(``σ_s = α σ_t``): along a ray the transmittance over a length ``ℓ`` is
``T(ℓ) = e^{−σ_t ℓ}``, and the radiance scattered towards the eye by a medium whose
in-scattered radiance per unit length ``σ_s·L_p`` is constant over a segment
``[a, b]`` is ``α·L_p·(T(a) − T(b))``; over the whole segment ``[0, ℓ]`` that is
``α·L_p·(1 − e^{−σ_t ℓ})``.

Examples
--------
>>> from derivations.media import hg_band_factor, g
>>> hg_band_factor(1)
g
>>> from derivations.media import segment_inscatter
>>> segment_inscatter()
Eq(L_s, L_p*alpha*(1 - exp(-ell*sigma_t)))

References
----------
L. G. Henyey, J. L. Greenstein, "Diffuse radiation in the galaxy", ApJ 93 (1941).
R. Ramamoorthi, P. Hanrahan, "An efficient representation for irradiance environment
maps", SIGGRAPH 2001 (the Funk–Hecke convolution of SH).
A. Kaplanyan, C. Dachsbacher, "Cascaded Light Propagation Volumes", I3D 2010, §6.
"""

from __future__ import annotations

from functools import cache

import sympy as sp

from derivations.registry import Result, result

MODULE = "media"

g = sp.Symbol("g", positive=True)
"""The HG asymmetry parameter, taken in ``(0, 1)`` in the integrals (module docstring)."""
t = sp.Symbol("t", real=True)
u = sp.Symbol("u", positive=True)
sigma_t, ell, alpha = sp.symbols("sigma_t ell alpha", positive=True)
L_p, L_s = sp.symbols("L_p L_s")
BANDS = 3
"""Bands the factors are derived for (L2 needs 0..2; band 3 is checked as well)."""


def isotropic_phase() -> sp.Expr:
    """``p_iso = 1/(4π)``: its integral over the sphere, ``4π·p``, is 1."""
    return 1 / (4 * sp.pi)


def hg_phase(cosine: sp.Expr = t) -> sp.Expr:
    """The Henyey–Greenstein phase function at the scattering cosine."""
    return (1 - g**2) / (4 * sp.pi * (1 + g**2 - 2 * g * cosine) ** sp.Rational(3, 2))


@cache
def hg_band_factor(band: int) -> sp.Expr:
    """``a_l = 2π ∫ p_HG(t) P_l(t) dt``, integrated exactly after ``u = √(1 + g² − 2gt)``
    (module docstring); equals ``g^l``."""
    if band < 0:
        raise ValueError(f"band must be >= 0, got {band}")
    in_u = (1 + g**2 - u**2) / (2 * g)
    # p_HG = (1 − g²)/(4π u³), dt = −u/g du; reversing the limits absorbs the minus sign
    integrand = 2 * sp.pi * (1 - g**2) / (4 * sp.pi * u**3) * sp.legendre(band, in_u) * u / g
    return sp.factor(sp.simplify(sp.integrate(sp.expand(integrand), (u, 1 - g, 1 + g))))


def hg_normalisation() -> sp.Expr:
    """``∫ p_HG dω``: band 0's factor, 1 for every ``g``."""
    return hg_band_factor(0)


def hg_zonal_coefficients(bands: int = BANDS) -> sp.ImmutableMatrix:
    """SH coefficients ``∫ p_HG(⟨ω, +z⟩) Y_l0(ω) dω = a_l·√((2l+1)/(4π))`` of the HG lobe
    around ``+z``, band by band."""
    return sp.ImmutableMatrix([sp.simplify(hg_band_factor(band)
                                           * sp.sqrt(sp.Rational(2 * band + 1, 4) / sp.pi))
                               for band in range(bands + 1)])


def isotropic_band_factors(bands: int = BANDS) -> sp.ImmutableMatrix:
    """``a_l`` of the isotropic phase function: ``2π ∫ P_l(t)/(4π) dt`` = (1, 0, 0, ...)."""
    return sp.ImmutableMatrix([sp.integrate(2 * sp.pi * isotropic_phase()
                                            * sp.legendre(band, t), (t, -1, 1))
                               for band in range(bands + 1)])


def transmittance() -> sp.Eq:
    """``T(ℓ) = e^{−σ_t ℓ}``: Beer–Lambert in a homogeneous medium."""
    return sp.Eq(sp.Symbol("T"), sp.exp(-sigma_t * ell))


def segment_inscatter() -> sp.Eq:
    """``∫_0^ℓ σ_s e^{−σ_t s} L_p ds = α L_p (1 − e^{−σ_t ℓ})`` for a constant ``L_p``."""
    s = sp.Symbol("s", positive=True)
    value = sp.integrate(alpha * sigma_t * sp.exp(-sigma_t * s) * L_p, (s, 0, ell))
    closed = alpha * L_p * (1 - sp.exp(-sigma_t * ell))
    if sp.simplify(value - closed) != 0:
        raise ArithmeticError(f"the segment integral {value} is not {closed}")
    return sp.Eq(L_s, closed)


def results() -> list[Result]:
    factors = [hg_band_factor(band) for band in range(BANDS + 1)]
    return [
        result(MODULE, "isotropic_phase", isotropic_phase(),
               "The isotropic phase function, 1/(4π) per steradian.",
               glsl_name="INV_FOUR_PI"),
        result(MODULE, "isotropic_normalisation", 4 * sp.pi * isotropic_phase(),
               "The isotropic phase function integrates to 1 over the sphere."),
        result(MODULE, "hg_phase", sp.Eq(sp.Symbol("p_{HG}"), hg_phase()),
               "Henyey–Greenstein phase function at the scattering cosine t, asymmetry g."),
        result(MODULE, "hg_normalisation", hg_normalisation(),
               "The HG phase function integrates to 1 over the sphere for every g."),
        result(MODULE, "hg_band_factors", sp.ImmutableMatrix(factors),
               "SH convolution factors a_l = 2π∫p_HG P_l dt of the HG lobe, bands 0..3: "
               "g^l exactly (Funk–Hecke)."),
        result(MODULE, "hg_zonal_coefficients", hg_zonal_coefficients(),
               "Zonal SH coefficients of the HG lobe around +z: g^l·√((2l+1)/(4π))."),
        result(MODULE, "isotropic_band_factors", isotropic_band_factors(),
               "SH convolution factors of the isotropic phase function: band 0 only."),
        result(MODULE, "transmittance", transmittance(),
               "Transmittance of a homogeneous medium over a length ℓ (Beer–Lambert)."),
        result(MODULE, "segment_inscatter", segment_inscatter(),
               "Single scattering of a constant in-scattered radiance L_p over a ray of "
               "length ℓ: α·L_p·(1 − exp(−σ_t·ℓ))."),
    ]
