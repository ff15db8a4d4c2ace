"""Every sentence of the course that says where a vector points or which sign a term
takes, checked against the numpy twin (explorer/lpv/twin/light_grid.py, itself tested equal to the
shaders): each case quotes its sentence, which must still be in the lesson, so that a
rewrite of the sentence comes back here."""

from __future__ import annotations

import re

import numpy as np
import pytest

from explorer.lessons import load_all
from explorer.lpv import constants as K
from explorer.lpv.grid import GridSpec
from explorer.lpv.settings import Corrections
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.vpl import VplArrays

UP = np.array([0.0, 1.0, 0.0])


def _step_text(lesson_id: str, number: int) -> str:
    lessons, errors = load_all(check_formula=None)
    assert not errors
    lesson = next(lesson for lesson in lessons if lesson.path.name.startswith(lesson_id))
    step = lesson.step(number)
    figures = " ".join(str(getattr(figure, "caption", "")) for figure in step.figures)
    return re.sub(r"\s+", " ", f"{step.text} {figures}")


def _says(lesson_id: str, number: int, *sentences: str) -> None:
    text = _step_text(lesson_id, number)
    for sentence in sentences:
        assert re.sub(r"\s+", " ", sentence) in text, f"{lesson_id}/{number}: {sentence!r}"


def _one_cell_grid(n: int, cell: tuple[int, int, int], lobe: np.ndarray) -> np.ndarray:
    grid = np.zeros((3, n, n, n, 4))
    grid[(slice(None), *cell)] = lobe
    return grid


def _wall(n: int, x_corner: int, normal: np.ndarray) -> np.ndarray:
    """A geometry volume ((n+1)³ corners) whose corner plane x = ``x_corner`` holds a wall
    of full cover (A/h² = 1 per corner) facing ``normal``."""
    geometry = np.zeros((n + 1, n + 1, n + 1, 4))
    geometry[x_corner] = twin.cosine_lobe(normal)
    return geometry


def test_09_3_the_blocker_is_evaluated_against_the_evaluation_direction():
    _says("09", 3, "evaluated *against* the face's evaluation direction $e_f$, at $-e_f$",
          "a lit wall does not block the bounce it sends out along its normal")
    _says("16", 2, "a surfel facing the camera stops light running into the face you see")
    plus_x = np.array([1.0, 0.0, 0.0])
    n = 3
    source, target = (0, 1, 1), (1, 1, 1)          # the face between them: corners x = 1
    grid = _one_cell_grid(n, source, twin.cosine_lobe(plus_x))   # light leaving along +x
    free, _ = twin.propagation_step(grid, Corrections())
    # a wall facing +x sends its bounce along +x: its own blockers take none of it
    out, _ = twin.propagation_step(grid, Corrections(), geometry=_wall(n, 1, plus_x))
    np.testing.assert_allclose(out[(slice(None), *target)], free[(slice(None), *target)],
                               atol=1e-12)
    # the same wall turned to face the light (the light runs into its front) blocks it
    out, _ = twin.propagation_step(grid, Corrections(), geometry=_wall(n, 1, -plus_x))
    ratio = twin.flux(out[(slice(None), *target)][:, None, None, None])[0] / \
        twin.flux(free[(slice(None), *target)][:, None, None, None])[0]
    assert 0.0 < ratio < 0.35


def test_09_3_a_full_wall_blocks_three_quarters_head_on_and_a_quarter_edge_on():
    _says("09", 3, "seen head on, evaluates to $1/4 + 1/2 = 3/4$",
          "Seen edge-on it still blocks $1/4$")
    blocker = twin.cosine_lobe(UP)
    # head on: light travelling along −n, evaluated at −e_f = n
    assert blocker @ twin.sh_basis(UP) == pytest.approx(0.75, abs=1e-12)
    assert blocker @ twin.sh_basis(np.array([1.0, 0.0, 0.0])) == pytest.approx(0.25,
                                                                              abs=1e-12)


def test_04_the_lobe_points_along_its_normal_and_its_back_is_negative():
    _says("04", 2, "a lobe pointing up along its normal",
          "the only band-1 weight that is not zero is that of $Y_1$, $-\\sqrt{\\pi/3}$")
    _says("04", 3, "the small blue cap under each is the negative back, a third the "
          "length of the front")
    lobe = twin.cosine_lobe(UP)
    assert lobe[1] == pytest.approx(-np.sqrt(np.pi / 3.0), abs=1e-12)
    assert lobe[2] == lobe[3] == 0.0
    directions = np.random.default_rng(3).normal(size=(4000, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    values = twin.sh_basis(directions) @ lobe
    assert (directions[np.argmax(values)] @ UP) > 0.99      # its peak: along the normal
    front, back = lobe @ twin.sh_basis(UP), lobe @ twin.sh_basis(-UP)
    assert back < 0.0 and -back / front == pytest.approx(1.0 / 3.0, abs=1e-12)


def test_06_the_injection_offset_moves_a_vpl_along_its_normal():
    _says("06", 5, "move each VPL half a cell along its normal", "$p' = p + h\\,n_p/2$")
    spec = GridSpec((0.0, 0.0, 0.0), 0.25, 8)
    vpls = VplArrays(positions=np.array([[1.0, 1.0, 1.0]]), normals=UP[None],
                     flux=np.ones((1, 3)), depth=np.ones(1), texel_area=1.0)
    moved = twin.injection_positions(vpls, spec, 0.5)
    np.testing.assert_allclose(moved[0] - vpls.positions[0], 0.5 * spec.cell_size * UP)


def test_07_negative_light_below_a_patch_comes_through_the_side_faces():
    _says("07", 2, "The cells just below it hold a little negative light (blue): their side "
          "faces saw the negative back of the injected lobes, and only front faces are "
          "clamped.")
    n = 3
    grid = _one_cell_grid(n, (1, 1, 1), twin.cosine_lobe(UP))
    out, _ = twin.propagation_step(grid, Corrections())
    assert out[0, 1, 0, 1, 0] < 0.0                    # the cell below: negative light
    fronts_only, _ = twin.propagation_step(grid, Corrections(side_faces=False))
    assert fronts_only[0, 1, 0, 1, 0] == 0.0            # its front face was clamped


def test_07_the_side_face_is_evaluated_towards_its_centre_and_reprojected_outward():
    _says("07", 2, "the evaluation direction points at its centre, the reprojection "
          "direction is its outward normal")
    d, u = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    centre = d + 0.5 * u           # the target's +u side face, seen from the source centre
    np.testing.assert_allclose(K.SIDE_EVAL_BIG * d + K.SIDE_EVAL_SMALL * u,
                               centre / np.linalg.norm(centre), atol=1e-15)
    faces = twin._faces(2, 1, True)
    evaluation, reprojection, _ = next(face for face in faces if face[1] @ u > 0.5)
    np.testing.assert_allclose(evaluation, centre / np.linalg.norm(centre), atol=1e-15)
    np.testing.assert_allclose(reprojection, u)


def test_08_the_front_face_emits_into_the_target():
    _says("08", 1, "LPV treats the face like a small diffuse emitter facing into the cell")
    for axis, sign in twin.DIRECTIONS:
        evaluation, reprojection, front = twin._faces(axis, sign, True)[0]
        assert front
        forward = np.zeros(3)
        forward[axis] = sign                          # from the source into the target
        np.testing.assert_allclose(reprojection, forward)


def test_10_the_gather_sees_the_light_arriving_against_the_normal():
    _says("10", 2, "Light that reaches the surface travels *against* the normal, so the "
          "surface sees the directions around $-n$.")
    _says("10", 4, "$\\langle s, Y(-n)\\rangle$, which is the *intensity* toward $-n$")
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 3)
    falling = _one_cell_grid(3, (1, 1, 1), twin.cosine_lobe(-UP))   # light heading down
    centre = np.array([[1.5, 1.5, 1.5]])
    floor = twin.gather_irradiance(falling, spec, centre, UP[None])
    ceiling = twin.gather_irradiance(falling, spec, centre, -UP[None])
    assert floor[0, 0] > 0.0 and ceiling[0, 0] == 0.0
