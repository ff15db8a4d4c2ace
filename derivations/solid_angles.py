r"""Solid angles of the faces a propagation step sends light through.

Propagation moves light from a source cell to a neighbour through five faces of the
neighbour: its far ("front") face and four side faces (docs/MODEL.md, "Propagation").
With the source centre at the origin and cells of side 2, the neighbour along ``+z`` has

* front face: the square ``z = 3``, ``x, y ∈ [-1, 1]``;
* a side face: ``x = 1``, ``y ∈ [1, 3]``, ``z ∈ [-1, 1]`` for the neighbour along ``+y``
  (the annotations' frame, §2.2); all four side faces are congruent by symmetry.

General closed form (an axis-aligned rectangle in the plane ``z = d > 0`` seen from the
origin). The solid angle is :math:`\iint d\,(x^2+y^2+d^2)^{-3/2}\,dx\,dy` (cos/r², see
below) and the corner function

.. math:: F(u, v) = \arctan\frac{u v}{d\sqrt{u^2+v^2+d^2}}, \qquad
          \frac{\partial^2 F}{\partial u\,\partial v} = \frac{d}{(u^2+v^2+d^2)^{3/2}}

is an antiderivative in both variables, so
:math:`\Omega = F(x_1,y_1) - F(x_0,y_1) - F(x_1,y_0) + F(x_0,y_0)`.

Each face is also computed by two independent methods, as the annotations do:

1. spherical trigonometry: project the corners onto the unit sphere, split the spherical
   quadrilateral into two triangles, and take each triangle's spherical excess
   ``A + B + C − π`` (Girard's theorem), with the angles from the spherical law of
   cosines;
2. integration of the radiance of a unit-intensity point light,
   :math:`\Omega = \int_{face} \cos\theta / r^2\, dA`: the inner integral by
   ``sympy.integrate``, the outer one with the antiderivative
   :math:`\int \frac{dy}{(y^2+a)\sqrt{y^2+c}} = \frac{1}{\sqrt{a(c-a)}}
   \arctan\frac{y\sqrt{c-a}}{\sqrt{a}\sqrt{y^2+c}}` (``0 < a < c``), which
   :func:`outer_antiderivative` checks exactly by differentiation.

The methods give different-looking closed forms (arccos sums vs arctan); :func:`prove_equal`
shows they agree: the cosines of both sides are equal exactly (``expand_trig`` reduces
both to algebraic numbers, compared exactly), and a 50-digit evaluation puts both angles
in ``(0, π)``, where the cosine is one-to-one.

Results: ``front_face = 4·atan(√11/33)``, ``side_face = 2·atan(3√11/11) − π/3`` and the
tiling identity ``front + 4·side = 2π/3``, i.e. ``6·(front + 4·side) = 4π``: the 30 faces
of the six neighbours cover the sphere exactly once (proved exactly in
:func:`tiling_proof`).

Examples
--------
>>> from derivations.solid_angles import front_face, side_face
>>> front_face()
4*atan(sqrt(11)/33)
>>> side_face()
-pi/3 + 2*atan(3*sqrt(11)/11)

References
----------
A. Kirsch, "Light Propagation Volumes — Annotations" (2010), §2.
F. Van Oosterom, J. Strackee, "The solid angle of a plane triangle", IEEE TBME 30 (1983).
M. Pharr, W. Jakob, G. Humphreys, *Physically Based Rendering*, 4th ed., §3.8 (spherical
geometry).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache

import sympy as sp

from derivations.registry import Result, result

MODULE = "solid_angles"

x, y, z = sp.symbols("x y z", real=True)
_theta, _phi = sp.symbols("theta phi", real=True)

FRONT_FACE_CORNERS = ((1, 1, 3), (-1, 1, 3), (-1, -1, 3), (1, -1, 3))
"""Corners of the front face (plane z = 3), in order around the face."""
SIDE_FACE_CORNERS = ((1, 1, -1), (1, 3, -1), (1, 3, 1), (1, 1, 1))
"""Corners of the side face (plane x = 1), in order around the face."""


# --- general closed form --------------------------------------------------------------

def rectangle_corner_term(u: sp.Expr, v: sp.Expr, d: sp.Expr) -> sp.Expr:
    """``F(u, v) = atan(u·v / (d·√(u²+v²+d²)))``: the corner function of the solid angle
    of a rectangle in the plane at distance ``d > 0``."""
    return sp.atan(u * v / (d * sp.sqrt(u**2 + v**2 + d**2)))


def rectangle_solid_angle(u0: sp.Expr, u1: sp.Expr, v0: sp.Expr, v1: sp.Expr,
                          d: sp.Expr) -> sp.Expr:
    """Solid angle of ``[u0, u1] × [v0, v1]`` in the plane at distance ``d > 0`` seen from
    the origin (the plane's normal through the origin hits ``(0, 0)``)."""
    if sp.sympify(d).is_positive is False:
        raise ValueError(f"the plane must be in front of the viewer (d > 0), got d = {d}")
    term = rectangle_corner_term
    return term(u1, v1, d) - term(u0, v1, d) - term(u1, v0, d) + term(u0, v0, d)


def axis_aligned_rectangle_solid_angle(eye: Sequence[sp.Expr], axis: int, plane: sp.Expr,
                                       low: Sequence[sp.Expr],
                                       high: Sequence[sp.Expr]) -> sp.Expr:
    """Solid angle of an axis-aligned rectangle seen from the point ``eye``.

    The rectangle lies in the plane ``coordinate[axis] = plane`` and spans ``low..high``
    in the two other coordinates (in increasing axis order). Translating ``eye`` to the
    origin reduces it to :func:`rectangle_solid_angle` at distance ``|plane − eye[axis]|``.
    """
    if axis not in (0, 1, 2):
        raise ValueError(f"axis must be 0, 1 or 2 (x, y, z), got {axis}")
    others = [k for k in range(3) if k != axis]
    distance = sp.Abs(sp.sympify(plane) - eye[axis])
    if distance == 0:
        raise ValueError("the eye lies in the rectangle's plane: the solid angle is degenerate")
    (a0, b0), (a1, b1) = low, high
    return rectangle_solid_angle(a0 - eye[others[0]], a1 - eye[others[0]],
                                 b0 - eye[others[1]], b1 - eye[others[1]], distance)


@cache
def corner_term_is_antiderivative() -> bool:
    """Exact check ``∂²F/∂u∂v = d/(u²+v²+d²)^{3/2}`` (the cos/r² density)."""
    u, v, d = sp.symbols("u v d", positive=True)
    density = d / (u**2 + v**2 + d**2) ** sp.Rational(3, 2)
    return sp.simplify(sp.diff(rectangle_corner_term(u, v, d), u, v) - density) == 0


def front_face() -> sp.Expr:
    """Front face: ``[-1, 1]²`` at distance 3 → ``4·atan(√11/33)``."""
    return rectangle_solid_angle(-1, 1, -1, 1, 3)


def side_face() -> sp.Expr:
    """Side face: ``y ∈ [1, 3]``, ``z ∈ [-1, 1]`` in the plane ``x = 1`` →
    ``2·atan(3√11/11) − π/3``."""
    return rectangle_solid_angle(1, 3, -1, 1, 1)


def cube_face() -> sp.Expr:
    """One face of a cube seen from its centre (``[-1, 1]²`` at distance 1): ``4π/6``."""
    return rectangle_solid_angle(-1, 1, -1, 1, 1)


# --- method 1: spherical trigonometry -------------------------------------------------

def unit(vector: Sequence[sp.Expr]) -> sp.Matrix:
    """``vector`` projected onto the unit sphere (exact)."""
    v = sp.Matrix(vector)
    norm2 = v.dot(v)
    if norm2 == 0:
        raise ValueError("cannot project the zero vector onto the unit sphere")
    return v / sp.sqrt(norm2)


def spherical_angle(a: sp.Matrix, b: sp.Matrix, c: sp.Matrix) -> sp.Expr:
    """Interior angle at vertex ``a`` of the spherical triangle ``abc`` (unit vectors).

    Spherical law of cosines with the sides as central angles:
    ``cos A = (cos a' − cos b' cos c') / (sin b' sin c')`` where ``cos c' = a·b``,
    ``cos b' = a·c``, ``cos a' = b·c``.
    """
    ab, ac, bc = a.dot(b), a.dot(c), b.dot(c)
    if ab**2 == 1 or ac**2 == 1:
        raise ValueError("degenerate spherical triangle: two corners coincide or are antipodal")
    cos_angle = (bc - ab * ac) / (sp.sqrt(1 - ab**2) * sp.sqrt(1 - ac**2))
    return sp.acos(sp.radsimp(cos_angle))


def spherical_triangle_area(a: sp.Matrix, b: sp.Matrix, c: sp.Matrix) -> sp.Expr:
    """Area of a spherical triangle = its spherical excess ``A + B + C − π`` (Girard)."""
    return (spherical_angle(a, b, c) + spherical_angle(b, c, a)
            + spherical_angle(c, a, b) - sp.pi)


def spherical_polygon_area(corners: Sequence[Sequence[sp.Expr]]) -> sp.Expr:
    """Area of the spherical projection of a convex planar polygon (fan of triangles)."""
    if len(corners) < 3:
        raise ValueError(f"a polygon needs at least 3 corners, got {len(corners)}")
    points = [unit(corner) for corner in corners]
    return sum((spherical_triangle_area(points[0], points[i], points[i + 1])
                for i in range(1, len(points) - 1)), sp.S.Zero)


def front_face_by_spherical_trigonometry() -> sp.Expr:
    """Front face as two spherical triangles."""
    return spherical_polygon_area(FRONT_FACE_CORNERS)


def side_face_by_spherical_trigonometry() -> sp.Expr:
    """Side face as two spherical triangles."""
    return spherical_polygon_area(SIDE_FACE_CORNERS)


# --- method 2: integration of cos/r² ---------------------------------------------------

def outer_antiderivative(var: sp.Symbol, a: sp.Expr, c: sp.Expr) -> sp.Expr:
    """An antiderivative of ``1/((var² + a)·√(var² + c))`` for ``0 < a < c``."""
    return sp.atan(var * sp.sqrt(c - a) / (sp.sqrt(a) * sp.sqrt(var**2 + c))) / sp.sqrt(
        a * (c - a))


@cache
def outer_antiderivative_is_valid() -> bool:
    """Exact check of :func:`outer_antiderivative` by differentiation (symbolic a < c)."""
    t = sp.Symbol("t", real=True)
    a, gap = sp.symbols("a gap", positive=True)
    c = a + gap
    derivative = sp.diff(outer_antiderivative(t, a, c), t)
    return sp.simplify(derivative - 1 / ((t**2 + a) * sp.sqrt(t**2 + c))) == 0


_k, _a, _c = sp.Wild("k"), sp.Wild("a"), sp.Wild("c")


def _integrate_outer(expr: sp.Expr, var: sp.Symbol, lo: sp.Expr, hi: sp.Expr) -> sp.Expr:
    """∫ expr d(var) over [lo, hi] for a sum of terms ``k/((var²+a)·√(var²+c))``."""
    total = sp.S.Zero
    for term in sp.Add.make_args(sp.expand(expr)):
        match = sp.factor(term).match(_k / ((var**2 + _a) * sp.sqrt(var**2 + _c)))
        if (not match or any(match[w].has(var) for w in (_k, _a, _c))
                or not (0 < match[_a] < match[_c])):
            raise ValueError(f"outer integrand term {term} is not k/((t²+a)√(t²+c)), 0<a<c")
        primitive = outer_antiderivative(var, match[_a], match[_c])
        total += match[_k] * (primitive.subs(var, hi) - primitive.subs(var, lo))
    return total


def face_solid_angle_by_integration(density: sp.Expr, inner: tuple, outer: tuple) -> sp.Expr:
    """``∫∫ density`` with ``inner = (var, lo, hi)`` done by sympy, then the outer one."""
    inner_integral = sp.integrate(density, inner)
    return sp.simplify(_integrate_outer(inner_integral, *outer))


@cache
def front_face_by_integration() -> sp.Expr:
    """``∫∫ ⟨(0,0,1), p⟩/|p| · 1/|p|² dx dy`` over the front face, ``p = (x, y, 3)``."""
    p = sp.Matrix([x, y, 3])
    cosine_over_r2 = p.dot(sp.Matrix([0, 0, 1])) / p.norm() ** 3
    return face_solid_angle_by_integration(cosine_over_r2, (x, -1, 1), (y, -1, 1))


@cache
def side_face_by_integration() -> sp.Expr:
    """``∫∫ ⟨(1,0,0), p⟩/|p|³ dy dz`` over the side face, ``p = (1, y, z)``."""
    p = sp.Matrix([1, y, z])
    cosine_over_r2 = p.dot(sp.Matrix([1, 0, 0])) / p.norm() ** 3
    return face_solid_angle_by_integration(cosine_over_r2, (y, 1, 3), (z, -1, 1))


# --- proofs ----------------------------------------------------------------------------

@dataclass(frozen=True)
class AngleProof:
    """Outcome of :func:`prove_equal`; ``method`` says how equality was established."""

    equal: bool
    method: str


def prove_equal(first: sp.Expr, second: sp.Expr, digits: int = 50) -> AngleProof:
    """Prove ``first == second`` for two angles known to lie in ``(0, π)``.

    Step 1 (exact): ``simplify(first − second) == 0`` when sympy manages it.
    Otherwise step 2: ``cos(first) − cos(second)`` after ``expand_trig`` is an algebraic
    number; it is shown to be 0 exactly (``simplify``, else ``minimal_polynomial`` = X).
    Step 3 (numeric, ``digits`` digits): both angles lie in ``(0, π)``, where cos is
    one-to-one, with a margin far above the evaluation error.
    """
    difference = first - second
    if difference == 0 or sp.simplify(difference) == 0:
        return AngleProof(True, "exact: simplify(a - b) == 0")
    cos_gap = sp.expand_trig(sp.cos(first)) - sp.expand_trig(sp.cos(second))
    cos_equal = cos_gap == 0 or sp.simplify(cos_gap) == 0
    if not cos_equal:
        try:
            cos_equal = sp.minimal_polynomial(cos_gap, sp.Symbol("X")) == sp.Symbol("X")
        except (sp.polys.polyerrors.NotAlgebraic, NotImplementedError):
            return AngleProof(False, "cos(a) - cos(b) is not an algebraic number sympy "
                                     "can decide")
    margin = sp.Float(10) ** (5 - digits)
    in_range = all(margin < sp.N(angle, digits) < sp.N(sp.pi, digits) - margin
                   for angle in (first, second))
    return AngleProof(bool(cos_equal and in_range),
                      "exact cos(a) == cos(b) (expand_trig, algebraic) + "
                      f"{digits}-digit check that a, b lie in (0, pi)")


@dataclass(frozen=True)
class TilingProof:
    """The steps of :func:`tiling_proof`, each checked exactly."""

    tan_a_times_tan_2b_is_one: bool
    a_in_0_quarter_pi: bool
    two_b_in_0_half_pi: bool
    front_plus_four_sides: sp.Expr

    @property
    def holds(self) -> bool:
        return (self.tan_a_times_tan_2b_is_one and self.a_in_0_quarter_pi
                and self.two_b_in_0_half_pi and self.front_plus_four_sides == 2 * sp.pi / 3)


@cache
def tiling_proof() -> TilingProof:
    """Exact proof of ``front + 4·side = 2π/3`` (only rational arithmetic on radicals).

    With ``a = atan(√11/33)`` and ``b = atan(3√11/11)``: ``front = 4a`` and
    ``side = 2b − π/3``, so ``front + 4·side = 4(a + 2b) − 4π/3``. ``tan 2b =
    2 tan b/(1 − tan²b) = 3√11 = 1/tan a``, so ``cos(a + 2b) = cos a·cos 2b·(1 − tan a·tan 2b)
    = 0``; ``tan a < 1`` and ``tan b < 1`` put ``a ∈ (0, π/4)`` and ``2b ∈ (0, π/2)``, so
    ``a + 2b ∈ (0, 3π/4)`` and therefore ``a + 2b = π/2``; hence ``front + 4·side =
    2π − 4π/3 = 2π/3``.
    """
    tan_a = sp.sqrt(11) / 33
    tan_b = 3 * sp.sqrt(11) / 11
    if front_face() != 4 * sp.atan(tan_a) or side_face() != 2 * sp.atan(tan_b) - sp.pi / 3:
        raise AssertionError("the closed forms changed; update the tiling proof")
    tan_2b = sp.radsimp(2 * tan_b / (1 - tan_b**2))
    product_is_one = sp.simplify(tan_a * tan_2b - 1) == 0
    # 0 < t < 1 for t = tan a, tan b, checked on t² (rationals): atan(t) ∈ (0, π/4).
    a_small = 0 < tan_a**2 < 1
    b_small = 0 < tan_b**2 < 1
    a_plus_2b = sp.pi / 2  # the only zero of cos on (0, 3π/4)
    total = sp.expand(4 * a_plus_2b - 4 * sp.pi / 3)
    return TilingProof(bool(product_is_one), bool(a_small), bool(b_small), total)


# --- registry --------------------------------------------------------------------------

def results() -> list[Result]:
    front, side = front_face(), side_face()
    return [
        result(MODULE, "front_face", front,
               "Solid angle of a neighbour's far face seen from the source cell centre.",
               glsl_name="FRONT_FACE_SOLID_ANGLE"),
        result(MODULE, "side_face", side,
               "Solid angle of one of a neighbour's four side faces seen from the source "
               "cell centre.",
               glsl_name="SIDE_FACE_SOLID_ANGLE"),
        result(MODULE, "front_face_spherical", front_face_by_spherical_trigonometry(),
               "Front face as two spherical triangles (Girard's excess); equals front_face."),
        result(MODULE, "side_face_spherical", side_face_by_spherical_trigonometry(),
               "Side face as two spherical triangles (Girard's excess); equals side_face."),
        result(MODULE, "tiling",
               sp.Eq(6 * sp.UnevaluatedExpr(front + 4 * side), 4 * sp.pi, evaluate=False),
               "The 6 front faces and 24 side faces of the neighbours cover the sphere "
               "exactly once (front + 4 side = 2π/3)."),
        result(MODULE, "cube_face", cube_face(),
               "One cube face seen from the cube centre: the whole field of a 90° square "
               "frustum (4π/6).",
               glsl_name="CUBE_FACE_SOLID_ANGLE"),
        result(MODULE, "sphere", 4 * sp.pi,
               "Solid angle of the whole sphere: the integral of dω over all directions.",
               glsl_name="FOUR_PI"),
        result(MODULE, "projected_hemisphere",
               sp.integrate(sp.cos(_theta) * sp.sin(_theta), (_theta, 0, sp.pi / 2),
                            (_phi, 0, 2 * sp.pi)),
               "Projected solid angle of the hemisphere: the integral of cos θ dω over it, π.",
               glsl_name="PI"),
    ]

