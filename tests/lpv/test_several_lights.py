"""Several lights in one volume (docs/MODEL.md "Several lights"): the point light's cube of
RSM faces, the sum of every light's direct light, the linearity of the LPV in its lights,
the geometry volume's merge of several views, the audit and the reference summing over
lights."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from derivations.registry import get
from explorer.gl.program import ProgramCache
from explorer.lpv.passes.atlas import AtlasLayout, PerView, VplAtlas
from explorer.lpv.passes.gather import GatherInputs, GatherPass
from explorer.lpv.passes.gbuffer import GBufferPass
from explorer.lpv.passes.geometry import merged_volume_reference
from explorer.lpv.passes.light_records import ShadowMaps
from explorer.lpv.passes.rsm import RsmPass, light_views, read_texture
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.vpl import VplArrays
from explorer.scene import Camera, MeshBuilder, PointLight, Scene, SceneError, load_scene
from explorer.scene.gpu import SceneBuffers
from explorer.scene.lights import CUBE_FACE_AXES
from explorer.truth.gbuffer import gbuffer_from_frame
from explorer.truth.reference import numpy_reference_irradiance
from explorer.truth.render import reference_for_frame

ALBEDO = 0.5
COLOUR = (1.0, 0.6, 0.3)
FLUX = 7.0
BULB = (0.3, 0.2, -0.1)
"""Off the box's centre, so the six faces see the walls unevenly."""
CORNELL = Settings(scene="cornell", grid_size=16, iterations=6, rsm_size=32, width=48,
                   height=48)
LINEAR = {"clamp_front_face": False}
"""The front-face clamp is the propagation's one nonlinear step (docs/MODEL.md "Several
lights"); without it the LPV is linear in its lights."""


def closed_box() -> Scene:
    """A closed 2 m box of reflectance 0.5, walls facing in, a coloured point light inside
    and a camera in a corner looking at the far corner (so it sees three walls and the
    seams of several cube faces)."""
    mesh = MeshBuilder()
    x, y, z = np.eye(3)
    grey = (ALBEDO,) * 3
    for axis, u in ((x, z), (y, x), (z, x)):
        mesh.rect(-axis, axis, u, 1, 1, grey)
        mesh.rect(axis, -axis, u, 1, 1, grey)
    positions, normals, albedo = mesh.arrays()
    bulb = PointLight(BULB, FLUX, name="bulb", colour=COLOUR)
    return Scene("closed box", positions, normals, albedo,
                 Camera((0.8, 0.8, 0.8), (-0.6, -0.7, -0.5), 80.0), bulb,
                 (-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))


@pytest.fixture(scope="module")
def box_rsms(gl_context):
    """The box, its six RSM views and their textures (one RSM pass per view)."""
    programs = ProgramCache(gl_context)
    scene = closed_box()
    geometry = SceneBuffers(gl_context, scene)
    views = light_views(scene, 64)
    passes = PerView(lambda: RsmPass(gl_context, programs))
    sets = [passes.run(k, geometry, view) for k, view in enumerate(views)]
    yield gl_context, programs, scene, geometry, views, sets
    for thing in (passes, geometry, programs):
        thing.release()


def test_a_point_light_has_six_cube_faces_that_tile_the_sphere(box_rsms):
    ctx, programs, scene, geometry, views, sets = box_rsms
    assert [v.kind for v in views] == ["point"] * 6 and [v.face for v in views] == list(
        range(6))
    axes = np.array([v.direction for v in views])
    assert np.allclose(axes, CUBE_FACE_AXES)
    # each face is the 90° frustum of a cone-less spot of the same intensity
    assert all(v.frustum_half_width == 1.0 and not v.spot_cone for v in views)
    assert all(v.intensity == pytest.approx(FLUX / (4 * math.pi)) for v in views)


def test_the_rsm_of_a_point_light_in_a_closed_room_reflects_c_times_its_flux(box_rsms):
    """The six faces' texel solid angles cover the sphere once (each face 4π/6), every
    direction hits a wall of reflectance c, so the RSM's total flux is c·Φ_L per channel
    times the light's colour: exact up to the float32 evaluation of the texel solid angles
    (measured 2·10⁻⁵ low at 64² per face; the spot's RSM tests allow the same 1e-4)."""
    ctx, programs, scene, geometry, views, sets = box_rsms
    room = get("rsm.point_light_room_flux").expr          # exact: c_diff·Φ_L
    c_diff, phi = sp.symbols("c_diff Phi_L", positive=True)
    assert sp.simplify(room - c_diff * phi) == 0
    total = sum(np.add.reduce(read_texture(s.flux)[..., :3].reshape(-1, 3), axis=0,
                              dtype=np.float64) for s in sets)
    expected = float(room.subs({c_diff: ALBEDO, phi: FLUX})) * np.asarray(COLOUR)
    assert np.allclose(total, expected, rtol=1e-4), (total, expected)
    # every texel of every face sees a wall
    assert all(np.all(read_texture(s.position)[..., 3] > 0.5) for s in sets)


def test_the_direct_light_of_a_point_light_counts_each_point_once(box_rsms):
    """The gather sums every face's direct light but a point takes it from the one face
    whose directions hold it (cube-map face selection): I·cos θ/r²·colour·a/π at every
    wall pixel, across the seams between faces, with no gap and nothing twice. (One hard
    shadow test: a PCF box at the box's concave corners reaches texels of the other wall,
    which dims a few pixels there for any light.)"""
    ctx, programs, scene, geometry, views, sets = box_rsms
    atlas, gbuffer, gather = VplAtlas(ctx, programs), GBufferPass(ctx, programs), \
        GatherPass(ctx, programs)
    try:
        shadow = atlas.build(sets)
        tiles = [atlas.layout.origin(k) for k in range(len(sets))]
        gbuffer.run(geometry, scene, (64, 64))
        gather.run(gbuffer, ShadowMaps(shadow, views, tiles), None,
                   GatherInputs(shadow_kernel=1))
        position = read_texture(gbuffer.position)
        normal = read_texture(gbuffer.normal)[..., :3]
        direct = read_texture(gather.targets["direct"])[..., :3]
    finally:
        for thing in (atlas, gbuffer, gather):
            thing.release()
    valid = position[..., 3] > 0.5
    offset = np.asarray(BULB) - position[..., :3]
    r2 = np.sum(offset ** 2, axis=-1)
    cos = np.sum(normal * offset, axis=-1) / np.sqrt(r2)
    expected = (ALBEDO / math.pi * FLUX / (4 * math.pi) * (cos / r2))[..., None] * \
        np.asarray(COLOUR)
    pick = valid & (cos > 0.15)
    assert pick.mean() > 0.8
    # the picture crosses face seams: pixels of at least three faces
    faces = {int(np.argmax(np.abs(-o))) * 2 + int(o[np.argmax(np.abs(o))] > 0)
             for o in offset[pick]}
    assert len(faces) >= 3
    assert np.allclose(direct[pick], expected[pick], rtol=1e-3)


def test_atlas_layout_stacks_tiles_in_columns_below_the_largest_size():
    layout = AtlasLayout.fit(9, (64, 64), largest=300)
    assert layout.rows == 4 and layout.columns == 3 and layout.size == (192, 256)
    assert [layout.origin(k) for k in (0, 3, 4, 8)] == [(0, 0), (0, 192), (64, 0), (128, 0)]
    assert AtlasLayout.fit(6, (32, 32)).size == (32, 192)
    with pytest.raises(ValueError, match="do not fit one atlas"):
        AtlasLayout.fit(40, (64, 64), largest=300)


@pytest.fixture(scope="module")
def cornell(gl_context):
    pipe = Pipeline(CORNELL, ctx=gl_context)
    yield pipe
    pipe.release()


def run_lights(pipeline, settings, *names):
    result = pipeline.run(settings.with_changes(lights=names))
    return result


def test_the_lpv_of_two_lights_is_the_sum_of_their_lpvs(cornell):
    """Linearity: without the front-face clamp (and without a geometry volume) the
    injection, the propagation and the direct light are linear in the lights, so the
    frame of the spot and the bulb (a point light: six RSM views in the atlas) equals the
    sum of the two single-light frames to float32 summation order."""
    settings = CORNELL.with_changes(corrections=LINEAR)
    spot = run_lights(cornell, settings, "spot")
    bulb = run_lights(cornell, settings, "bulb")
    both = run_lights(cornell, settings, "spot", "bulb")
    assert both.light_names == ("spot", "bulb") and both.view_lights == (0,) + (1,) * 6
    for level in range(len(both.cascades)):
        total = both.cascades[level].accumulated.astype(np.float64)
        parts = spot.cascades[level].accumulated.astype(np.float64) + \
            bulb.cascades[level].accumulated
        assert np.abs(total - parts).max() <= 1e-5 * np.abs(total).max()
    assert np.allclose(both.direct, spot.direct + bulb.direct, rtol=1e-5, atol=1e-7)
    # the audit sums over the lights
    assert np.allclose(both.audit.rsm, spot.audit.rsm + bulb.audit.rsm, rtol=1e-9)
    assert np.allclose(both.audit.rsm_per_light, [spot.audit.rsm, bulb.audit.rsm])
    assert np.allclose(both.audit.injected, spot.audit.injected + bulb.audit.injected,
                       rtol=1e-5)
    assert np.allclose(both.audit.accumulated,
                       spot.audit.accumulated + bulb.audit.accumulated, rtol=1e-5)
    assert both.vpls.count == spot.vpls.count + bulb.vpls.count
    # the bulb's light really is in the grid: it adds a sizeable share
    assert (bulb.audit.injected / both.audit.injected).min() > 0.05


def test_the_front_face_clamp_is_what_breaks_linearity(cornell):
    """With the clamp (the corrected preset) clamp+(a + b) ≤ clamp+(a) + clamp+(b): the
    two-light grid differs from the sum, by a little."""
    spot = run_lights(cornell, CORNELL, "spot").accumulated.astype(np.float64)
    bulb = run_lights(cornell, CORNELL, "bulb").accumulated.astype(np.float64)
    both = run_lights(cornell, CORNELL, "spot", "bulb").accumulated.astype(np.float64)
    error = np.abs(both - (spot + bulb)).max() / np.abs(both).max()
    assert 1e-5 < error < 0.05


def test_a_surface_seen_by_two_lights_blocks_once(gl_context):
    """single-source's spot and bulb sit at the same point, and the spot's 90° frustum is
    the bulb's −y face: both RSMs see the same surfels. The merged geometry volume keeps
    one view per cell, so it equals each light's own volume (a sum would block twice),
    and with that volume the LPV is still linear in the two lights."""
    settings = Settings(scene="single-source", grid_size=8, iterations=4, rsm_size=32,
                        width=32, height=32, geometry_volume="one-sided").with_changes(
                            corrections=LINEAR)
    with Pipeline(settings, ctx=gl_context) as pipe:
        spot = run_lights(pipe, settings, "spot")
        bulb = run_lights(pipe, settings, "bulb")
        both = run_lights(pipe, settings, "spot", "bulb")
    assert np.abs(spot.geometry_volume).max() > 0
    assert np.array_equal(both.geometry_volume, spot.geometry_volume)
    assert np.array_equal(bulb.geometry_volume, spot.geometry_volume)
    total = both.accumulated.astype(np.float64)
    assert np.abs(total - spot.accumulated - bulb.accumulated).max() <= \
        1e-5 * np.abs(total).max()


def test_the_geometry_volume_of_two_lights_keeps_per_cell_the_view_with_more_area(cornell):
    """Cornell's spot and lamp see partly different surfaces: the two-light volume is,
    cell by cell, the single-light volume whose surfels cover more area there (the
    numpy twin of shaders/geometry_merge.glsl), not their sum."""
    settings = CORNELL.with_changes(geometry_volume="one-sided")
    spot = run_lights(cornell, settings, "spot").geometry_volume
    lamp = run_lights(cornell, settings, "lamp").geometry_volume
    both = run_lights(cornell, settings, "spot", "lamp").geometry_volume
    assert np.array_equal(both, merged_volume_reference([spot, lamp]).astype(np.float32))
    differ = (spot[..., 0] > 0) & (lamp[..., 0] > 0) & (spot[..., 0] != lamp[..., 0])
    assert differ.sum() > 10
    assert np.all(both[..., 0] <= np.maximum(spot[..., 0], lamp[..., 0]))


def test_the_reference_sums_over_lights(cornell, gl_context):
    """The one-bounce reference of a two-light frame gathers every light's VPLs: the GPU
    reference equals the float64 numpy sum of the per-light references."""
    settings = CORNELL.with_changes(rsm_size=8, width=16, height=16, lights=("spot", "bulb"))
    frame = cornell.run(settings)
    assert len(frame.vpl_sets) == 7
    radiance, gbuffer = reference_for_frame(frame, visibility=False, ctx=gl_context)
    min_distance = 0.5 * frame.grid_spec.cell_size
    by_light = []
    for light in range(2):
        sets = [s for s, owner in zip(frame.vpl_sets, frame.view_lights) if owner == light]
        vpls = VplArrays.concatenate(sets)
        by_light.append(numpy_reference_irradiance(gbuffer, vpls, min_distance))
    expected = np.where(gbuffer.valid[..., None], gbuffer.albedo / np.pi * sum(by_light), 0)
    assert np.abs(expected).max() > 0 and np.abs(by_light[1]).max() > 0
    assert np.allclose(radiance, expected, rtol=1e-4, atol=1e-4 * np.abs(expected).max())
    assert gbuffer_from_frame(frame).valid.sum() == gbuffer.valid.sum()


def test_lights_names_are_checked_against_the_scene(cornell):
    scene = load_scene("cornell")
    assert scene.light_names == ("spot", "lamp", "bulb", "sun")
    assert [light.kind for light in scene.rig] == ["spot", "spot", "point", "directional"]
    assert scene.lights == (scene.rig[0],)
    assert scene.with_lights(("bulb", "spot")).light.name == "bulb"
    with pytest.raises(SceneError, match=r"lights must name 1 to 8 different lights of "
                                         r"scene 'cornell' \(spot, lamp, bulb, sun\)"):
        scene.with_lights(("spot", "moon"))
    for bad in ((), ("spot", "spot"), ("a",) * 9, ("spot", " ")):
        with pytest.raises(ValueError, match="lights must be a list of 1 to 8 different "
                                             "names or None"):
            Settings(lights=bad)
    assert Settings(lights=["bulb", "spot"]).lights == ("bulb", "spot")
    with pytest.raises(SceneError, match="moon"):
        cornell.run(CORNELL.with_changes(lights=("moon",)))


def test_settings_light_moves_the_primary_light_whatever_its_kind():
    scene = load_scene("cornell")
    moved = scene.with_overrides(light=((0.1, 0.2, 0.3), (0.0, -1.0, 0.0)),
                                 light_flux=5.0, lights=("bulb", "spot"))
    assert moved.light.kind == "point" and moved.light.position == (0.1, 0.2, 0.3)
    assert moved.light.flux == 5.0
    assert moved.lights[1] == scene.rig[0]              # the spot is untouched
    # spot_cone off drops every spot's cone; the degrees go to the primary spot only
    coneless = scene.with_overrides(spot_cone=False, lights=("spot", "lamp"))
    assert all(light.cone_degrees is None for light in coneless.lights)
    narrow = scene.with_overrides(spot_cone_degrees=(10.0, 20.0), lights=("spot", "lamp"))
    assert narrow.lights[0].cone_degrees == (10.0, 20.0)
    assert narrow.lights[1].cone_degrees == scene.rig[1].cone_degrees


def test_a_light_colour_scales_its_flux_per_channel():
    bulb = load_scene("cornell").rig[2]
    assert np.allclose(bulb.channel_flux, bulb.flux * np.asarray(bulb.colour))
    with pytest.raises(ValueError, match="colour must be three finite numbers"):
        PointLight((0, 0, 0), 1.0, name="x", colour=(1.0, -1.0, 0.0))


def test_lessons_quote_the_lights_from_the_frame(cornell):
    """The live numbers the lessons quote about several lights are read from the frame."""
    from explorer.lessons import live_values as lv

    frame = run_lights(cornell, CORNELL, "spot", "bulb")
    context = lv.LiveContext(result=frame)

    def value(name):
        return lv.lookup(name).value(context)

    assert value("frame.lights") == 2 and value("frame.rsm_views") == 7
    assert value("audit.rsm_primary") == pytest.approx(float(frame.audit.rsm_per_light[0].sum()))
    assert 0.0 < value("audit.rsm_primary_share") < 1.0
    assert value("frame.gbuffer_ran") in ("yes", "no")
    moved = cornell.run(CORNELL.with_changes(object_transforms={"tall block": (0, 0, 0.05)}))
    context = lv.LiveContext(result=moved)
    assert value("frame.moved_objects") == 1 and value("frame.gbuffer_ran") == "yes"
    assert value("frame.stages_ran") == len(moved.stages_run)
