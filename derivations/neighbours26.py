r"""Propagation over 26 neighbours: the faces, their exact solid angles and the flux of a step.

The six-neighbour step (docs/MODEL.md "Propagation") sends a source cell's light through the
five exit faces of each face neighbour: its far ("front") face and four side faces. The side
faces are shared with the edge neighbours, so the light that really travels on towards an
edge or corner neighbour is kept in the face neighbour and turned sideways.

With 26 neighbours a ray from the source centre is booked to the neighbour through which it
leaves the 3×3×3 block of cells around the source, through the face it leaves by. With the
source centre at the origin and cells of side 2 the block is ``[-3, 3]³``; its surface is 54
squares of side 2, each the outer face of exactly one neighbour at offset ``o ∈ {-1, 0, 1}³``:

* a face neighbour (6, ``o = ±e_i``): its front face ``x_i = 3·o_i``, ``[-1, 1]²``: the same
  face, solid angle and directions as the six-neighbour front face;
* an edge neighbour (12, two non-zero components): two faces, e.g. for ``o = (1, 0, 1)`` the
  squares ``x = 3``, ``y ∈ [-1, 1]``, ``z ∈ [1, 3]`` and ``z = 3``, ``x ∈ [1, 3]``,
  ``y ∈ [-1, 1]``, each ``Δω_edge``;
* a corner neighbour (8): three faces, e.g. ``x = 3``, ``y, z ∈ [1, 3]``, each
  ``Δω_corner``.

A face in the plane ``x_i = 3·o_i`` is evaluated towards its centre (the point ``2·o`` with
component ``i`` replaced by ``3·o_i``, as the six-neighbour side faces are) and reprojected
along its normal ``o_i·e_i``. The 54 squares tile the block's surface, so their projections
tile the sphere exactly once: ``6·Δω_front + 24·Δω_edge + 24·Δω_corner = 4π``
(:func:`tiling`; one face of the block gives ``Δω_front + 4·Δω_edge + 4·Δω_corner = 2π/3``).
The face set has the cube's full symmetry, so ``Σ_f Δω_f·Y_k(e_f) = 0`` for every band-1
and band-2 function (:func:`basis_sums`): the corrected step conserves flux with L1 and L2.

The six-neighbour side faces are not used: their light is now the edge and corner
neighbours'. The near faces of the neighbours (shared with the source or another neighbour)
are entry faces, crossed on the way in.

Examples
--------
>>> from derivations.neighbours26 import edge_face, corner_face
>>> edge_face()
-2*atan(sqrt(11)/33) + 2*atan(sqrt(19)/19)
>>> corner_face()
-2*atan(sqrt(19)/19) + atan(sqrt(11)/33) + pi/6
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import cache

import sympy as sp

from derivations import sh
from derivations.registry import Result, result
from derivations.solid_angles import axis_aligned_rectangle_solid_angle, front_face

MODULE = "neighbours26"


@dataclass(frozen=True)
class OuterFace:
    """One of the 54 outer faces of the 3×3×3 block, owned by the neighbour ``offset``."""

    offset: tuple[int, int, int]
    axis: int
    solid_angle: sp.Expr
    evaluation: sp.Matrix
    """Unit direction from the source centre to the face centre."""
    reprojection: sp.Matrix
    """The face normal ``offset[axis]·e_axis``."""

    @property
    def kind(self) -> str:
        return ("front", "edge", "corner")[sum(1 for c in self.offset if c) - 1]


def neighbour_offsets() -> list[tuple[int, int, int]]:
    """The 26 offsets ``o ∈ {-1, 0, 1}³ \\ {0}``."""
    return [o for o in itertools.product((-1, 0, 1), repeat=3) if any(o)]


def outer_faces(offset: tuple[int, int, int]) -> list[OuterFace]:
    """The faces of neighbour ``offset`` on the surface of the block ``[-3, 3]³`` (cells of
    side 2, source centre at the origin): one per non-zero component."""
    faces = []
    for axis in range(3):
        if offset[axis] == 0:
            continue
        others = [k for k in range(3) if k != axis]
        low = [2 * offset[k] - 1 for k in others]
        high = [2 * offset[k] + 1 for k in others]
        angle = axis_aligned_rectangle_solid_angle((0, 0, 0), axis, 3 * offset[axis], low, high)
        centre = [sp.Integer(2 * c) for c in offset]
        centre[axis] = sp.Integer(3 * offset[axis])
        normal = [0, 0, 0]
        normal[axis] = offset[axis]
        vector = sp.Matrix(centre)
        faces.append(OuterFace(offset, axis, sp.simplify(angle),
                               vector / sp.sqrt(vector.dot(vector)), sp.Matrix(normal)))
    return faces


@cache
def all_faces() -> tuple[OuterFace, ...]:
    """The 54 outer faces of the 26 neighbours, neighbour by neighbour."""
    return tuple(face for o in neighbour_offsets() for face in outer_faces(o))


def edge_face() -> sp.Expr:
    """``x = 3``, ``y ∈ [-1, 1]``, ``z ∈ [1, 3]``: one of an edge neighbour's two faces."""
    return sp.simplify(axis_aligned_rectangle_solid_angle((0, 0, 0), 0, 3, (-1, 1), (1, 3)))


def corner_face() -> sp.Expr:
    """``x = 3``, ``y, z ∈ [1, 3]``: one of a corner neighbour's three faces."""
    return sp.simplify(axis_aligned_rectangle_solid_angle((0, 0, 0), 0, 3, (1, 1), (3, 3)))


@cache
def tiling() -> sp.Expr:
    """``Σ_f Δω_f`` over the 54 faces minus 4π, simplified: exactly 0."""
    return sp.simplify(sum((face.solid_angle for face in all_faces()), sp.S.Zero) - 4 * sp.pi)


@cache
def block_face_tiling() -> sp.Expr:
    """``Δω_front + 4·Δω_edge + 4·Δω_corner − 2π/3`` (one face of the block): exactly 0."""
    return sp.simplify(front_face() + 4 * edge_face() + 4 * corner_face() - 2 * sp.pi / 3)


@cache
def basis_sums() -> sp.Matrix:
    """``Σ_f Δω_f·Y_k(e_f)`` of the L2 basis over the 54 faces: ``(4π·c0, 0, …, 0)``: only
    band 0 survives, so a step conserves flux with L1 and L2 (the argument of
    ``propagation.face_basis_sums``)."""
    x, y, z = sh.x, sh.y, sh.z
    total = sp.zeros(len(sh.L2_BASIS), 1)
    for face in all_faces():
        at = dict(zip((x, y, z), list(face.evaluation)))
        total += face.solid_angle * sp.Matrix([b.subs(at, simultaneous=True)
                                               for b in sh.L2_BASIS])
    return total.applyfunc(sp.simplify)


@cache
def step_flux_factor() -> sp.Expr:
    """Flux out ÷ flux in of one corrected 26-neighbour step (weights ``Δω_f/π``, no clamp,
    occlusion or border): 1."""
    s = sp.Matrix(sp.symbols("s_0:9"))
    out = sp.zeros(9, 1)
    for face in all_faces():
        at = dict(zip((sh.x, sh.y, sh.z), list(face.evaluation)))
        basis = sp.Matrix([b.subs(at, simultaneous=True) for b in sh.L2_BASIS])
        out += face.solid_angle / sp.pi * s.dot(basis) * sp.Matrix(
            sh.lobe_l2(list(face.reprojection)))
    # flux of an SH vector: only band 0 integrates to non-zero (sh.flux_of)
    return sp.simplify(sh.flux_of([out[0]]) / sh.flux_of([s[0]]))


def _evaluation_components(kind: str) -> tuple[sp.Expr, sp.Expr]:
    """(along the face normal, along each other non-zero offset axis) of ``e_f``."""
    offset = {"edge": (1, 0, 1), "corner": (1, 1, 1)}[kind]
    face = outer_faces(offset)[0]          # the face x = 3
    return face.evaluation[0], face.evaluation[2]


def results() -> list[Result]:
    edge, corner = edge_face(), corner_face()
    edge_big, edge_small = _evaluation_components("edge")
    corner_big, corner_small = _evaluation_components("corner")
    return [
        result(MODULE, "edge_face", edge,
               "Solid angle of one of an edge neighbour's two outer faces (on the surface "
               "of the 3×3×3 block) seen from the source cell centre.",
               glsl_name="EDGE_FACE_SOLID_ANGLE"),
        result(MODULE, "corner_face", corner,
               "Solid angle of one of a corner neighbour's three outer faces seen from the "
               "source cell centre.",
               glsl_name="CORNER_FACE_SOLID_ANGLE"),
        result(MODULE, "edge_eval_big", edge_big,
               "Edge-face evaluation direction: component along the face normal, 3/√13.",
               glsl_name="EDGE_EVAL_BIG"),
        result(MODULE, "edge_eval_small", edge_small,
               "Edge-face evaluation direction: component along the other offset axis, 2/√13.",
               glsl_name="EDGE_EVAL_SMALL"),
        result(MODULE, "corner_eval_big", corner_big,
               "Corner-face evaluation direction: component along the face normal, 3/√17.",
               glsl_name="CORNER_EVAL_BIG"),
        result(MODULE, "corner_eval_small", corner_small,
               "Corner-face evaluation direction: component along each other axis, 2/√17.",
               glsl_name="CORNER_EVAL_SMALL"),
        result(MODULE, "tiling",
               sp.Eq(sp.UnevaluatedExpr(6 * front_face() + 24 * edge + 24 * corner),
                     tiling() + 4 * sp.pi, evaluate=False),
               "The 54 outer faces of the 26 neighbours cover the sphere exactly once."),
        result(MODULE, "block_face_tiling",
               sp.Eq(sp.UnevaluatedExpr(front_face() + 4 * edge + 4 * corner),
                     block_face_tiling() + 2 * sp.pi / 3, evaluate=False),
               "One face of the 3×3×3 block: a front, four edge and four corner faces, 2π/3."),
        result(MODULE, "step_flux_factor", step_flux_factor(),
               "Flux after ÷ before one corrected 26-neighbour step (L1 or L2), without "
               "clamping, occlusion or border."),
    ]
