r"""Geometry-volume (fuzzy occlusion) injection and why double-sided injection is isotropic.

An occluder surfel with unit normal ``n`` and area ``A`` adds ``A/s²·lobe(n)`` to the
geometry volume (``s`` the cell size; docs/MODEL.md, "Geometry volume"). Injecting both
sides adds ``lobe(n) + lobe(−n)``; band 1 of the lobe is linear in ``n``
(``sh.lobe``), so it cancels exactly for every ``n``:

.. math:: \mathrm{lobe}(n) + \mathrm{lobe}(-n) = (\sqrt\pi, 0, 0, 0),

an isotropic blocker that has lost the surface's orientation (annotations §5.1).
Evaluated in any direction it blocks ``√π·c0 = 1/2`` per unit of ``A/s²``.

Statistical visibility (``Settings.geometry_visibility = "statistical"``): the blocking
``τ`` a face reads from the volume is the summed cross-section of its surfels over the
face's area. Split it among ``m`` surfels of ``τ/m`` each, placed independently and
uniformly over the face: a ray passes each with chance ``1 − τ/m``, all of them with
``(1 − τ/m)^m``, which tends to ``exp(−τ)`` as the surfels become many and small (a
Boolean, Poisson model of occluders; the transmittance of a participating medium of
optical depth ``τ``). Its first-order term is the LPV paper's linear ``1 − τ``; two
independent layers multiply, ``V(τ₁)·V(τ₂) = V(τ₁ + τ₂)``.

Examples
--------
>>> from derivations.occlusion import double_sided_lobe
>>> double_sided_lobe().T
Matrix([[sqrt(pi), 0, 0, 0]])

References
----------
A. Kirsch, "Light Propagation Volumes — Annotations" (2010), §5.1.
A. Kaplanyan, C. Dachsbacher, "Cascaded Light Propagation Volumes", I3D 2010, §5.
F. Sillion, "A Unified Hierarchical Algorithm for Global Illumination with Scattering
Volumes and Object Clusters", IEEE TVCG 1(3), 1995 (clusters of surfaces as a medium of
extinction ``Σ A cos θ / volume``).
"""

from __future__ import annotations

import sympy as sp

from derivations import sh
from derivations.registry import Result, result

MODULE = "occlusion"

area, cell = sp.symbols("A s", positive=True)


def one_sided(normal=(sh.n_x, sh.n_y, sh.n_z)) -> sp.ImmutableMatrix:
    """Geometry-volume SH of one surfel per unit ``A/s²``: ``lobe(n)``."""
    return sh.lobe(normal)


def double_sided_lobe(normal=(sh.n_x, sh.n_y, sh.n_z)) -> sp.ImmutableMatrix:
    """``lobe(n) + lobe(−n)`` for a symbolic unit ``n``, simplified exactly."""
    flipped = tuple(-component for component in normal)
    return sp.ImmutableMatrix((sh.lobe(normal) + sh.lobe(flipped)).applyfunc(sp.simplify))


def isotropic_blocking() -> sp.Expr:
    """``dot(lobe(n) + lobe(−n), Y(ω))`` for a unit ``ω``: independent of ``ω`` and ``n``."""
    omega = sp.symbols("omega_x omega_y omega_z", real=True)
    return sp.simplify(sh.evaluate(list(double_sided_lobe()), omega))


fov_y, height, depth, tilt = sp.symbols("theta_y H w theta", positive=True)
texel = sp.Symbol("delta", positive=True)


def camera_surfel_area() -> sp.Expr:
    """World area of one camera pixel at view depth ``w`` on a plane facing the camera
    (docs/MODEL.md "Camera occluders"): the frustum is ``2w·tan(θ_y/2)`` tall at depth
    ``w`` and ``H`` pixels high, and pixels are square, so ``(2w·tan(θ_y/2)/H)²``: the
    RSM texel's rule ``texel_area·w²`` with ``texel_area = (2·tan(θ_y/2)/H)²``."""
    edge = 2 * depth * sp.tan(fov_y / 2) / height
    return edge**2


def reprojection_depth_bound() -> sp.Expr:
    """Largest difference between the light-view depth of a point on a plane and the depth
    the shadow map stores for the same plane at the centre of the texel the point falls
    in: the point lies at most half a texel diagonal, ``(√2/2)·δ`` (``δ`` the texel's edge
    at that depth), from the centre, and the plane's depth changes by ``tan θ`` per unit
    of sideways distance (``θ`` the angle between the plane's normal and the light's
    direction)."""
    return sp.sqrt(2) / 2 * texel * sp.tan(tilt)


coverage = sp.Symbol("tau", nonnegative=True)
surfels = sp.Symbol("m", positive=True, integer=True)


def statistical_visibility() -> sp.Expr:
    """``lim_{m→∞} (1 − τ/m)^m``: the chance that a ray crosses a face whose blocking ``τ``
    is shared by ``m`` independent, uniformly placed surfels, as they become many."""
    return sp.limit((1 - coverage / surfels) ** surfels, surfels, sp.oo)


def statistical_first_order() -> sp.Expr:
    """``exp(−τ)`` to first order in ``τ``: the linear blocker ``1 − τ``."""
    return sp.series(statistical_visibility(), coverage, 0, 2).removeO()


def results() -> list[Result]:
    return [
        result(MODULE, "one_sided", sp.ImmutableMatrix(area / cell**2 * one_sided()),
               "Geometry-volume SH added by a one-sided occluder surfel of area A "
               "(cell size s)."),
        result(MODULE, "double_sided_lobe", double_sided_lobe(),
               "lobe(n) + lobe(−n): band 1 cancels for every normal n, leaving (√π, 0, 0, 0)."),
        result(MODULE, "double_sided_blocking", isotropic_blocking(),
               "A double-sided surfel blocks the same amount, 1/2 per unit A/s², in every "
               "direction."),
        result(MODULE, "camera_surfel_area", camera_surfel_area(),
               "World area of a camera pixel at view depth w on a plane facing the camera "
               "(vertical field of view θ_y, H pixels high): the RSM texel's rule."),
        result(MODULE, "statistical_visibility", statistical_visibility(),
               "Visibility of a face of blocking τ shared by many small surfels placed "
               "independently at random: lim (1 − τ/m)^m = exp(−τ)."),
        result(MODULE, "statistical_first_order", statistical_first_order(),
               "exp(−τ) to first order in τ: the LPV paper's linear blocker 1 − τ."),
        result(MODULE, "reprojection_depth_bound", reprojection_depth_bound(),
               "How far the shadow map's stored depth can differ from a point's own depth on "
               "the same plane: half a texel diagonal times tan θ."),
    ]
