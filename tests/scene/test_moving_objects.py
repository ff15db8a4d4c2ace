"""Moving objects and animation (docs/MODEL.md "Moving objects and temporal stability"):
object transforms, the scene stage posing them, the stages a move re-runs, animation
paths, the fly-through, and the temporal stability measure."""

from __future__ import annotations

import math

import numpy as np
import pytest

from explorer.cli import main
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.stability import Motion, frame_changes, measure
from explorer.scene import ObjectTransform, SceneError, load_scene
from explorer.scene.animation import camera_at, path_names, pose_changes
from explorer.scene.atrium import fly_through
from explorer.scene.gpu import VERTEX_BYTES, SceneBuffers
from explorer.scene.objects import check_transforms, transform_corners
from explorer.scene.paths import KeyframePath

SMALL = Settings(scene="cornell", grid_size=8, iterations=4, rsm_size=32, width=40,
                 height=32)
SCENE_STAGES = ("scene", "rsm", "downsample", "inject", "geometry", "propagate", "gbuffer",
                "gather", "display")
"""What moving an object re-runs: everything after the scene stage but the grid, whose
specs do not depend on the objects (the geometry stage runs and, with the volume off,
releases nothing new)."""
LIGHT_STAGES = ("rsm", "downsample", "inject", "geometry", "propagate", "gather", "display")
"""What moving the light re-runs: not the G-buffer."""


def test_transform_matrix_round_trips_and_turns_normals_with_the_inverse_transpose():
    transform = ObjectTransform((0.1, -0.2, 0.3), (10.0, -35.0, 70.0), (1.5, 0.5, 2.0))
    pivot = (0.3, -0.4, 0.2)
    back = ObjectTransform.from_model_matrix(transform.model_matrix(pivot), pivot)
    assert np.allclose(back.values(), transform.values())
    # the pivot goes to pivot + translation
    matrix = transform.matrix(pivot)
    assert np.allclose(matrix[:3, :3] @ pivot + matrix[:3, 3], np.add(pivot, (0.1, -0.2, 0.3)))
    # a normal stays perpendicular to its (stretched) surface
    rng = np.random.default_rng(3)
    tangent, other = rng.standard_normal((2, 3))
    normal = np.cross(tangent, other)
    normal /= np.linalg.norm(normal)
    corners = np.array([np.zeros(3), tangent, other])
    moved, turned = transform_corners(corners, np.tile(normal, (3, 1)), transform, pivot)
    assert abs(np.dot(turned[0], moved[1] - moved[0])) < 1e-12
    assert abs(np.dot(turned[0], moved[2] - moved[0])) < 1e-12
    assert np.allclose(np.linalg.norm(turned, axis=1), 1.0)
    with pytest.raises(ValueError, match="mirrors"):
        ObjectTransform.from_model_matrix(np.diag([-1.0, 1.0, 1.0, 1.0]), pivot)


def test_transforms_are_checked_and_normalised():
    assert check_transforms({"b": [1, 2, 3], "a": (0, 0, 0, 0, 90, 0)}) == (
        ("a", (0.0, 0.0, 0.0, 0.0, 90.0, 0.0, 1.0, 1.0, 1.0)),
        ("b", (1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0)))
    for bad in ({"a": [1, 2]}, {"a": [0] * 6 + [0, 1, 1]}, {"a": [math.nan, 0, 0]},
                {"": [0, 0, 0]}, "a=1,2,3", [("a", [0, 0, 0]), ("a", [1, 1, 1])]):
        assert check_transforms(bad) is None
    with pytest.raises(ValueError, match=r"object_transforms must be a table of object "
                                         r"names to \[tx, ty, tz"):
        Settings(object_transforms={"short block": [0, 0]})
    settings = Settings(object_transforms={"short block": [0.1, 0, 0]})
    assert Settings.from_dict(settings.to_dict()) == settings


def test_posing_moves_only_the_named_object_about_its_pivot():
    scene = load_scene("cornell")
    block = scene.object_named("short block")
    posed = scene.posed({"short block": (0.1, 0.0, -0.2, 0.0, 90.0, 0.0)})
    inside = slice(block.first, block.stop)
    outside = np.ones(len(scene.positions), bool)
    outside[inside] = False
    assert np.array_equal(posed.positions[outside], scene.positions[outside])
    # a quarter turn about the vertical through the pivot, then the translation
    local = scene.positions[inside].astype(np.float64) - block.pivot
    turned = np.stack([local[:, 2], local[:, 1], -local[:, 0]], axis=1)
    assert np.allclose(posed.positions[inside], turned + block.pivot + (0.1, 0.0, -0.2),
                       atol=1e-6)
    # posing again starts from the scene as built, not from the last pose
    assert np.array_equal(posed.posed(()).positions, scene.positions)
    assert np.allclose(posed.posed({"short block": (0.1, 0, 0)}).positions,
                       scene.posed({"short block": (0.1, 0, 0)}).positions)
    with pytest.raises(SceneError, match="has no object 'vase'; its objects are box, "
                                         "short block, tall block"):
        scene.posed({"vase": (0, 0, 0)})


def test_scene_buffers_rewrite_only_the_moved_object(gl_context):
    scene = load_scene("cornell")
    buffers = SceneBuffers(gl_context, scene)
    try:
        posed = scene.posed({"tall block": (0.0, 0.1, 0.0)})
        written = buffers.show(posed)
        assert written == scene.object_named("tall block").count
        assert buffers.buffer.read() == posed.vertex_bytes()
        assert buffers.show(posed) == 0                     # nothing moved since
        assert buffers.show(scene) == written               # back to the built pose
        assert len(buffers.buffer.read()) == VERTEX_BYTES * len(scene.positions)
    finally:
        buffers.release()


@pytest.fixture
def pipeline(gl_context, ctx):
    pipe = Pipeline(SMALL, ctx=gl_context)
    yield pipe
    pipe.release()


def test_moving_an_object_re_runs_exactly_the_scene_dependent_stages(pipeline):
    pipeline.run(SMALL)
    moved = pipeline.run(SMALL.with_changes(object_transforms={"short block": (0.1, 0, 0)}))
    assert moved.stages_run == SCENE_STAGES
    # the G-buffer shows the block where it now is
    floor = moved.gbuffer_position
    assert floor.shape[:2] == (32, 40)
    again = pipeline.run(SMALL.with_changes(object_transforms={"short block": (0.1, 0, 0)}))
    assert again.stages_run == ()
    # the light moving re-runs the RSM and what follows it, not the G-buffer
    light = pipeline.run(SMALL.with_changes(object_transforms={"short block": (0.1, 0, 0)},
                                            light=((0.1, 0.9, 0.9), (0.0, -0.5, -0.8))))
    assert light.stages_run == LIGHT_STAGES


def test_an_animated_frame_is_an_ordinary_frame(pipeline):
    """pose_changes turns the scene's paths at a time into Settings fields: the stage
    keys see a moved light and object, and the frame equals the same fields set by
    hand."""
    scene = load_scene("cornell")
    assert path_names(scene) == ("light", "short block")
    at_zero = pose_changes(scene, 0.0)
    assert at_zero["light"] == (scene.light.position, scene.light.target)
    assert dict(at_zero["object_transforms"])["short block"] == (
        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0)
    pipeline.run(SMALL)
    changes = pose_changes(scene, 1.5)
    animated = pipeline.run(SMALL.with_changes(**changes))
    assert animated.stages_run == SCENE_STAGES
    light_only = pose_changes(scene, 2.0, ["light"])
    assert set(light_only) == {"light"}
    assert pipeline.run(SMALL.with_changes(**{**changes, **light_only})
                        ).stages_run == LIGHT_STAGES
    with pytest.raises(SceneError, match="has no animation path 'tall block'; its paths "
                                         "are light, short block"):
        pose_changes(scene, 1.0, ["tall block"])


def test_keyframe_paths_pass_through_their_keys_and_loop():
    keys = [(0.0, 0.0), (1.0, 2.0), (3.0, -1.0), (0.5, 4.0)]
    path = KeyframePath(keys, 8.0)
    for k, key in enumerate(keys):
        assert np.allclose(path.at(2.0 * k), key)
    assert np.allclose(path.at(9.3), path.at(1.3))
    with pytest.raises(ValueError, match="period"):
        KeyframePath(keys, 0.0)


def test_the_fly_through_is_the_atriums_camera_path():
    atrium = load_scene("atrium")
    for t in (0.0, 0.37, 1.8):
        eye, target = camera_at(atrium, t)
        assert np.allclose(eye, fly_through(t)[0]) and np.allclose(target, fly_through(t)[1])
    with pytest.raises(SceneError, match="no camera path"):
        camera_at(load_scene("cornell"), 0.5)


def test_render_fly_through_renders_the_frame_at_the_path_parameter(tmp_path, capsys):
    out = tmp_path / "fly.png"
    assert main(["render", "--scene", "atrium", "--fly-through", "0.25", "--size", "48x32",
                 "--rsm-size", "32", "--grid", "8", "--iterations", "2", "--out",
                 str(out)]) == 0
    assert out.is_file()
    import argparse

    from explorer.commands.render import add_arguments, animated

    parser = argparse.ArgumentParser()
    add_arguments(parser)
    args = parser.parse_args(["--scene", "atrium", "--fly-through", "0.25"])
    settings = animated(args, Settings(scene="atrium"))
    eye, target = fly_through(0.25)
    assert np.allclose(settings.camera[0], eye) and np.allclose(settings.camera[1], target)
    # --time puts the paths there; an explicit --object wins over its path
    args = parser.parse_args(["--time", "1.5", "--object", "short block=0,0.2,0"])
    from explorer.commands import options

    settings = animated(args, options.settings_from_args(args))
    assert dict(settings.object_transforms)["short block"][:3] == (0.0, 0.2, 0.0)
    assert settings.light == pose_changes(load_scene("cornell"), 1.5)["light"]
    assert main(["render", "--fly-through", "0.5", "--out", str(tmp_path / "x.png")]) == 2
    assert "no camera path" in capsys.readouterr().err


def test_frame_changes_on_a_tiny_sequence():
    """Three 2×2 frames: the middle pixel pair changes by 0.1 then not at all, one pixel
    shows another surface point in the last frame (left out)."""
    valid = np.ones((2, 2, 4))
    positions = [valid.copy(), valid.copy(), valid.copy()]
    positions[2][0, 0, :3] = 5.0
    grey = np.full((2, 2, 3), 0.5)
    second = grey.copy()
    second[1, 1] = 0.6
    third = second.copy()
    third[0, 0] = 3.0                                    # a moving object's pixel
    means, peaks, reference = frame_changes([grey, second, third], positions)
    assert reference == pytest.approx(0.5)
    assert means == pytest.approx([0.1 / 4 / 0.5, 0.0])
    assert peaks == pytest.approx([0.1 / 0.5, 0.0])


def test_snapping_keeps_the_light_still_for_a_camera_moving_a_tenth_of_a_cell(pipeline):
    """Cascades that follow the camera: snapped, a move of a tenth of a finest cell per
    frame leaves them in place (until a snap), so the LPV gathered at fixed surface points
    changes less than without snapping, where every frame moves the VPLs to other
    cells."""
    base = SMALL.with_changes(cascades=2, width=32, height=32)
    first = pipeline.run(base)
    motion = Motion("camera", 0.1 * first.grid_spec.cell_size)
    runs = {snap: measure(pipeline.run, lambda s: load_scene(s.scene).for_settings(s), base,
                          motion, 4, snap) for snap in (True, False)}
    assert runs[False].frames_changed == 4 and runs[False].mean > 0.0
    assert runs[True].mean < 0.5 * runs[False].mean
    assert runs[True].frames_changed <= 1


def test_a_still_camera_regathers_the_net_flux_frame_as_the_gpu_did(pipeline):
    """The camera move's numpy regather follows Settings.gather_net_flux (docs/MODEL.md
    "Net-flux gather"): with a step of 0 the first frame's Ȳ_0 is the GPU image's."""
    from explorer.lpv.twin.tonemap import luminance

    base = SMALL.with_changes(gather_net_flux=True, width=32, height=32)
    run = measure(pipeline.run, lambda s: load_scene(s.scene).for_settings(s), base,
                  Motion("camera", 0.0), 1, True)
    first = pipeline.run(base)
    valid = first.gbuffer_position[..., 3] > 0.5
    gpu = float(np.mean(luminance(np.asarray(first.indirect, np.float64))[valid]))
    assert run.reference == pytest.approx(gpu, rel=1e-4)
    assert run.mean == 0.0


def test_stability_command_prints_both_rows(capsys):
    assert main(["stability", "--move", "object", "--frames", "2", "--step", "0.05",
                 "--size", "32x32", "--rsm-size", "16", "--grid", "8"]) == 0
    printed = capsys.readouterr().out
    assert "object 'short block' moves 0.05 m" in printed
    assert "| on |" in printed and "| off |" in printed and "/2 |" in printed
    assert "the two rows are the same frames" in printed
    assert main(["stability", "--move", "object", "--object", "vase", "--frames", "1",
                 "--size", "16x16", "--rsm-size", "8", "--grid", "8"]) == 2
    assert "has no object 'vase'" in capsys.readouterr().err


def test_stability_command_flips_the_rsm_snap_and_refuses_an_unknown_switch(capsys):
    """``--snap rsm``: the rows turn Settings.rsm_snap on and off; a light moving 0.01 m
    a frame (under a seventieth of the spot's texel at RSM 16²) changes no snapped
    frame and every unsnapped one."""
    assert main(["stability", "--snap", "rsm", "--frames", "2", "--step", "0.01",
                 "--size", "32x32", "--rsm-size", "16", "--grid", "8"]) == 0
    printed = capsys.readouterr().out
    assert "| RSM snapping |" in printed
    assert "| on | 0.000 % | 0.00 % | 0/2 |" in printed
    assert "| off |" in printed and "| 2/2 |" in printed
    assert main(["stability", "--move", "camera", "--snap", "rsm", "--frames", "1",
                 "--size", "16x16", "--rsm-size", "8", "--grid", "8"]) == 0
    assert "with a still one neither row's RSM moves" in capsys.readouterr().out
    assert main(["stability", "--snap", "grid"]) == 2
    error = capsys.readouterr().err
    assert "--snap: invalid choice: 'grid'" in error and len(error.splitlines()) == 1


def test_a_turning_light_keeps_its_place_and_turns_its_target_by_the_step():
    """``light-turn``: frame t's target is the first's turned by t·step degrees about the
    axis through the light, at the same distance; the light stays where it is."""
    scene = load_scene("cornell").for_settings(SMALL)
    motion = Motion("light-turn", 2.5, "x")
    position = np.asarray(scene.light.position)
    first = np.asarray(scene.light.target) - position
    for frame in (1, 3):
        settings = motion.settings(SMALL, scene, frame)
        moved_position, target = (np.asarray(p) for p in settings.light)
        np.testing.assert_allclose(moved_position, position, atol=1e-12)
        turned = target - position
        assert np.linalg.norm(turned) == pytest.approx(np.linalg.norm(first), rel=1e-12)
        cosine = turned @ first / (np.linalg.norm(turned) * np.linalg.norm(first))
        assert math.degrees(math.acos(min(cosine, 1.0))) == pytest.approx(2.5 * frame)
        assert turned[0] == pytest.approx(first[0], abs=1e-12)     # about x: x stays


def test_rsm_snapping_leaves_a_turning_light_as_it_is(capsys):
    """The RSM snap is a translation of the light's eye: a spot turning about its own
    position has nothing to snap, so both rows change every frame alike, and the command
    says why; a turn of a point light needs a --step (no texel angle to default to)."""
    assert main(["stability", "--move", "light-turn", "--snap", "rsm", "--frames", "2",
                 "--size", "32x32", "--rsm-size", "16", "--grid", "8"]) == 0
    printed = capsys.readouterr().out
    spot = load_scene("cornell").light
    step = 0.1 * math.degrees(math.atan(2.0 * spot.frustum_half_width / 16))
    assert f"the light 'spot' turns {step:.4g}° per frame about x" in printed
    rows = [line for line in printed.splitlines() if line.startswith(("| on |", "| off |"))]
    assert len(rows) == 2 and rows[0][len("| on "):] == rows[1][len("| off "):]
    assert rows[0].endswith("| 2/2 |")
    assert "has no move to snap, so the two rows are the same frames" in printed
    assert main(["stability", "--move", "light-turn", "--scene", "room", "--lights", "lamp",
                 "--frames", "1", "--size", "16x16", "--rsm-size", "8", "--grid", "8"]) == 2
    error = capsys.readouterr().err
    assert "is a point light: give --step in degrees per frame" in error


def test_a_lesson_step_starts_with_the_scenes_own_lights_and_objects():
    """Lights and objects of the scene on screen would not exist in a step's scene: every
    step starts from its scene's own (unless it sets them)."""
    from explorer.lessons import find_lesson, load_all

    lessons, errors = load_all(check_formula=None)
    lesson = find_lesson("in-practice", lessons, errors)
    base = Settings(lights=("bulb",), object_transforms={"short block": (0.1, 0.0, 0.0)})
    first = lesson.step(1).settings(base)
    assert first.lights is None and first.object_transforms == ()
    several = next(step for step in lesson.steps if step.title == "Several lights in one volume")
    assert several.settings(base).lights == ("sun", "lamp")
