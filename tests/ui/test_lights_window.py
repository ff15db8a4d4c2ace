"""The window's Lights & objects panel, its animation clock and the object gizmo: the
clock and the gizmo's matrix are checked without a window (they only change the app
state); the panel and the gizmo are drawn in a real window under Xvfb."""

from __future__ import annotations

import numpy as np
import pytest
from window_cases import display_problem

from explorer.lpv.settings import Settings
from explorer.scene import ObjectTransform, load_scene
from explorer.scene.animation import camera_at, pose_changes
from explorer.ui.animation import MAX_STEP_S, animation_of, tick
from explorer.ui.state import AppState

TINY = Settings(grid_size=16, iterations=4, rsm_size=64, width=256, height=192)


def loaded(state: AppState, name: str) -> AppState:
    """``state`` as the app leaves it once the pipeline loaded scene ``name``."""
    state.settings = state.settings.with_changes(scene=name)
    state.runtime.scene_facts.scene = (name, load_scene(name))
    return state


def test_the_clock_plays_the_paths_into_the_settings():
    state = loaded(AppState(settings=TINY), "cornell")
    scene = state.runtime.scene_facts.scene[1]
    animation = animation_of(state)
    assert not tick(state, 10.0)                     # nothing plays: nothing changes
    assert state.settings.light is None
    animation.playing, animation.speed = True, 2.0
    assert tick(state, 10.1)
    expected = pose_changes(scene, animation.seconds)
    assert animation.seconds == pytest.approx(0.2)
    assert state.settings.light == expected["light"]
    assert state.settings.object_transforms == expected["object_transforms"]
    # a slow frame advances the clock by MAX_STEP_S at most
    tick(state, 20.0)
    assert animation.seconds == pytest.approx(0.2 + 2.0 * MAX_STEP_S)
    # only the chosen paths play; an object moved by hand keeps its transform
    animation.paths = ("light",)
    state.update(object_transforms={"tall block": (0.0, 0.1, 0.0)})
    before = dict(state.settings.object_transforms)
    tick(state, 20.1)
    assert dict(state.settings.object_transforms) == before
    assert state.settings.light == pose_changes(scene, animation.seconds, ["light"])["light"]


def test_the_fly_through_moves_the_camera_along_the_path():
    state = loaded(AppState(settings=TINY), "atrium")
    animation = animation_of(state)
    animation.flying, animation.fly_speed = True, 0.05
    tick(state, 0.0)
    tick(state, 0.2)
    assert animation.fly_parameter == pytest.approx(0.01)
    eye, target = camera_at(state.runtime.scene_facts.scene[1], 0.01)
    assert np.allclose(state.settings.camera[0], eye)
    assert np.allclose(state.settings.camera[1], target)
    # a scene without a camera path stops the fly-through and says why
    state = loaded(AppState(settings=TINY), "cornell")
    animation_of(state).flying = True
    tick(state, 0.0)
    tick(state, 0.1)
    assert not animation_of(state).flying
    assert "no camera path" in state.messages[-1].text


def test_a_new_scene_starts_a_new_clock():
    state = loaded(AppState(settings=TINY), "cornell")
    animation_of(state).selected = "short block"
    state = loaded(state, "room")
    assert animation_of(state).selected is None and animation_of(state).scene == "room"


def test_the_gizmo_matrix_becomes_the_objects_transform():
    pytest.importorskip("imgui_bundle")
    from explorer.ui.gizmo import apply_matrix, object_transform

    state = loaded(AppState(settings=TINY), "cornell")
    block = state.runtime.scene_facts.scene[1].object_named("short block")
    wanted = ObjectTransform((0.05, 0.0, -0.1), (0.0, 30.0, 0.0), (1.0, 1.2, 1.0))
    assert apply_matrix(state, block, wanted.model_matrix(block.pivot))
    assert np.allclose(object_transform(state.settings, "short block").values(),
                       wanted.values())
    before = state.settings
    mirror = np.diag([-1.0, 1.0, 1.0, 1.0])
    assert not apply_matrix(state, block, mirror) and state.settings is before
    tiny = ObjectTransform(scale=(1e-3, 1.0, 1.0)).model_matrix(block.pivot)
    assert not apply_matrix(state, block, tiny) and state.settings is before


_PROBLEM = display_problem()


@pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))
def test_the_panel_and_the_gizmo_draw_and_play(tmp_path, monkeypatch):
    """Cornell with two lights and the short block under the gizmo: the panel and the
    gizmo draw without an error, and playing the paths re-runs the pipeline with the
    moved light and block, at the camera drag's reduced size (a frame in flight finishes
    before the next starts) and without idling; paused, the picture converges at full
    size."""
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "config"))
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    from explorer.ui.app import App
    from explorer.ui.window_options import WindowOptions

    state = AppState(settings=TINY.with_changes(lights=("spot", "bulb")))
    app = App(state, WindowOptions(width=900, height=640, visible=False, vsync=False,
                                   persist_settings=False))
    try:
        assert app.settle()
        assert app.state.runtime.scene_facts.scene[0] == "cornell"
        app.state.requests.focus_panel = "Lights & objects"
        animation = animation_of(app.state)
        animation.selected = "short block"
        for operation in ("move", "turn", "scale"):
            animation.operation = operation
            app.frame()
        result = app.state.runtime.frame.result
        assert result.light_names == ("spot", "bulb") and len(result.vpl_sets) == 7
        animation.playing = True
        side = app.controller.sides["A"]
        for _ in range(1000):              # until a frame of the moving scene is shown
            app.frame()
            asked = side.request or side.done
            assert asked.interactive and asked.settings.width < app.state.settings.width
            assert app.interacting()      # a playing animation is no reason to idle
            shown = app.state.runtime.frame.result
            if shown.settings.light is not None:
                break
        assert app.state.settings.light is not None and app.state.settings.object_transforms
        assert "scene" in shown.stages_run and shown.settings.object_transforms
        animation.playing = False
        assert app.settle()
        assert not side.done.interactive
        assert side.done.settings.width == app.state.settings.width
        app.screenshot(tmp_path / "lights.png")
        assert [m.text for m in app.state.messages if m.level == "error"] == []
    finally:
        app.close()
