"""Camera occluders (docs/MODEL.md "Camera occluders"): the G-buffer's pixels that no RSM
view sees join the geometry volume, against the numpy twin (one light and several),
each surface once, and only rebuilt when the camera is used."""

from __future__ import annotations

import numpy as np
import pytest
from lpv_cases import frame_view_lights, relative_error

from explorer.lpv.passes.geometry import merged_volume_reference
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.twin import light_grid as twin
from explorer.lpv.twin import media

ROOM = Settings(scene="room", grid_size=16, iterations=6, width=96, height=64, rsm_size=64,
                geometry_volume="one-sided", camera_occluders=True,
                camera=((1.6, 2.5, 3.0), (0.0, 0.4, -1.0)))
"""The room seen from the right: the thin inner wall's +x face, which the sun does not
reach, fills part of the view."""
PATCH = Settings(scene="single-source", grid_size=8, iterations=2, width=64, height=48,
                 rsm_size=32, geometry_volume="one-sided", camera_occluders=True,
                 camera=((0.0, 0.1, 0.7), (0.0, -0.5, 0.0)))
"""One patch that both the spot light and the camera (close to it) see."""


@pytest.fixture(scope="module")
def pipeline(gl_context):
    pipe = Pipeline(ROOM, ctx=gl_context)
    yield pipe
    pipe.release()


def reference_surfels(pipeline, result):
    """``(each RSM view's surfels, the camera surfels the reference picks from the frame's
    own G-buffer and every view's shadow map)``."""
    albedo = np.dstack([result.albedo, np.ones(result.albedo.shape[:2])])
    camera = media.camera_surfels(result.gbuffer_position, result.gbuffer_normal, albedo,
                                  result.camera, frame_view_lights(pipeline))
    return [rsm.to_arrays() for rsm in pipeline.light_views.rsm_sets], camera


def reference_volume(pipeline, result, mode: str = "one-sided", spec=None):
    """The reference geometry volume of the grid ``spec`` (default: level 0's): the RSM
    views' volumes merged per cell plus the camera's surfels, and the camera's surfels."""
    views, camera = reference_surfels(pipeline, result)
    spec = result.grid_spec if spec is None else spec
    corrections = result.settings.corrections
    volume = (merged_volume_reference([twin.inject_geometry(vpls, spec, corrections, mode)
                                       for vpls in views])
              + twin.inject_geometry(camera, spec, corrections, mode))
    return volume, camera


@pytest.mark.parametrize("changes", [{}, {"geometry_volume": "double-sided"},
                                     {"corrections": {"surfel_area_squared": False}},
                                     {"lights": ("sun", "lamp")}])     # + a point light
def test_camera_surfels_match_the_reference(pipeline, changes):
    settings = ROOM.with_changes(**changes)
    result = pipeline.run(settings)
    expected, camera = reference_volume(pipeline, result, settings.geometry_volume)
    seen = int((result.gbuffer_position[..., 3] > 0.5).sum())
    assert 0 < camera.count < seen            # the sun sees part of what the camera sees
    assert relative_error(result.geometry_volume, expected) < 1e-5


def test_camera_surfels_reach_every_cascade(pipeline):
    result = pipeline.run(ROOM.with_changes(cascades=2, grid_size=8))
    for level in result.cascades:
        expected, _ = reference_volume(pipeline, result, spec=level.spec)
        assert relative_error(level.geometry_volume, expected) < 1e-5


def test_a_surface_both_see_blocks_exactly_once(gl_context):
    """Every camera pixel of the patch is a surface the RSM holds already: the volume with
    camera occluders is exactly the volume without them."""
    with Pipeline(PATCH, ctx=gl_context) as pipe:
        with_camera = pipe.run(PATCH).geometry_volume.copy()
        result = pipe.last_result
        assert (result.gbuffer_position[..., 3] > 0.5).sum() > 100
        _, camera = reference_volume(pipe, result)
        assert camera.count == 0
        without = pipe.run(PATCH.with_changes(camera_occluders=False)).geometry_volume
        assert np.array_equal(with_camera, without)


def test_a_surface_the_camera_and_one_of_two_lights_see_blocks_exactly_once(gl_context):
    """single-source's spot turned away from the patch and its bulb, whose −y face sees
    it: the camera's pixels of the patch are tested against every view's map, so the
    bulb's view holds them and none is added. The volume with camera occluders is exactly
    the one without, which is the bulb's alone (the spot's views hold nothing); tested
    against the spot's map only, every pixel would have been added a second time."""
    turned = PATCH.with_changes(light=((0.0, -0.2, 0.0), (0.0, 1.0, 0.0)),
                                lights=("spot", "bulb"))
    with Pipeline(turned, ctx=gl_context) as pipe:
        with_camera = pipe.run(turned).geometry_volume.copy()
        result = pipe.last_result
        seen = int((result.gbuffer_position[..., 3] > 0.5).sum())
        assert seen > 100
        views = frame_view_lights(pipe)
        assert [light.kind for light, _ in views] == ["spot"] + ["point"] * 6
        albedo = np.dstack([result.albedo, np.ones(result.albedo.shape[:2])])
        spot_only = media.camera_surfels(result.gbuffer_position, result.gbuffer_normal,
                                         albedo, result.camera, views[:1])
        assert spot_only.count == seen
        _, camera = reference_volume(pipe, result)
        assert camera.count == 0
        without = pipe.run(turned.with_changes(camera_occluders=False)).geometry_volume
        assert np.array_equal(with_camera, without)
        bulb = pipe.run(turned.with_changes(lights=("bulb",))).geometry_volume
        assert np.array_equal(with_camera, bulb) and bulb[..., 0].max() > 0


def test_a_surface_only_the_camera_sees_blocks_with_its_pixel_area(gl_context):
    """With the spot turned away from the patch the camera's pixels are the only surfels:
    the volume holds exactly Σ A/h²·lobe(n) with A = pixel_area·w² per pixel."""
    turned = PATCH.with_changes(light=((0.0, -0.2, 0.0), (0.0, 1.0, 0.0)))
    with Pipeline(turned, ctx=gl_context) as pipe:
        result = pipe.run(turned)
        _, camera = reference_volume(pipe, result)
        seen = int((result.gbuffer_position[..., 3] > 0.5).sum())
        assert camera.count == seen > 100
        without = pipe.run(turned.with_changes(camera_occluders=False)).geometry_volume
        added = result.geometry_volume - without
        expected = twin.inject_geometry(camera, result.grid_spec)
        assert relative_error(added, expected) < 1e-5
        # band 0 of a one-sided surfel is √π/2·A/h²: the summed band 0 is the summed area
        eye = np.asarray(result.camera.eye)
        fov = np.radians(result.camera.fov_y_degrees)
        view = result.camera.view_matrix()
        points = result.gbuffer_position[result.gbuffer_position[..., 3] > 0.5, :3]
        depth = -(points @ view[:3, :3].T + view[:3, 3])[:, 2]
        area = (2 * np.tan(fov / 2) / turned.height) ** 2 * np.sum(depth**2.0)
        assert np.all(np.linalg.norm(points - eye, axis=1) >= depth)
        band0 = float(added[..., 0].sum()) * result.grid_spec.cell_size**2
        assert band0 == pytest.approx(np.sqrt(np.pi) / 2 * area, rel=1e-5)


def test_the_volume_reads_the_camera_only_when_it_uses_it(pipeline):
    moved = ((1.5, 2.6, 3.1), (0.0, 0.4, -1.0))
    pipeline.run(ROOM)
    assert pipeline.run(ROOM.with_changes(camera=moved)).stages_run == (
        "geometry", "propagate", "gbuffer", "gather", "display")
    plain = ROOM.with_changes(camera_occluders=False)
    pipeline.run(plain.with_changes(camera=moved))
    assert pipeline.run(plain).stages_run == (
        "gbuffer", "gather", "display")
    # without a geometry volume the switch has nothing to add to
    off = ROOM.with_changes(geometry_volume="off")
    pipeline.run(off)
    assert pipeline.run(off.with_changes(camera=moved)).stages_run == (
        "gbuffer", "gather", "display")


def test_camera_occluders_stop_the_leak_into_the_closed_room(gl_context):
    """In two-rooms everything the camera sees lies in the room the light cannot reach:
    all the LPV light on screen leaked through the shared wall, which the light does not
    see. The camera's surfels of that wall take most of it away with a double-sided
    volume (docs/MODEL.md "Camera occluders"); with a one-sided volume less."""
    base = Settings(scene="two-rooms", grid_size=16, iterations=8, width=96, height=72,
                    rsm_size=64)
    with Pipeline(base, ctx=gl_context) as pipe:
        gathered = {}
        for mode in ("one-sided", "double-sided"):
            for on in (False, True):
                result = pipe.run(base.with_changes(geometry_volume=mode,
                                                    camera_occluders=on))
                assert result.direct.max() == 0.0         # no direct light reaches it
                gathered[mode, on] = float(np.sum(result.audit.gathered))
    assert gathered["double-sided", True] < 0.7 * gathered["double-sided", False]
    assert gathered["one-sided", True] < gathered["one-sided", False]
    assert gathered["double-sided", True] < gathered["one-sided", True]
