"""The 26-neighbour faces (derivations/neighbours26.py): exact tiling and flux."""

from __future__ import annotations

import sympy as sp

from derivations import neighbours26 as n26
from derivations.solid_angles import front_face, spherical_polygon_area


def test_the_54_outer_faces_tile_the_sphere_exactly():
    faces = n26.all_faces()
    assert len(faces) == 54
    assert sorted(f.kind for f in faces).count("edge") == 24
    assert sorted(f.kind for f in faces).count("corner") == 24
    assert n26.tiling() == 0
    total = sum((f.solid_angle for f in faces), sp.S.Zero)
    assert sp.simplify(total - 4 * sp.pi) == 0
    assert n26.block_face_tiling() == 0
    assert sp.simplify(front_face() + 4 * n26.edge_face() + 4 * n26.corner_face()
                       - 2 * sp.pi / 3) == 0


def test_face_neighbours_keep_the_six_neighbour_front_face():
    fronts = [f for f in n26.all_faces() if f.kind == "front"]
    assert len(fronts) == 6
    assert all(sp.simplify(f.solid_angle - front_face()) == 0 for f in fronts)
    assert all(f.evaluation == f.reprojection for f in fronts)


def test_edge_and_corner_faces_agree_with_spherical_trigonometry():
    """An independent method (Girard's excess) for the closed forms, 30 digits."""
    edge = spherical_polygon_area(((3, -1, 1), (3, 1, 1), (3, 1, 3), (3, -1, 3)))
    corner = spherical_polygon_area(((3, 1, 1), (3, 3, 1), (3, 3, 3), (3, 1, 3)))
    assert abs(sp.N(edge - n26.edge_face(), 30)) < 1e-25
    assert abs(sp.N(corner - n26.corner_face(), 30)) < 1e-25


def test_a_step_conserves_flux_with_l1_and_l2():
    sums = n26.basis_sums()
    assert sp.simplify(sums[0] - 2 * sp.sqrt(sp.pi)) == 0      # 4π·c0
    assert all(entry == 0 for entry in sums[1:])
    assert n26.step_flux_factor() == 1


def test_evaluation_directions_point_at_the_face_centres():
    face = n26.outer_faces((1, 0, 1))[0]
    assert face.evaluation == sp.Matrix([3, 0, 2]) / sp.sqrt(13)
    assert face.reprojection == sp.Matrix([1, 0, 0])
    face = n26.outer_faces((-1, 1, 1))[1]
    assert face.evaluation == sp.Matrix([-2, 3, 2]) / sp.sqrt(17)
    assert face.reprojection == sp.Matrix([0, 1, 0])


def test_the_face_count_per_step_is_the_derivations():
    """The face evaluations the course quotes per cell and step (explorer.lpv.neighbours)
    are the derivation's faces: 54 outer faces for 26 neighbours, 6 × 5 for six."""
    from derivations.neighbours26 import all_faces
    from explorer.lpv.neighbours import FACES_PER_STEP

    assert FACES_PER_STEP[26] == len(all_faces()) == 54
    assert FACES_PER_STEP[6] == 6 * 5
