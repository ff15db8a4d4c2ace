"""The overlays in the explorer window under Xvfb, driven through the app state (and, for
picking, imgui mouse events): each overlay changes the view, none runs a pipeline stage,
picking a pixel of the Cornell box reads the frame's arrays, the camera controls re-run
only the camera's stages."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.lpv.settings import Settings
from explorer.lpv.twin import light_grid as twin
from explorer.ui.overlays import picking
from explorer.ui.state import AppState

pytest.importorskip("glfw")
from test_app_window import _PROBLEM, _app, _view_pixels, config_home  # noqa: E402,F401

pytestmark = [pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM)),
              pytest.mark.usefixtures("config_home")]   # settings go to a temporary folder

TINY = Settings(grid_size=16, iterations=4, rsm_size=64, width=256, height=192,
                geometry_volume="one-sided")


class RunCounter:
    """Wraps a pipeline's start() to count the frames asked of it from now on."""

    def __init__(self, pipeline) -> None:
        self.count = 0
        original = pipeline.start

        def counted(*args, **kwargs):
            self.count += 1
            return original(*args, **kwargs)

        pipeline.start = counted


def _settled_app(view_mode: str = "single"):
    state = AppState(settings=TINY)
    state.follow_view_size = False
    state.view_mode = view_mode
    # big enough that the view shows every frame pixel at least once (no pick rounding)
    app = _app(state, width=1600, height=900)
    app.settle()
    assert app.state.runtime.frame.result is not None, app.state.runtime.frame.pipeline_error
    return app


OVERLAYS = [("slice", dict(slice=True)), ("glyphs", dict(glyphs=True)),
            ("vpls", dict(vpls=True)), ("lattice", dict(lattice=True)),
            ("cascade extents", dict(cascade_boxes=True)), ("blockers", dict(blockers=True))]


def test_each_overlay_changes_the_view_and_runs_no_stage():
    app = _settled_app()
    try:
        runs = RunCounter(app.controller.sides["A"].pipeline)
        result = app.state.runtime.frame.result
        app.frame(capture=True)
        plain = _view_pixels(app)
        for name, switches in OVERLAYS:
            for key, value in switches.items():
                setattr(app.state.overlays, key, value)
            app.frame(capture=True)
            shown = _view_pixels(app)
            assert np.abs(shown - plain).sum(axis=2).astype(bool).sum() > 20, name
            for key in switches:
                setattr(app.state.overlays, key, False)
        # the slice moves through the volume: a new picture, still no pass
        app.state.overlays.slice = True
        app.frame(capture=True)
        first = _view_pixels(app)
        app.state.overlays.slice_index = 3
        app.state.overlays.slice_axis = "x"
        app.frame(capture=True)
        assert np.abs(_view_pixels(app) - first).mean() > 0.5
        assert runs.count == 0 and app.state.runtime.frame.result is result
        # the light in flight needs the propagation steps: one run records them (with no
        # progressive pictures, which would gather the accumulation as it grows)
        app.state.progressive = False
        app.state.overlays.slice_quantity = "in-flight"
        app.settle()
        assert runs.count == 1 and app.state.runtime.frame.result.steps is not None
        # the same light again, with its steps: nothing downstream changed
        assert app.state.runtime.frame.result.stages_run == ("propagate",)
        for step in range(TINY.iterations + 1):
            app.state.overlays.slice_step = step
            app.frame()
        assert runs.count == 1
        assert app.state.runtime.services.compositor.notes["A"] == []
        errors = [m.text for m in app.state.messages if m.level == "error"]
        assert errors == []
        assert app.ctx.error == "GL_NO_ERROR"
    finally:
        app.close()


def test_overlays_are_drawn_on_both_sides_of_the_split_view():
    app = _settled_app("split")
    try:
        assert app.state.runtime.frame.compare_result is not None
        runs_a, runs_b = (RunCounter(app.controller.sides[side].pipeline) for side in "AB")
        app.frame(capture=True)
        plain = _view_pixels(app)
        app.state.overlays.vpls = True
        app.state.overlays.vpl_density = 1.0
        app.frame(capture=True)
        changed = np.abs(_view_pixels(app) - plain).sum(axis=2) > 0
        half = changed.shape[1] // 2
        assert changed[:, :half - 8].sum() > 20 and changed[:, half + 8:].sum() > 20
        assert runs_a.count == runs_b.count == 0
    finally:
        app.close()


def _screen_position(app, x: int, y: int) -> tuple[float, float]:
    """Where pixel (x, y) of the frame is drawn, in imgui's screen units."""
    from imgui_bundle import imgui

    x0, y0, x1, y1 = app.state.runtime.view.view_rect
    width, height = app.state.settings.width, app.state.settings.height
    scale = imgui.get_io().display_framebuffer_scale.x or 1.0
    return ((x0 + (x + 0.5) / width * (x1 - x0)) / scale,
            (y0 + (y + 0.5) / height * (y1 - y0)) / scale)


def test_clicking_a_pixel_of_the_cornell_box_picks_the_frames_values():
    from imgui_bundle import imgui

    app = _settled_app()
    try:
        result = app.state.runtime.frame.result
        x, y = 80, 170                          # the floor, left of the short block
        assert result.gbuffer_normal[y, x, 1] > 0.99
        io = imgui.get_io()
        io.add_mouse_pos_event(*_screen_position(app, x, y))
        app.frame()
        assert app.state.runtime.view.hover is None, "a pointer that did not move reads nothing"
        io.add_mouse_pos_event(*_screen_position(app, x + 3, y))
        app.frame()
        io.add_mouse_pos_event(*_screen_position(app, x, y))
        app.frame()
        hover = app.state.runtime.view.hover
        assert hover is not None and hover.pixel == (x, y)
        io.add_mouse_button_event(0, True)
        app.frame()
        io.add_mouse_button_event(0, False)
        app.frame()
        o = app.state.overlays
        assert (o.picked_kind, o.picked_side) == ("pixel", "A")
        assert o.picked_point == tuple(float(v) for v in result.gbuffer_position[y, x, :3])
        pick = hover.pick
        assert np.array_equal(pick.position, result.gbuffer_position[y, x, :3])
        assert np.array_equal(pick.normal, result.gbuffer_normal[y, x, :3])
        assert np.array_equal(pick.direct, result.direct[y, x])
        assert np.array_equal(pick.indirect, result.indirect[y, x])
        cell = tuple(int(v) for v in result.grid_spec.cell_index(pick.position))
        assert picking.cell_at(result, o.picked_cascade, o.picked_point) == cell
        assert np.array_equal(pick.cells[0].coefficients,
                              result.accumulated[(slice(None),) + cell])
        np.testing.assert_allclose(pick.indirect_from_grid, pick.indirect, rtol=1e-4)
        # the picked point is drawn (its cell box and marker) and the Picked panel reads it
        app.frame(capture=True)
        assert app.state.runtime.services.compositor.compositions > 0
        app.state.open_panels["Picked"] = True
        app.state.requests.focus_panel = "Picked"
        for _ in range(2):
            app.frame()
        # a click on the slice plane picks the cell under the mouse
        o.slice, o.slice_axis, o.slice_index = True, "z", 8
        io.add_mouse_pos_event(*_screen_position(app, 128, 60))
        app.frame()
        hover = app.state.runtime.view.hover
        assert hover.cell is not None and hover.cell.index[2] == 8
        # the value under the mouse is the slice's quantity in that cell (acc_N's intensity
        # toward +y, mean of the channels), recomputed here from the arrays
        up = twin.sh_basis(np.array([0.0, 1.0, 0.0]))
        expected = np.dot(result.accumulated[(slice(None),) + hover.cell.index], up).mean()
        assert hover.slice_value[1] == pytest.approx(expected, rel=1e-5)
        io.add_mouse_button_event(0, True)
        app.frame()
        io.add_mouse_button_event(0, False)
        app.frame()
        assert o.picked_kind == "cell"
        assert picking.cell_at(result, o.picked_cascade, o.picked_point)[2] == 8
        errors = [m.text for m in app.state.messages if m.level == "error"]
        assert errors == []
    finally:
        app.close()


def test_the_picked_pixel_reads_its_reference_and_the_picked_cell_its_audit(tmp_path):
    """The Picked panel's reference radiance (computed in the app loop's
    background, equal to the full reference image's pixel) and the picked cell's own audit
    records, read back from the GPU."""
    from explorer.truth.progressive import pixel_reference
    from explorer.truth.render import reference_for_frame
    from explorer.ui.overlays.describe import cell_audit_rows
    from explorer.ui.overlays.in_view import pick_with_references
    from explorer.ui.overlays.pixel_reference import pixel_references

    app = _settled_app()
    try:
        rt, o = app.state.runtime, app.state.overlays
        result = rt.frame.result
        x, y = 80, 170                          # the floor, left of the short block
        o.pick("pixel", "A", 0, result.gbuffer_position[y, x, :3])
        app.state.open_panels["Picked"] = True
        app.state.requests.focus_panel = "Picked"
        service = pixel_references(app.state)
        service.request(result, (x, y))
        for _ in range(20):
            app.frame()
            if len(service.values(result, (x, y))) == 2:
                break
        found = dict(service.values(result, (x, y)))
        assert set(found) == {"visible", "unoccluded"} and service.problem is None
        full, _ = reference_for_frame(result, False, ctx=app.ctx)
        np.testing.assert_allclose(found["unoccluded"], full[y, x], rtol=1e-5)
        np.testing.assert_array_equal(found["visible"],
                                      pixel_reference(app.ctx, result, x, y, True))
        assert found["visible"].max() > 0
        pick = pick_with_references(app.state, result, (x, y))
        assert dict(pick.references).keys() == found.keys()
        # the picked cell's audit: its records on the GPU, and acc_N = grid_0 + received.
        # The default layout's flux plot asks only for the flux per step (no records);
        # the Picked panel, now shown, asks for the full audit: only propagate runs again
        for _ in range(40):
            if rt.frame.result.cascades[0].cell_records is not None:
                break
            app.frame()
        assert rt.frame.result.cascades[0].cell_records is not None
        assert rt.frame.result is not result
        result = rt.frame.result
        cell = picking.cell_at(result, o.picked_cascade, o.picked_point)
        info = picking.cell_audit(result, o.picked_cascade, cell)
        assert isinstance(info, picking.CellAuditInfo) and info.steps == TINY.iterations
        assert info.total.received.max() > 0 and info.last is not None
        labels = [label for label, _ in cell_audit_rows(info)]
        assert "received, all 4 steps" in labels and "occluded, step 4" in labels
        app.frame(capture=True)
        from explorer.ui.images import write_png

        write_png(app.last_pixels, tmp_path / "picked.png")
        errors = [m.text for m in app.state.messages if m.level == "error"]
        assert errors == []
        # a newer propagation overwrites the records: the old frame says so
        app.state.update(iterations=3)
        for _ in range(3):
            app.frame()
        assert rt.frame.result is not result
        other = tuple((c + 1) % 16 for c in cell)
        assert isinstance(picking.cell_audit(result, 0, other), str)
        assert isinstance(picking.cell_audit(rt.frame.result, 0, other), picking.CellAuditInfo)
    finally:
        app.close()


def test_camera_controls_rerun_only_the_camera_stages():
    from explorer.ui import camera_controls

    app = _settled_app()
    try:
        before = app.state.runtime.frame.result
        assert camera_controls.frame_scene(app.state)
        app.settle()
        after = app.state.runtime.frame.result
        assert after is not before and after.stages_run == ("gbuffer", "gather", "display")
        assert after.gbuffer_position[96, 128, 3] > 0.5
        point = after.gbuffer_position[96, 128, :3]
        app.state.overlays.pick("pixel", "A", 0, point)
        assert camera_controls.frame_picked(app.state)
        app.settle()
        framed = app.state.runtime.frame.result
        assert np.allclose(framed.camera.target, point)
        # the picked point stays anchored: the new frame shows it at the image centre
        x, y = picking.pixel_of(framed, point)
        assert abs(x - 128) <= 1 and abs(y - 96) <= 1
    finally:
        app.close()


def test_a_picked_pixels_final_colour_is_exposed_as_the_view_shows_it():
    """The pipelines run with the display's fields pinned (exposure 1); the pixel rows'
    "final (exposed)" carry the exposure and indirect-only the view applies."""
    from explorer.ui.overlays.in_view import pick_with_references

    app = _settled_app()
    try:
        result = app.state.runtime.frame.result
        assert result.settings.exposure == 1.0
        x, y = 80, 170                          # the floor, left of the short block
        for exposure, indirect_only in ((2.5, False), (0.5, True)):
            app.state.update(exposure=exposure, indirect_only=indirect_only)
            app.frame()
            assert app.state.runtime.frame.result is result          # no stage ran
            pick = pick_with_references(app.state, result, (x, y), "A")
            linear = result.indirect[y, x] if indirect_only else \
                result.direct[y, x] + result.indirect[y, x]
            expected = (np.float32(exposure) * linear).astype(np.float32)
            assert np.array_equal(pick.final, np.asarray(expected, np.float64))
            assert pick.final.max() > 0
    finally:
        app.close()
