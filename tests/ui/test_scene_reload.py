"""A scene file edited while the window shows it (explorer/ui/scene_watch.py): the
controller reads it again and renders the edit; an edit that does not load keeps the
scene on screen and says why in one line; the next good edit is shown again."""

from __future__ import annotations

import os

import numpy as np
from test_controller import _settle

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.ui.controller import PipelineController
from explorer.ui.scene_watch import SceneWatch
from explorer.ui.state import AppState

SCENE = """builtin = "cornell"

[[lights]]
kind = "spot"
position = [0.0, 1.9, 0.0]
target = [0.0, 0.0, 0.0]
flux = {flux}
"""


def _write(path, text: str) -> None:
    path.write_text(text, encoding="utf-8")
    stamp = path.stat().st_mtime_ns + 10_000_000      # a later save, whatever the clock
    os.utime(path, ns=(stamp, stamp))


def test_an_edited_scene_file_is_shown_and_a_broken_edit_keeps_the_last(gl_context, ctx,
                                                                         tmp_path):
    path = tmp_path / "scene.toml"
    _write(path, SCENE.format(flux="20.0"))
    settings = Settings(scene=str(path), grid_size=8, iterations=4, rsm_size=32, width=48,
                        height=36)
    state = AppState(settings=settings)
    state.follow_view_size = False
    controller = PipelineController(gl_context, Pipeline)
    try:
        _settle(controller, state)
        controller.poll_shaders(state)          # the first poll starts watching the file
        first = state.runtime.frame.result
        assert first is not None and controller.scene_watch.files == (str(path.resolve()),)

        _write(path, SCENE.format(flux="40.0"))   # twice the light
        controller.poll_shaders(state)
        assert any("changed on disk: reloaded" in m.text for m in state.messages)
        _settle(controller, state)
        second = state.runtime.frame.result
        assert second is not first
        assert np.allclose(second.audit.rsm, 2.0 * first.audit.rsm, rtol=1e-5)

        _write(path, SCENE.format(flux="[broken"))   # not TOML
        controller.poll_shaders(state)
        errors = [m.text for m in state.messages if m.level == "error"]
        assert len(errors) == 1 and "does not load" in errors[0] and str(path) in errors[0]
        assert "\n" not in errors[0]
        _settle(controller, state)
        assert state.runtime.frame.result is second      # still the last good scene

        _write(path, SCENE.format(flux="10.0"))
        controller.poll_shaders(state)
        _settle(controller, state)
        assert np.allclose(state.runtime.frame.result.audit.rsm, 0.5 * first.audit.rsm,
                           rtol=1e-5)
    finally:
        controller.release()


def test_a_file_being_replaced_waits_and_each_change_is_told_once(tmp_path):
    mesh, scene = tmp_path / "room.glb", tmp_path / "scene.toml"
    for path in (mesh, scene):
        _write(path, "one")
    watch = SceneWatch()
    watch.watch("scene.toml", (str(scene), str(mesh)))
    assert not watch.changed()
    _write(mesh, "two")
    assert watch.changed() and not watch.changed()
    scene.unlink()                    # an editor saving by rename: gone for a moment
    assert not watch.changed()
    _write(scene, "three")
    assert watch.changed()
