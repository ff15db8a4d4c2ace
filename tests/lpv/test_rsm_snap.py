"""RSM snapping (``Settings.rsm_snap``, explorer/lpv/rsm_snap.py, docs/MODEL.md "Moving
objects and temporal stability"): a light's RSM view moves by whole texels only."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.lpv.passes.rsm import light_views
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.rsm_snap import box_pitch, plane_snap, spot_pitch
from explorer.lpv.settings import Settings
from explorer.lpv.stability import Motion, measure
from explorer.scene import load_scene

SIZE = 32
"""RSM texels per side in these tests."""


def _pitch(view, scene) -> float:
    if view.kind == "spot":
        return spot_pitch(scene.light, SIZE)
    return box_pitch(scene.bounds_min, scene.bounds_max, SIZE)


@pytest.mark.parametrize("scene_name, lights", [("cornell", None), ("room", ("sun",)),
                                                ("room", ("lamp",))])
def test_a_snapped_view_sits_on_its_lattice_within_half_a_texel_of_the_light(scene_name,
                                                                            lights):
    """For lights moved anywhere: the snapped eye's image-plane coordinates are whole
    multiples of the texel pitch, it lies at most half a texel from the unsnapped eye
    along each image-plane axis (so the frustum moves by less than one texel), and the
    view's axes (the light's direction) stay."""
    base = load_scene(scene_name).with_lights(lights)
    rng = np.random.default_rng(7)
    for shift in rng.uniform(-0.4, 0.4, size=(20, 3)):
        light = base.light
        scene = base.with_primary(light.moved(np.add(light.position, shift),
                                              np.add(light.target, shift)))
        exact, snapped = light_views(scene, SIZE)[0], light_views(scene, SIZE, snap=True)[0]
        pitch = _pitch(exact, scene)
        np.testing.assert_allclose(snapped.view[:3, :3], exact.view[:3, :3], atol=1e-12)
        moved = np.asarray(snapped.position) - np.asarray(exact.position)
        # a point light's lattice is cubic, anchored at the box's corner
        anchor = np.asarray(scene.bounds_min) if exact.kind == "point" else np.zeros(3)
        for axis in exact.view[:2, :3]:
            along = float((np.asarray(snapped.position) - anchor) @ axis) / pitch
            assert along == pytest.approx(round(along), abs=1e-9)
            assert abs(float(moved @ axis)) <= 0.5 * pitch + 1e-12
        if exact.kind == "point":      # every face's axes are world axes
            assert np.max(np.abs(moved)) <= 0.5 * pitch + 1e-12
        else:                          # nothing along the light's axis
            assert abs(float(moved @ exact.view[2, :3])) <= 1e-12
        assert np.linalg.norm(moved) < pitch


@pytest.mark.parametrize("scene_name, lights", [("cornell", None), ("room", ("sun",)),
                                                ("room", ("lamp",))])
def test_the_lattice_runs_through_the_light_as_the_scene_placed_it(scene_name, lights):
    """With the scene's own light as the anchor: a light that has not moved keeps its
    exact view (a still frame is the unsnapped one), and a moved one lands on the lattice
    through the anchor, within half a texel of where it was moved to."""
    placed = load_scene(scene_name).with_lights(lights)
    anchors = {light.name: light for light in placed.rig}
    exact = light_views(placed, SIZE)
    still = light_views(placed, SIZE, snap=True, anchors=anchors)
    assert len(still) == len(exact)
    for a, b in zip(exact, still):
        assert np.array_equal(a.view, b.view) and np.array_equal(a.position, b.position)
    light = placed.light
    origin = np.asarray(light.eye(placed.bounds_min, placed.bounds_max)
                        if exact[0].kind == "directional" else light.position)
    shift = np.array([0.37, -0.21, 0.55])
    moved = placed.with_primary(light.moved(np.add(light.position, shift),
                                            np.add(light.target, shift)))
    unsnapped = light_views(moved, SIZE)[0]
    snapped = light_views(moved, SIZE, snap=True, anchors=anchors)[0]
    pitch = _pitch(unsnapped, moved)
    for axis in unsnapped.view[:2, :3]:
        along = float((np.asarray(snapped.position) - origin) @ axis) / pitch
        assert along == pytest.approx(round(along), abs=1e-9)
        offset = float((np.asarray(snapped.position) - unsnapped.position) @ axis)
        assert abs(offset) <= 0.5 * pitch + 1e-12


def test_plane_snap_is_idempotent_and_rejects_a_bad_pitch():
    view = np.eye(4)
    eye = np.array([0.26, -0.74, 3.0])
    shift = plane_snap(eye, view, 0.5)
    np.testing.assert_allclose(shift, [0.24, 0.24, 0.0], atol=1e-15)
    np.testing.assert_allclose(plane_snap(eye + shift, view, 0.5), 0.0, atol=1e-15)
    with pytest.raises(ValueError, match="pitch must be positive"):
        plane_snap(eye, view, 0.0)


@pytest.fixture(scope="module")
def pipeline(gl_context):
    with Pipeline(Settings(scene="cornell")) as owned:
        yield owned


SMALL = Settings(scene="cornell", grid_size=8, iterations=2, rsm_size=SIZE, width=32,
                 height=32)


def test_a_still_frame_is_the_same_with_and_without_snapping(pipeline):
    """The scene's own light is its lattice's anchor: snapping a still frame changes
    nothing (its accuracy against physics neither)."""
    on, off = (pipeline.run(SMALL.with_changes(rsm_snap=snap)) for snap in (True, False))
    assert np.array_equal(on.rsm_position, off.rsm_position)
    assert np.array_equal(on.indirect, off.indirect)


def test_a_sub_texel_light_move_keeps_the_snapped_vpls_and_moves_the_exact_ones(pipeline):
    """Cornell's spot (its own anchor as built) moved by 0.3 of a texel along x: snapped,
    every VPL (RSM texel position and flux) is the one before; exact, they move."""
    scene = load_scene("cornell")
    pitch = spot_pitch(scene.light, SIZE)
    light = scene.light
    moved = (tuple(np.add(light.position, (0.3 * pitch, 0, 0))),
             tuple(np.add(light.target, (0.3 * pitch, 0, 0))))
    for snap in (True, False):
        before = pipeline.run(SMALL.with_changes(rsm_snap=snap))
        after = pipeline.run(SMALL.with_changes(rsm_snap=snap, light=moved))
        same = (np.array_equal(before.rsm_position, after.rsm_position)
                and np.array_equal(before.rsm_flux, after.rsm_flux))
        assert same == snap


def test_snapping_the_rsm_keeps_the_indirect_light_still_between_snaps(pipeline):
    """The stability measure with the light moving a tenth of a finest cell per frame
    (a small share of a texel): snapped, no frame changes before the light has moved half
    a texel; exact, every frame changes."""
    scene = load_scene("cornell")
    step = 0.02 * spot_pitch(scene.light, SIZE)
    runs = {snap: measure(pipeline.run, lambda s: load_scene(s.scene).for_settings(s),
                          SMALL, Motion("light", step), 3, snap, "rsm")
            for snap in (True, False)}
    assert runs[True].frames_changed == 0
    assert runs[False].frames_changed == 3 and runs[False].mean > 0.0
