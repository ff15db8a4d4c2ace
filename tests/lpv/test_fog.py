"""Fog (docs/MODEL.md "Fog"): the GPU's march against the numpy twin, and the
invariants of a homogeneous medium: density 0 changes nothing, the transmittance is
exp(−σ_t·ℓ), the phase functions integrate to 1 and a uniform radiance field scatters
α·L·(1 − T) whatever the phase function."""

from __future__ import annotations

import numpy as np
import pytest
from lpv_cases import frame_view_lights

from explorer.lpv.cascades import SampledGrid
from explorer.lpv.passes.fog import camera_rays
from explorer.lpv.passes.rsm import read_texture
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.stages.fog import Params as FogParams
from explorer.lpv.twin import media

FOG = Settings(scene="cornell", grid_size=8, iterations=4, width=48, height=32, rsm_size=32,
               fog=True, fog_density=0.7, fog_steps=8)
TRANSMITTANCE_TOLERANCE = 1e-4
"""Largest |T_GPU − T_reference| (float32 distances and exponentials over paths of a few
metres)."""
INSCATTER_TOLERANCE = 2e-4
"""Largest in-scattering difference relative to the image's largest value."""


@pytest.fixture(scope="module")
def pipeline(gl_context):
    pipe = Pipeline(FOG, ctx=gl_context)
    yield pipe
    pipe.release()


def reference_fog(pipeline, result):
    """The reference march of every pixel of ``result`` (transmittance, direct, LPV)."""
    s = result.settings
    scene = pipeline.scene_state.scene
    eye, inverse = camera_rays(scene, (s.width, s.height))
    directions, distances = media.pixel_rays(eye, inverse, result.gbuffer_position)
    medium = FogParams.of(s).medium
    transmittance, direct, lpv = media.march_fog(
        eye, directions.reshape(-1, 3), distances.reshape(-1),
        (scene.bounds_min, scene.bounds_max), result.cascade_accumulated,
        result.cascade_specs, medium.density, medium.albedo, medium.g, medium.steps,
        frame_view_lights(pipeline))
    shape = (s.height, s.width)
    return (transmittance.reshape(shape), direct.reshape(shape + (3,)),
            lpv.reshape(shape + (3,)))


@pytest.mark.parametrize("changes", [
    {},                                                          # spot, HG g = 0.4
    {"scene": "room"},                                           # directional light
    {"cascades": 2, "fog_phase": "isotropic"},
    {"sh_order": 2, "fog_g": -0.5},
    {"lights": ("spot", "bulb")},                                # + a point light: 7 views
    {"scene": "room", "lights": ("sun", "lamp")},                # directional + point
])
def test_the_march_matches_the_reference(pipeline, changes):
    result = pipeline.run(FOG.with_changes(**changes))
    transmittance, direct, lpv = reference_fog(pipeline, result)
    fog = result.fog
    assert np.abs(fog.transmittance - transmittance).max() < TRANSMITTANCE_TOLERANCE
    assert direct.max() > 0 and lpv.max() > 0
    assert np.abs(fog.direct - direct).max() < INSCATTER_TOLERANCE * direct.max()
    assert np.abs(fog.lpv - lpv).max() < INSCATTER_TOLERANCE * lpv.max()


def test_the_in_scattering_is_linear_in_the_lights(pipeline):
    """fog(A + B) = fog(A) + fog(B) for the in-scattered light, the transmittance
    unchanged: the direct term sums every RSM view's (each with its own shadow map), and
    without the front-face clamp and a geometry volume the grid is linear in its lights
    (docs/MODEL.md "Several lights"), so the LPV's in-scattering is too wherever the lobe's
    clamp+ does not act (it can only lower the sum: clamp+(a + b) ≤ clamp+(a) +
    clamp+(b)). With the isotropic phase function (band 0 alone, which dips below 0 only
    in a few cells, by under 3 % of its largest value) the sum holds to float32 order."""
    linear = FOG.with_changes(corrections={"clamp_front_face": False}, fog_phase="isotropic")
    frames = {names: pipeline.run(linear.with_changes(lights=names)).fog
              for names in (("spot",), ("bulb",), ("spot", "bulb"))}
    spot, bulb, both = frames[("spot",)], frames[("bulb",)], frames[("spot", "bulb")]
    assert np.array_equal(both.transmittance, spot.transmittance)
    assert np.array_equal(both.transmittance, bulb.transmittance)
    for part in ("direct", "lpv"):
        total = getattr(both, part).astype(np.float64)
        parts = getattr(spot, part).astype(np.float64) + getattr(bulb, part)
        assert np.abs(total - parts).max() <= 1e-5 * np.abs(total).max(), part
        assert np.all(total <= parts + 1e-6 * np.abs(total).max()), part
        # the bulb's light is a sizeable part of it
        assert getattr(bulb, part).sum() > 0.05 * total.sum(), part


def test_transmittance_is_exp_of_the_path_in_the_box(pipeline):
    """T = exp(−σ_t·ℓ), ℓ the part of the view ray inside the scene's box before the
    surface: the Cornell camera stands outside the box, so ℓ < distance to the surface."""
    result = pipeline.run(FOG)
    s = result.settings
    scene = pipeline.scene_state.scene
    eye, inverse = camera_rays(scene, (s.width, s.height))
    directions, distances = media.pixel_rays(eye, inverse, result.gbuffer_position)
    flat = directions.reshape(-1, 3)
    t0, t1 = media.ray_box(np.broadcast_to(eye, flat.shape), flat, scene.bounds_min,
                           scene.bounds_max)
    path = np.maximum(np.minimum(t1, distances.reshape(-1)) - np.maximum(t0, 0), 0)
    expected = np.exp(-s.fog_density * path).reshape(s.height, s.width)
    assert np.abs(result.fog.transmittance - expected).max() < TRANSMITTANCE_TOLERANCE
    seen = result.gbuffer_position[..., 3] > 0.5
    assert np.all(path.reshape(seen.shape)[seen] < distances[seen])
    assert result.fog.transmittance.min() < 0.5 < result.fog.transmittance.max()


def test_density_zero_changes_nothing(pipeline):
    plain = pipeline.run(FOG.with_changes(fog=False))
    shown = pipeline.final_texture.read()
    clear = pipeline.run(FOG.with_changes(fog_density=0.0))
    assert np.all(clear.fog.transmittance == 1.0)
    assert not clear.fog.direct.any() and not clear.fog.lpv.any()
    assert np.array_equal(clear.final_image, plain.final_image)
    assert clear.display_scale == plain.display_scale
    assert pipeline.final_texture.read() == shown


def test_the_display_composes_the_fog(pipeline):
    result = pipeline.run(FOG.with_changes(exposure=2.0))
    fog = result.fog
    t = fog.transmittance[..., None]
    expected = 2.0 * (t * (result.direct + result.indirect) + fog.direct + fog.lpv)
    assert np.allclose(result.final_image, expected, rtol=1e-6, atol=1e-7)
    only = pipeline.run(FOG.with_changes(exposure=2.0, indirect_only=True))
    assert np.allclose(only.final_image, 2.0 * (t * result.indirect + fog.lpv),
                       rtol=1e-6, atol=1e-7)
    assert only.stages_run == ("display",)


def test_fog_settings_rerun_the_fog_and_the_display_only(pipeline):
    pipeline.run(FOG)
    assert pipeline.run(FOG.with_changes(fog_density=1.1)).stages_run == ("fog", "display")
    assert pipeline.run(FOG.with_changes(fog_density=1.1, camera=(
        (0.1, 0.5, 4.2), (0.0, -0.1, 0.0)))).stages_run == (
        "gbuffer", "gather", "fog", "display")
    off = FOG.with_changes(fog=False)
    pipeline.run(off)
    moved = pipeline.run(off.with_changes(camera=((0.2, 0.5, 4.2), (0.0, -0.1, 0.0))))
    assert moved.stages_run == ("gbuffer", "gather", "display") and moved.fog is None


@pytest.mark.parametrize("g", [0.0, 0.6, -0.8])
def test_phase_functions_integrate_to_one(g):
    """∫ p dω = 2π ∫ p(t) dt over the cosine (Gauss–Legendre): 1 for the isotropic
    function (g = 0) and every Henyey–Greenstein lobe."""
    nodes, weights = np.polynomial.legendre.leggauss(512)
    assert 2 * np.pi * np.sum(weights * media.hg_phase(nodes, g)) == pytest.approx(1, abs=1e-9)


@pytest.mark.parametrize("phase, g", [("isotropic", 0.0), ("henyey-greenstein", 0.7),
                                      ("henyey-greenstein", -0.4)])
def test_a_uniform_field_scatters_its_radiance_times_one_minus_t(pipeline, ctx, phase, g):
    """A grid holding the same band-0 intensity s0 in every cell is a radiance L = c0·s0/h²
    from every direction; any normalised phase function scatters L, so the fog adds
    α·L·(1 − T) to every pixel (exactly, segment by segment)."""
    settings = FOG.with_changes(fog_phase=phase, fog_g=g)
    result = pipeline.run(settings)
    spec = result.grid_spec
    s0 = np.array([0.5, 1.0, 2.0])
    textures = []
    for channel in range(3):
        data = np.zeros((spec.resolution,) * 3 + (4,), np.float32)
        data[..., 0] = s0[channel]
        textures.append(ctx.texture3d((spec.resolution,) * 3, 4, data.tobytes(), dtype="f4"))
    try:
        lights = pipeline.light_views
        fog = pipeline.state.fog_pass
        fog.run(pipeline.state.gbuffer_pass, lights.shadow_maps, pipeline.scene_state.scene,
                SampledGrid.single(spec, tuple(textures)), FogParams.of(settings).medium)
        lpv = read_texture(fog.targets["fog_lpv"])[..., :3]
        transmittance = read_texture(fog.targets["fog_direct"])[..., 3]
    finally:
        for texture in textures:
            texture.release()
    radiance = 1.0 / (2.0 * np.sqrt(np.pi)) * s0 / spec.cell_size**2
    expected = settings.fog_albedo * radiance * (1.0 - transmittance)[..., None]
    assert np.abs(lpv - expected).max() < 1e-5 * radiance.max()
    assert (transmittance < 0.9).any()
