r"""Geometry and flux balance of one propagation step (docs/MODEL.md, "Propagation").

Faces. With unit cells, source centre at the origin and the target cell centred at
``d`` (a unit axis vector), the target's far face (normal ``d``) is evaluated and
reprojected along ``d``. A side face (normal ``u``, ``u ⟂ d``) has its centre at
``u/2 + d``; the direction from the source centre to it, normalised, is the
evaluation direction (annotations §6.1):

.. math:: e = \frac{u/2 + d}{\lVert u/2 + d\rVert} = \frac{1}{\sqrt5}\,u + \frac{2}{\sqrt5}\,d,

e.g. ``(1/√5, 2/√5, 0)`` for ``u = x``, ``d = y``; it is reprojected along ``u``.

Flux per step. For each of the 30 faces ``f``:
``out += k_R·k_I·k_P·Δω_f·dot(s, Y(e_f))·lobe(r_f)`` (no clamping, occlusion or border).
The lobe carries ``π`` of flux, band 1 of ``Σ_f Δω_f·Y(e_f)`` vanishes by symmetry and
``Σ_f Δω_f = 6(Δω_front + 4Δω_side) = 4π`` (``solid_angles.tiling``), so one step maps
flux ``Φ`` to ``π·k_R·k_I·k_P·Φ``: ``Φ/(4π)`` with the published formulas and ``Φ`` with
the corrected ones. :func:`step_flux_factor` computes this sum symbolically over all 30
faces.

The DX11 article weights the front face by ``Δω_front/(2π)`` and side faces by
``Δω_side/(3π)`` with no reprojection or injection factor: its step factor is
``(3Δω_front + 8Δω_side)/(4π) ≈ 0.365``.

Examples
--------
>>> from derivations.propagation import side_evaluation_direction
>>> side_evaluation_direction((1, 0, 0), (0, 1, 0)).T
Matrix([[sqrt(5)/5, 2*sqrt(5)/5, 0]])

References
----------
A. Kirsch, "Light Propagation Volumes — Annotations" (2010), §6.
A. Kaplanyan, C. Dachsbacher, "Cascaded Light Propagation Volumes", I3D 2010, §4.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache

import sympy as sp

from derivations import sh
from derivations.registry import Result, result
from derivations.solid_angles import side_face, tiling_proof, unit

MODULE = "propagation"

k_I, k_P, k_R = sp.symbols("k_I k_P k_R", positive=True)
omega_front, omega_side = sp.symbols("Delta_omega_front Delta_omega_side", positive=True)

AXES = tuple(tuple(int(i == j) * s for j in range(3)) for i in range(3) for s in (1, -1))
"""The six neighbour directions ±x, ±y, ±z."""


@dataclass(frozen=True)
class Face:
    """One face of the target cell seen from the source cell centre."""

    kind: str                   # "front" | "side"
    solid_angle: sp.Expr
    evaluation: sp.Matrix       # direction where the source intensity is evaluated
    reprojection: sp.Matrix     # axis of the re-emitted cosine lobe (the face normal)


def side_evaluation_direction(u: Sequence[int], d: Sequence[int]) -> sp.Matrix:
    """Unit direction from the source centre to the centre ``u/2 + d`` of a side face."""
    u_vec, d_vec = sp.Matrix(u), sp.Matrix(d)
    if u_vec.dot(d_vec) != 0:
        raise ValueError(f"side normal {tuple(u)} must be perpendicular to {tuple(d)}")
    return unit(u_vec / 2 + d_vec)


def faces(direction: Sequence[int], front: sp.Expr = omega_front,
          side: sp.Expr = omega_side) -> list[Face]:
    """The five faces of the neighbour along ``direction`` (front first)."""
    d = sp.Matrix(direction)
    out = [Face("front", front, d, d)]
    for axis in AXES:
        u = sp.Matrix(axis)
        if u.dot(d) == 0:
            out.append(Face("side", side, side_evaluation_direction(axis, direction), u))
    return out


@cache
def step_output(front_weight: sp.Expr | None = None,
                side_weight: sp.Expr | None = None) -> sp.Matrix:
    """SH vector one source cell ``s = (s0..s3)`` sends out over all 30 faces.

    A face ``f`` contributes ``w_f·dot(s, Y(e_f))·lobe(r_f)``; the weights default to
    ``k_R·k_I·k_P·Δω`` (docs/MODEL.md), without clamping, occlusion or border loss.
    """
    s = sp.symbols("s_0:4")
    front_weight = k_R * k_I * k_P * omega_front if front_weight is None else front_weight
    side_weight = k_R * k_I * k_P * omega_side if side_weight is None else side_weight
    total = sp.zeros(4, 1)
    for direction in AXES:
        for face in faces(direction):
            weight = front_weight if face.kind == "front" else side_weight
            intensity = sh.evaluate(s, list(face.evaluation))
            total += weight * intensity * sp.Matrix(sh.lobe(list(face.reprojection)))
    return total.applyfunc(lambda entry: sp.factor(sp.expand(entry)))


def step_flux_ratio(front_weight: sp.Expr | None = None,
                    side_weight: sp.Expr | None = None) -> sp.Expr:
    """Flux out ÷ flux in of one step, summed over the 30 faces (solid angles as given)."""
    s0 = sp.Symbol("s_0")
    out = step_output(front_weight, side_weight)
    ratio = sp.simplify(sh.flux_of(list(out)) / sh.flux_of([s0, 0, 0, 0]))
    if ratio.has(*sp.symbols("s_1:4")):
        raise AssertionError(f"band 1 did not cancel over the 30 faces: {ratio}")
    return ratio


def step_flux_factor(front_weight: sp.Expr | None = None,
                     side_weight: sp.Expr | None = None) -> sp.Expr:
    """Flux out ÷ flux in of one step, with the tiling identity substituted exactly."""
    ratio = step_flux_ratio(front_weight, side_weight)
    # 6(front + 4 side) = 4π, proved in solid_angles.tiling_proof.
    if not tiling_proof().holds:
        raise AssertionError("the tiling identity failed")
    return sp.simplify(ratio.subs(omega_front, 2 * sp.pi / 3 - 4 * omega_side))


def face_basis_sums(basis: Sequence[sp.Expr] = sh.L2_BASIS) -> dict[str, sp.Matrix]:
    """``Σ Y_k(e_f)`` over the 6 front faces and over the 24 side faces of one step.

    A step sends ``Σ_f w_f·⟨s, Y(e_f)⟩·lobe(r_f)``; every reprojected lobe carries the same
    flux per unit intensity, so the flux out is ``Σ_k s_k·Σ_f w_f·Y_k(e_f)`` times that.
    Both sums vanish for every band-1 and band-2 function (the face set has the cube's
    symmetry, and bands 1 and 2 hold no cube-invariant function), so only ``s_0`` is
    carried, with L1 and with L2 alike: the corrected step conserves flux for both.
    """
    x, y, z = sh.x, sh.y, sh.z
    sums = {"front": sp.zeros(len(basis), 1), "side": sp.zeros(len(basis), 1)}
    for direction in AXES:
        for face in faces(direction):
            at = dict(zip((x, y, z), list(face.evaluation)))
            sums[face.kind] += sp.Matrix([b.subs(at, simultaneous=True) for b in basis])
    return {kind: total.applyfunc(sp.simplify) for kind, total in sums.items()}


def step_flux_factor_for(injection_pi: bool, propagation_4pi: bool,
                         reprojection_pi: bool) -> sp.Expr:
    """Step flux factor for a choice of the three corrections (True = corrected)."""
    factors = {k_I: 1 / sp.pi if injection_pi else 1,
               k_P: 1 if propagation_4pi else 1 / (4 * sp.pi),
               k_R: 1 if reprojection_pi else 1 / sp.pi}
    return sp.simplify(step_flux_factor().subs(factors))


DX11_WEIGHTS = (omega_front / (2 * sp.pi), omega_side / (3 * sp.pi))
"""The DX11 shader's face weights: ``0.4006696846/Pi/2`` and ``0.4234413544/Pi/3``."""


def dx11_step_flux_factor() -> sp.Expr:
    """Step factor with the DX11 weights Δω_front/(2π), Δω_side/(3π) (no k's), exact
    solid angles: ``(Δω_front + 4π/3)/(4π) = 5/6 − 2·atan(3√11/11)/π``."""
    ratio = step_flux_factor(*DX11_WEIGHTS)  # tiling already used: depends on Δω_side only
    return sp.expand(ratio.subs(omega_side, side_face()))


def results() -> list[Result]:
    e_side = side_evaluation_direction((1, 0, 0), (0, 1, 0))
    general = step_flux_factor()
    dx11_front, dx11_side = DX11_WEIGHTS
    return [
        result(MODULE, "side_eval_direction", sp.ImmutableMatrix(e_side),
               "Evaluation direction of the side face x = 1/2 of the neighbour along +y: "
               "towards the face centre (1/2, 1, 0)."),
        result(MODULE, "side_eval_small", e_side[0],
               "Side-face evaluation direction: component along the side normal, 1/√5.",
               glsl_name="SIDE_EVAL_SMALL"),
        result(MODULE, "side_eval_big", e_side[1],
               "Side-face evaluation direction: component along the propagation axis, 2/√5.",
               glsl_name="SIDE_EVAL_BIG"),
        result(MODULE, "side_reprojection_direction", sp.ImmutableMatrix([1, 0, 0]),
               "Side-face reprojection direction: the face normal (here +x)."),
        result(MODULE, "front_reprojection_direction", sp.ImmutableMatrix([0, 1, 0]),
               "Front-face evaluation and reprojection direction: the propagation axis "
               "(here +y)."),
        result(MODULE, "l2_face_basis_sums", sp.ImmutableMatrix.hstack(
            *(face_basis_sums()[kind] for kind in ("front", "side"))),
               "Σ Y_k(e_f) of the L2 basis over the 6 front faces (column 0) and the 24 "
               "side faces (column 1): only band 0 survives, so a corrected L2 step "
               "conserves flux like an L1 step."),
        result(MODULE, "step_flux_factor", general,
               "Flux after ÷ before one propagation step, without clamping, occlusion or "
               "border: π·k_R·k_I·k_P."),
        result(MODULE, "step_flux_factor_original",
               step_flux_factor_for(False, False, False),
               "One propagation step with the published formulas keeps 1/(4π) of the flux."),
        result(MODULE, "step_flux_factor_corrected",
               step_flux_factor_for(True, True, True),
               "One propagation step with the corrected formulas keeps all the flux."),
        result(MODULE, "step_flux_factor_dx11", dx11_step_flux_factor(),
               "One step of the DX11 shader (weights Δω/(2π) front, Δω/(3π) side): "
               "(3Δω_front + 8Δω_side)/(4π)."),
        result(MODULE, "front_weight_dx11", sp.simplify(dx11_front / omega_front),
               "DX11 front-face factor ÷ Δω_front, the whole factor of the face: 1/(2π) "
               "(corrected model: k_P·k_R·k_I = 1/π; published: 1/(4π²))."),
        result(MODULE, "side_weight_dx11", sp.simplify(dx11_side / omega_side),
               "DX11 side-face factor ÷ Δω_side, the whole factor of the face: 1/(3π) "
               "(corrected model: k_P·k_R·k_I = 1/π; published: 1/(4π²))."),
        result(MODULE, "front_share_dx11", sp.simplify(dx11_front / omega_front * sp.pi),
               "DX11 front-face factor ÷ the corrected model's 1/π: 1/2 (the shader's "
               "Δω_front/PI/2).", glsl_name="DX11_FRONT_SHARE"),
        result(MODULE, "side_share_dx11", sp.simplify(dx11_side / omega_side * sp.pi),
               "DX11 side-face factor ÷ the corrected model's 1/π: 1/3 (the shader's "
               "Δω_side/PI/3).", glsl_name="DX11_SIDE_SHARE"),
    ]
