r"""Reflective shadow map: the flux a texel reflects, its solid angle, its surfel area.

Outgoing flux (annotations §3). A point light of flux ``Φ_L`` (intensity ``Φ_L/(4π)``)
at distance ``r`` lights a diffuse surfel of area ``A`` (facing the light) and
reflectance ``c_diff`` at incidence ``θ_i``:

.. math::
   E = \frac{1}{r^2}\frac{\Phi_L}{4\pi},\quad
   L_o = \frac{c_{diff}}{\pi} E\,\overline{\cos\theta_i},\quad
   M = \int_{H^2} L_o\cos\theta_o\,d\omega_o = \pi L_o,\quad
   \Phi_o = A M = c_{diff}\,\frac{\Delta\omega_\text{texel}}{4\pi}\,\Phi_L\,\overline{\cos\theta_i}

with ``Δω_texel = A/r²`` the surfel's solid angle seen from the light.

Erratum (texel flux). In an RSM, ``Δω_texel`` is the solid angle of the *texel*, fixed by the
frustum; the surfel that texel sees is tilted by ``θ_i``, so its area is
``A = Δω_texel·r²/cos θ_i`` (a tilted surfel subtends ``A·cos θ_i/r²``). Substituting that area
cancels the cosine: ``Φ_o = c_diff·Δω_texel/(4π)·Φ_L`` for any surface facing the light. The
published form keeps ``cos⁺θ_i`` *and* uses ``Δω_texel = A/r²``, which counts the cosine twice;
it is right only for surfels facing the light. See :func:`texel_flux_steps`.

Per-pixel solid angle. A 90° square frustum of ``W×H`` texels looks at one cube face,
``4π/6`` of the sphere. The annotations approximate each texel by ``(4π/6)/(W·H)``; the
exact value is the rectangle formula (``solid_angles.rectangle_solid_angle``) on the
texel's footprint in the image plane ``z = 1``. The exact texel solid angles sum to
``4π/6`` (the corner terms telescope), so the approximation is right on average but off
by the density ``(1 + u² + v²)^{-3/2}``: as ``W → ∞`` the ratio approximate/exact tends
to ``π/6 ≈ 0.52`` at the centre and ``√3π/2 ≈ 2.72`` in the corners.
:func:`pixel_solid_angle_errors` measures it on a real map.

Surfel area. At view depth ``w`` a 90° frustum's cross-section is ``2w·tan 45° = 2w``
wide, so a texel covers ``(2w)²/(W·H) = 4w²/(W·H)``: quadratic in ``w``, the bug the
annotations warn about (§5) being the linear ``4w/(W·H)``.

Spot cone (docs/MODEL.md "Spot cone"). A spot with a cone radiates ``I·f(θ)`` with
``f = smoothstep(cos θ_o, cos θ_i, cos θ) = 3t² − 2t³``,
``t = clamp((cos θ − cos θ_o)/(cos θ_i − cos θ_o), 0, 1)``. Because ``f`` is a polynomial
in ``cos θ`` and ``dω = −d(cos θ)·dφ``, the solid angle it weights is exact:
``∫f dω = 2π·(1 − (cos θ_i + cos θ_o)/2)`` (:func:`cone_solid_angle`), the flux leaving
the cone ``Φ_L/(4π)·∫f dω`` and, on a surface that catches the whole cone, the reflected
flux ``c_diff·Φ_L·(1 − (cos θ_i + cos θ_o)/2)/2``. Its RSM frustum is the square one
around the outer cone (``t = tan θ_o`` at depth 1), so a texel covers
``4t²w²/(W·H)`` at depth ``w`` and reflects ``c_diff·Δω_texel·f(θ_c)·Φ_L/(4π)`` with ``θ_c`` the
angle of its centre direction: the midpoint rule of ``∫_texel f dω``, whose error over the
whole map falls as ``1/W²``.

Point light (docs/MODEL.md "Several lights"). An isotropic point light renders six RSM
faces, the 90° frusta along ±x, ±y, ±z, each one cube face of ``4π/6``
(``solid_angles.cube_face``): they tile the sphere, every texel reflects
``c_diff·Δω_texel·Φ_L/(4π)``, and in a closed room of reflectance ``c_diff`` the six faces'
texels sum to ``6·(4π/6)·c_diff·Φ_L/(4π) = c_diff·Φ_L`` (:func:`point_light_room_flux`).

Examples
--------
>>> from derivations.rsm import outgoing_flux_steps
>>> outgoing_flux_steps()[-1].rhs
Delta_omega_texel*Phi_L*c_diff*Max(0, cos(theta_i))/(4*pi)

References
----------
C. Dachsbacher, M. Stamminger, "Reflective Shadow Maps", I3D 2005.
A. Kirsch, "Light Propagation Volumes — Annotations" (2010), §3 and §5.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy as sp

from derivations.registry import Result, result
from derivations.solid_angles import rectangle_corner_term, rectangle_solid_angle

MODULE = "rsm"

E, M, L_o, Phi_o, Phi_L, A, r, c_diff, texel_omega = sp.symbols(
    "E M L_o Phi_o Phi_L A r c_diff Delta_omega_texel", positive=True)
theta_i, theta_o, phi_o = sp.symbols("theta_i theta_o phi_o", real=True)
W, H, w = sp.symbols("W H w", positive=True)
i, j = sp.symbols("i j", integer=True, nonnegative=True)
clamped_cos_i = sp.Max(0, sp.cos(theta_i))


def outgoing_flux_steps() -> list[sp.Eq]:
    """The chain ``E → L_o → M → Φ_o`` as exact equations; the last is the result."""
    irradiance = Phi_L / (4 * sp.pi) / r**2
    radiance = c_diff / sp.pi * irradiance * clamped_cos_i
    # M = ∫_{H²} L_o cos θ_o dω_o with L_o constant over ω_o (Lambertian).
    projected_hemisphere = sp.integrate(sp.cos(theta_o) * sp.sin(theta_o),
                                        (theta_o, 0, sp.pi / 2), (phi_o, 0, 2 * sp.pi))
    exitance = radiance * projected_hemisphere
    flux = A * exitance
    in_texel_omega = sp.simplify(flux.subs(A, texel_omega * r**2))
    return [sp.Eq(E, irradiance), sp.Eq(L_o, radiance), sp.Eq(M, exitance),
            sp.Eq(Phi_o, flux), sp.Eq(Phi_o, in_texel_omega)]


def texel_flux_steps() -> list[sp.Eq]:
    """Flux reflected by the surfel one RSM texel of solid angle ``Δω_texel`` sees at
    incidence ``θ_i`` (``0 ≤ θ_i < π/2``): the surfel area is ``Δω_texel·r²/cos θ_i``, and
    the cosine cancels.

    The last equation is the flux the renderer stores per texel (docs/MODEL.md, RSM).
    """
    theta = sp.Symbol("theta_i", nonnegative=True)
    published = outgoing_flux_steps()[3].rhs            # Φ_o = A·M with cos⁺θ_i in L_o
    facing = published.subs(clamped_cos_i, sp.cos(theta))   # lit side: cos⁺ = cos
    tilted_area = texel_omega * r**2 / sp.cos(theta)
    per_texel = sp.simplify(facing.subs(A, tilted_area))
    return [sp.Eq(A, tilted_area), sp.Eq(Phi_o, facing.subs(A, tilted_area)),
            sp.Eq(Phi_o, per_texel)]


def texel_flux_published_over_correct() -> sp.Expr:
    """Published texel flux (``Δω_texel = A/r²`` with ``cos⁺θ_i`` kept) over the correct one on
    the lit side: ``cos θ_i``, the cosine counted a second time."""
    theta = sp.Symbol("theta_i", nonnegative=True)
    published = outgoing_flux_steps()[-1].rhs.subs(clamped_cos_i, sp.cos(theta))
    return sp.simplify(published / texel_flux_steps()[-1].rhs)


def pixel_solid_angle_approx() -> sp.Expr:
    """``(4π/6)/(W·H)`` (annotations §3)."""
    return rectangle_solid_angle(-1, 1, -1, 1, 1) / (W * H)


def pixel_solid_angle_exact() -> sp.Expr:
    """Exact solid angle of texel ``(i, j)`` of a ``W×H`` 90° frustum."""
    u0, u1 = -1 + 2 * i / W, -1 + 2 * (i + 1) / W
    v0, v1 = -1 + 2 * j / H, -1 + 2 * (j + 1) / H
    return rectangle_solid_angle(u0, u1, v0, v1, 1)


CORNER = sp.Function("F")
"""The corner function of the rectangle formula, ``solid_angles.rectangle_corner_term``."""
_u, _v = sp.symbols("u v", real=True)
_EDGES = sp.symbols("u_i u_{i+1} v_j v_{j+1}", real=True)


def texel_edges(index: sp.Expr, size: sp.Expr) -> sp.Expr:
    """Image-plane coordinate (plane ``z = 1``) of texel edge ``index`` of ``size``."""
    return -1 + 2 * index / size


def pixel_solid_angle_corners() -> sp.Equality:
    """``Δω_ij`` as four corner terms of the texel's edges: the readable form of
    :func:`pixel_solid_angle_exact` (``F`` and the edges substituted give it exactly)."""
    u0, u1, v0, v1 = _EDGES
    return sp.Eq(sp.Symbol(r"\Delta\omega_{ij}"),
                 CORNER(u1, v1) - CORNER(u0, v1) - CORNER(u1, v0) + CORNER(u0, v0),
                 evaluate=False)


def corner_function() -> sp.Equality:
    """``F(u, v) = atan(u·v/√(1 + u² + v²))``: the corner term on the plane ``z = 1``."""
    return sp.Eq(CORNER(_u, _v), rectangle_corner_term(_u, _v, 1), evaluate=False)


def corners_substituted() -> sp.Expr:
    """:func:`pixel_solid_angle_corners` with ``F`` and the edges ``u_i = −1 + 2i/W``,
    ``v_j = −1 + 2j/H`` substituted: equal to :func:`pixel_solid_angle_exact`."""
    u0, u1, v0, v1 = _EDGES
    edges = {u0: texel_edges(i, W), u1: texel_edges(i + 1, W), v0: texel_edges(j, H),
             v1: texel_edges(j + 1, H)}
    body = pixel_solid_angle_corners().rhs.replace(
        CORNER, lambda a, b: rectangle_corner_term(a, b, 1))
    return body.subs(edges, simultaneous=True)


def pixel_density(u: sp.Expr, v: sp.Expr) -> sp.Expr:
    """Solid angle per image-plane area at ``(u, v, 1)``: ``(1 + u² + v²)^{-3/2}``."""
    return (1 + u**2 + v**2) ** sp.Rational(-3, 2)


def approx_over_exact_limit(u: sp.Expr, v: sp.Expr) -> sp.Expr:
    """``lim_{W=H→∞}`` approximate/exact texel solid angle at image point ``(u, v)``:
    the texel area is ``4/W²``, so the ratio is ``(4π/6)/(4·density)``."""
    return sp.simplify(rectangle_solid_angle(-1, 1, -1, 1, 1) / (4 * pixel_density(u, v)))


cos_c, cos_i, cos_o = sp.symbols("cos_theta cos_theta_i cos_theta_o", real=True)
theta_o_sym = sp.Symbol("theta_o", positive=True)


def spot_falloff() -> sp.Expr:
    """``f`` between the two angles: ``3t² − 2t³`` with ``t = (cos θ − cos θ_o)/(cos θ_i −
    cos θ_o)`` (1 inside the inner angle, 0 outside the outer one)."""
    t = (cos_c - cos_o) / (cos_i - cos_o)
    return 3 * t**2 - 2 * t**3


def cone_solid_angle() -> sp.Expr:
    """``∫_{S²} f dω`` for ``cos θ_o < cos θ_i``: ``2π∫f d(cos θ)`` over ``[cos θ_o,
    cos θ_i]`` (the ramp) plus ``2π(1 − cos θ_i)`` (the cap where f = 1)."""
    ramp = sp.integrate(spot_falloff(), (cos_c, cos_o, cos_i))
    return sp.factor(sp.simplify(2 * sp.pi * (ramp + (1 - cos_i))))


def cone_total_flux() -> sp.Expr:
    """Flux reflected by a diffuse surface of reflectance ``c_diff`` that catches the whole
    cone: the texel fluxes ``c_diff·Δω_texel·f·Φ_L/(4π)`` summed into an integral."""
    return sp.simplify(c_diff * Phi_L / (4 * sp.pi) * cone_solid_angle())


def cone_surfel_area() -> sp.Expr:
    """World area of an RSM texel at view depth ``w`` when the frustum holds a cone of
    outer half-angle ``θ_o``: ``(2·w·tan θ_o)²/(W·H)``."""
    return (2 * w * sp.tan(theta_o_sym)) ** 2 / (W * H)


def point_light_room_flux() -> sp.Expr:
    """Flux the six cube faces of a point light reflect in a closed room of reflectance
    ``c_diff``: the texels' solid angles add up to six cube faces, the whole sphere."""
    faces = 6 * rectangle_solid_angle(-1, 1, -1, 1, 1)
    return sp.simplify(c_diff * faces * Phi_L / (4 * sp.pi))


def surfel_area() -> sp.Expr:
    """World area of one texel at view depth ``w``: ``(2·w·tan(π/4))²/(W·H)``."""
    return sp.simplify((2 * w * sp.tan(sp.pi / 4)) ** 2 / (W * H))


@dataclass(frozen=True)
class PixelSolidAngleErrors:
    """Relative error of the approximation over one map (``approx/exact − 1``)."""

    size: int
    max_relative_error: float
    mean_relative_error: float
    min_ratio: float
    max_ratio: float
    total_exact: float


@lru_cache(maxsize=8)
def pixel_solid_angle_errors(size: int = 512) -> PixelSolidAngleErrors:
    """Exact vs approximate texel solid angles over a ``size × size`` map (numpy, float64).

    The exact texel values come from the same corner function as the sympy closed form
    (``lambdify``), differenced over the texel edges; their sum reproduces ``4π/6`` to
    ~1e-13, which bounds the numeric error of each texel value far below the errors
    reported.
    """
    if size < 1:
        raise ValueError(f"size must be >= 1, got {size}")
    u, v = sp.symbols("u v", real=True)
    corner = sp.lambdify((u, v), rectangle_corner_term(u, v, 1), "numpy")
    edges = np.linspace(-1.0, 1.0, size + 1)
    grid_u, grid_v = np.meshgrid(edges, edges, indexing="ij")
    f = corner(grid_u, grid_v)
    exact = f[1:, 1:] - f[:-1, 1:] - f[1:, :-1] + f[:-1, :-1]
    approx = (4.0 * np.pi / 6.0) / (size * size)
    ratio = approx / exact
    relative = np.abs(ratio - 1.0)
    return PixelSolidAngleErrors(size, float(relative.max()), float(relative.mean()),
                                 float(ratio.min()), float(ratio.max()), float(exact.sum()))


def results() -> list[Result]:
    steps = outgoing_flux_steps()
    names = ("irradiance", "outgoing_radiance", "radiant_exitance", "outgoing_flux_area",
             "outgoing_flux")
    statements = (
        "Irradiance on a surfel facing a point light of flux Φ_L at distance r.",
        "Radiance leaving a diffuse surfel (Lambert) lit at incidence θ_i.",
        "Radiant exitance: the integral of L_o cos θ_o dω over the hemisphere, π·L_o.",
        "Flux reflected by a surfel of area A: Φ_o = A·M.",
        "Flux reflected by an RSM texel of solid angle Δω_texel = A/r²: "
        "c_diff·Δω_texel/(4π)·Φ_L·max(0, cos θ_i).",
    )
    out = [result(MODULE, n, eq, s) for n, eq, s in zip(names, steps, statements)]
    out += [
        result(MODULE, "texel_flux", texel_flux_steps()[-1],
               "Erratum: flux an RSM texel of solid angle Δω_texel reflects, any incidence on "
               "the lit side: c_diff·Δω_texel/(4π)·Φ_L (the surfel area Δω_texel·r²/cos θ_i "
               "cancels the cosine)."),
        result(MODULE, "texel_flux_published_over_correct",
               texel_flux_published_over_correct(),
               "The published texel flux over the correct one: cos θ_i, counted twice."),
        result(MODULE, "pixel_solid_angle_approx", pixel_solid_angle_approx(),
               "Per-texel solid angle of a 90° frustum, approximated as (4π/6)/(W·H)."),
        result(MODULE, "pixel_solid_angle_exact", pixel_solid_angle_exact(),
               "Exact solid angle of texel (i, j) of a W×H 90° frustum (rectangle formula)."),
        result(MODULE, "pixel_solid_angle_corners", pixel_solid_angle_corners(),
               "Exact solid angle of texel (i, j) from the corner function F at the texel's "
               "edges u_i = −1 + 2i/W, v_j = −1 + 2j/H on the image plane z = 1."),
        result(MODULE, "corner_function", corner_function(),
               "The rectangle formula's corner function on the image plane z = 1."),
        result(MODULE, "pixel_ratio_centre", approx_over_exact_limit(0, 0),
               "Large-map limit of approximate/exact texel solid angle at the centre: π/6."),
        result(MODULE, "pixel_ratio_corner", approx_over_exact_limit(1, 1),
               "Large-map limit of approximate/exact texel solid angle in a corner: √3π/2."),
        result(MODULE, "surfel_area", surfel_area(),
               "World area of an RSM texel at view depth w (90° frustum): 4w²/(W·H)."),
        result(MODULE, "spot_falloff", sp.Eq(sp.Symbol("f"), spot_falloff()),
               "Spot cone falloff between the inner and outer angles: smoothstep of cos θ, "
               "3t² − 2t³ with t = (cos θ − cos θ_o)/(cos θ_i − cos θ_o)."),
        result(MODULE, "cone_solid_angle", cone_solid_angle(),
               "Solid angle the spot cone's falloff weights, ∫f dω = 2π(1 − (cos θ_i + "
               "cos θ_o)/2): exact, f being a polynomial in cos θ."),
        result(MODULE, "cone_total_flux", cone_total_flux(),
               "Flux reflected by a surface that catches the whole cone: "
               "c_diff·Φ_L·(1 − (cos θ_i + cos θ_o)/2)/2."),
        result(MODULE, "point_light_room_flux", point_light_room_flux(),
               "Flux a point light's six RSM faces (90° frusta along ±x, ±y, ±z, one cube "
               "face each) reflect in a closed room of reflectance c_diff: c_diff·Φ_L."),
        result(MODULE, "cone_surfel_area", cone_surfel_area(),
               "World area of an RSM texel at view depth w when the square frustum holds "
               "the outer cone θ_o: 4w²tan²θ_o/(W·H)."),
    ]
    return out
