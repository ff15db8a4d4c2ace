"""The spot cone (docs/MODEL.md "Spot cone"): its falloff, the RSM flux it gives (exact per
texel, its total against the closed form), and the direct light using the same falloff."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from derivations import rsm as rsm_derivation
from explorer.lpv.passes.gather import GatherInputs, GatherPass
from explorer.lpv.passes.gbuffer import GBufferPass
from explorer.lpv.passes.light_records import ShadowMaps
from explorer.lpv.passes.rsm import RsmPass, light_view, read_texture
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.scene import Camera, MeshBuilder, Scene, SpotLight, load_scene
from explorer.scene.gpu import SceneBuffers
from explorer.scene.lights import spot_falloff

SIZE = 64
ALBEDO = np.array([0.8, 0.5, 0.25])
CONE = (30.0, 60.0)
FLUX = 12.0


def rectangle_solid_angle(x, y):
    """Solid angle of [0, x]×[0, y] on the plane at distance 1 (signed), an independent
    closed form (not the shader's triangle formula)."""
    return np.arctan(x * y / np.sqrt(1.0 + x * x + y * y))


def texel_solid_angles(size: int, half_width: float) -> np.ndarray:
    """(rows from the bottom, columns) exact solid angles of the texels of a square
    frustum cutting the plane at depth 1 in [-t, t]²."""
    edges = np.linspace(-half_width, half_width, size + 1)
    x0, x1 = edges[None, :-1], edges[None, 1:]
    y0, y1 = edges[:-1, None], edges[1:, None]
    return (rectangle_solid_angle(x1, y1) - rectangle_solid_angle(x0, y1)
            - rectangle_solid_angle(x1, y0) + rectangle_solid_angle(x0, y0))


def texel_centre_cosines(size: int, half_width: float) -> np.ndarray:
    """cos of the angle between each texel's centre direction and the axis."""
    edges = np.linspace(-half_width, half_width, size + 1)
    centres = 0.5 * (edges[:-1] + edges[1:])
    x, y = np.meshgrid(centres, centres)
    return 1.0 / np.sqrt(1.0 + x * x + y * y)


def floor_scene(light) -> Scene:
    """A horizontal floor 1 m under the light, wide enough to catch the whole frustum."""
    mesh = MeshBuilder()
    mesh.rect((0.0, -1.0, 0.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0), 40.0, 40.0, ALBEDO)
    positions, normals, albedo = mesh.arrays()
    return Scene("floor", positions, normals, albedo, Camera((0.0, 0.5, 1.2), (0.0, -1.0, 0.0),
                                                             70.0),
                 light, (-3.0, -3.0, -3.0), (3.0, 3.0, 3.0))


def render_rsm(ctx, programs, scene, size=SIZE):
    geometry = SceneBuffers(ctx, scene)
    rsm = RsmPass(ctx, programs)
    try:
        view = light_view(scene, size)
        textures = rsm.run(geometry, view)
        flux = np.frombuffer(textures.flux.read(), np.float32).reshape(size, size, 4)
        return view, textures.texel_area, flux[..., :3].astype(np.float64)
    finally:
        rsm.release()
        geometry.release()


# --- the falloff -------------------------------------------------------------------------

def test_falloff_is_one_inside_zero_outside_and_smooth():
    ci, co = (math.cos(math.radians(a)) for a in CONE)
    angles = np.radians(np.linspace(0.0, 90.0, 9001))
    f = spot_falloff(np.cos(angles), ci, co)
    assert np.all(f[angles <= math.radians(CONE[0])] == 1.0)
    assert np.all(f[angles >= math.radians(CONE[1])] == 0.0)
    assert np.all(np.diff(f) <= 0.0)                     # falls monotonically off the axis
    # C¹ in cos θ: the slope of 3t² − 2t³ is 0 at both ends
    t = sp.Symbol("t")
    slope = sp.diff(3 * t**2 - 2 * t**3, t)
    assert slope.subs(t, 0) == 0 and slope.subs(t, 1) == 0
    # equal angles: a hard step at the outer angle
    hard = spot_falloff(np.cos(angles), co, co)
    assert set(np.unique(hard)) == {0.0, 1.0}
    assert np.all(hard[angles < math.radians(CONE[1]) - 1e-9] == 1.0)


def test_the_cone_weights_the_closed_form_solid_angle():
    # exact: sympy integrates the polynomial falloff over the sphere
    ci, co = rsm_derivation.cos_i, rsm_derivation.cos_o
    expected = 2 * sp.pi * (1 - (ci + co) / 2)
    assert sp.simplify(rsm_derivation.cone_solid_angle() - expected) == 0
    flux = rsm_derivation.cone_total_flux()
    assert sp.simplify(flux - rsm_derivation.c_diff * rsm_derivation.Phi_L
                       * (1 - (ci + co) / 2) / 2) == 0
    # and the numpy falloff (the shader's twin) integrates to it: 2π ∫ f d(cos θ)
    cos_inner, cos_outer = (math.cos(math.radians(a)) for a in CONE)
    edges = np.linspace(-1.0, 1.0, 200001)
    mid = 0.5 * (edges[1:] + edges[:-1])
    numeric = 2 * math.pi * np.sum(spot_falloff(mid, cos_inner, cos_outer)) * (edges[1] - edges[0])
    closed = float(expected.subs({ci: cos_inner, co: cos_outer}))
    assert numeric == pytest.approx(closed, rel=1e-8)


def test_light_cone_validation_and_frustum():
    light = SpotLight((0, 1, 0), (0, 0, 0), 1.0, cone_degrees=(20, 50))
    assert light.fov_degrees == 100.0
    assert light.frustum_half_width == pytest.approx(math.tan(math.radians(50)))
    assert light.texel_area(8, 8) == pytest.approx(4 * math.tan(math.radians(50)) ** 2 / 64)
    frustum = light.with_cone(None)
    assert frustum.fov_degrees == 90.0 and frustum.frustum_half_width == 1.0
    assert frustum.texel_area(8, 8) == 4.0 / 64
    assert np.all(frustum.falloff(np.linspace(-1, 1, 5)) == 1.0)
    for bad in ((50, 20), (-1, 30), (10, 85), (0, 0), ("a", 3), (10,)):
        with pytest.raises(ValueError, match="cone_degrees"):
            SpotLight((0, 1, 0), (0, 0, 0), 1.0, cone_degrees=bad)
    with pytest.raises(ValueError, match="spot_cone_degrees"):
        Settings(spot_cone_degrees=(40.0, 20.0))
    with pytest.raises(ValueError, match="spot_cone must be true or false, got 1"):
        Settings(spot_cone=1)


def test_settings_switch_the_scene_light_between_cone_and_frustum():
    scene = load_scene("cornell")
    assert scene.light.cone_degrees == (40.0, 70.0)
    assert scene.for_settings(Settings(spot_cone=False)).light.cone_degrees is None
    assert scene.for_settings(Settings(spot_cone_degrees=(10.0, 30.0))).light.cone_degrees \
        == (10.0, 30.0)
    room = load_scene("room")       # a directional light has no cone: nothing changes
    assert room.for_settings(Settings(spot_cone=False)).light == room.light


# --- the RSM -------------------------------------------------------------------------------

def test_rsm_texel_flux_carries_the_falloff_exactly(ctx, programs):
    light = SpotLight((0.0, 0.0, 0.0), (0.0, -1.0, 0.0), FLUX, cone_degrees=CONE)
    view, texel_area, flux = render_rsm(ctx, programs, floor_scene(light))
    t = math.tan(math.radians(CONE[1]))
    assert view.frustum_half_width == pytest.approx(t)
    assert texel_area == pytest.approx(4 * t * t / SIZE**2)
    rho = texel_solid_angles(SIZE, t)
    f = spot_falloff(texel_centre_cosines(SIZE, t), *light.cone_cosines)
    # MODEL.md "Spot cone": Φ_o = c_diff · ρ · f(θ_c) · Φ_L/(4π) per texel
    expected = ALBEDO * (rho * f * FLUX / (4 * math.pi))[..., None]
    assert np.allclose(flux, expected, rtol=2e-4, atol=1e-7 * expected.max())
    # the whole cone lands on the floor: Σ is the midpoint rule of ∫f dω, within 1e-3 of
    # the closed form c·Φ_L·(1 − (cos θ_i + cos θ_o)/2)/2 at 64² (the rule's error falls as
    # 1/W²; it is 1.9e-4 here)
    ci, co = light.cone_cosines
    closed = ALBEDO * FLUX * (1.0 - (ci + co) / 2.0) / 2.0
    assert np.allclose(flux.sum(axis=(0, 1)), closed, rtol=1e-3)
    assert np.allclose(expected.sum(axis=(0, 1)), closed, rtol=1e-3)


def test_single_source_rsm_is_the_same_with_the_cone_on_or_off(ctx):
    small = Settings(scene="single-source", grid_size=8, iterations=1, rsm_size=32,
                     width=16, height=16)
    with Pipeline(small, ctx=ctx) as pipeline:
        cone = pipeline.run().rsm_flux.copy()
        frustum = pipeline.run(small.with_changes(spot_cone=False)).rsm_flux
    assert cone.sum() > 0 and np.array_equal(cone, frustum)


def test_frustum_mode_keeps_the_published_total(ctx, programs):
    # spot_cone off: the 90° frustum at uniform intensity; a floor filling it reflects
    # c·Φ_L/6 (MODEL.md "Reflective shadow map"), the number the RSM lessons measure
    light = SpotLight((0.0, 0.0, 0.0), (0.0, -1.0, 0.0), FLUX, cone_degrees=CONE)
    scene = floor_scene(light).for_settings(Settings(spot_cone=False))
    view, texel_area, flux = render_rsm(ctx, programs, scene)
    assert not view.spot_cone and texel_area == 4.0 / SIZE**2
    assert np.allclose(flux.sum(axis=(0, 1)), ALBEDO * FLUX / 6.0, rtol=1e-4)


# --- the direct light shares the falloff ----------------------------------------------------

def test_direct_light_and_rsm_share_the_falloff(ctx, programs):
    light = SpotLight((0.0, 0.0, 0.0), (0.3, -1.0, 0.1), FLUX, cone_degrees=CONE)
    scene = floor_scene(light)
    geometry = SceneBuffers(ctx, scene)
    rsm, gbuffer, gather = RsmPass(ctx, programs), GBufferPass(ctx, programs), GatherPass(
        ctx, programs)
    size = (80, 64)
    try:
        view = light_view(scene, SIZE)
        shadow = rsm.run(geometry, view)
        rsm_flux = np.frombuffer(shadow.flux.read(), np.float32).reshape(SIZE, SIZE, 4)
        gbuffer.run(geometry, scene, size)
        gather.run(gbuffer, ShadowMaps(shadow, view), None, GatherInputs(shadow_kernel=1))
        direct = read_texture(gather.targets["direct"])[..., :3].astype(np.float64)
        position = read_texture(gbuffer.position)
    finally:
        for thing in (gather, gbuffer, rsm, geometry):
            thing.release()
    ci, co = light.cone_cosines
    # the RSM's falloff at its texel centres
    t = view.frustum_half_width
    rho = texel_solid_angles(SIZE, t)
    f_rsm = rsm_flux[..., 0] / (ALBEDO[0] * FLUX / (4 * math.pi) * rho)
    cos_rsm = texel_centre_cosines(SIZE, t)
    # the direct light's falloff at its pixels: direct / (a/π · I · cos θ_i / r²)
    valid = position[..., 3] > 0.5
    offset = position[..., :3] - np.asarray(light.position)
    r2 = np.sum(offset**2, axis=-1)
    cos_incidence = -offset[..., 1] / np.sqrt(r2)            # floor normal +y
    unshadowed = ALBEDO[0] / math.pi * FLUX / (4 * math.pi) * cos_incidence / r2
    cos_direct = (offset / np.sqrt(r2)[..., None]) @ light.direction
    pick = valid & (cos_incidence > 0.2)
    f_direct = direct[..., 0][pick] / unshadowed[pick]
    # both are the one function of the angle from the axis (shaders/spot.glsl; numpy twin)
    assert np.allclose(f_rsm, spot_falloff(cos_rsm, ci, co), atol=2e-4)
    assert np.allclose(f_direct, spot_falloff(cos_direct[pick], ci, co), atol=2e-4)
    # and the image spans the whole ramp: lit core, fall-off band, dark outside
    assert f_direct.max() > 0.999 and f_direct.min() < 1e-4
    assert np.count_nonzero((f_direct > 0.05) & (f_direct < 0.95)) > 200
