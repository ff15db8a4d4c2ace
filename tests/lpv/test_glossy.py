"""Glossy reflections (docs/MODEL.md "Glossy reflections"): the gather's march along the
reflected view direction against the numpy twin, and what the lobe does."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.lpv.grid import GridSpec
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.twin import media

PLAIN = Settings(scene="cornell", grid_size=8, iterations=4, width=48, height=32,
                 rsm_size=32)
TOLERANCE = 2e-6
"""Largest glossy difference relative to the largest glossy radiance (float32 lookups)."""


@pytest.fixture(scope="module")
def pipeline(gl_context):
    pipe = Pipeline(PLAIN, ctx=gl_context)
    yield pipe
    pipe.release()


def glossy_term(pipeline, settings):
    """(the GPU's glossy radiance per visible pixel, the reference's, the frame)."""
    plain = pipeline.run(settings.with_changes(glossy=False))
    diffuse = plain.indirect.copy()
    result = pipeline.run(settings.with_changes(glossy=True))
    seen = result.gbuffer_position[..., 3] > 0.5
    expected = media.glossy(result.cascade_accumulated, result.cascade_specs,
                            result.gbuffer_position[seen, :3], result.gbuffer_normal[seen, :3],
                            result.camera.eye, settings.glossy_roughness,
                            settings.glossy_strength, settings.glossy_samples)
    return (result.indirect - diffuse)[seen], expected, result


@pytest.mark.parametrize("changes", [
    {}, {"cascades": 2}, {"sh_order": 2, "glossy_roughness": 0.0},
    {"glossy_roughness": 1.0, "glossy_samples": 7, "glossy_strength": 0.9},
    {"lights": ("spot", "lamp", "bulb", "sun")},        # every light of the Cornell rig
])
def test_the_march_matches_the_reference(pipeline, changes):
    got, expected, _ = glossy_term(pipeline, PLAIN.with_changes(**changes))
    assert expected.max() > 0
    assert np.abs(got - expected).max() < TOLERANCE * expected.max()


def test_glossy_settings_rerun_the_gather_only(pipeline):
    pipeline.run(PLAIN.with_changes(glossy=True))
    for change in ({"glossy_roughness": 0.7}, {"glossy_strength": 0.2},
                   {"glossy_samples": 2}):
        assert pipeline.run(PLAIN.with_changes(glossy=True, **change)).stages_run == (
            "gather", "display")


def test_strength_zero_adds_nothing_and_strength_scales(pipeline):
    plain = pipeline.run(PLAIN).indirect.copy()
    none = pipeline.run(PLAIN.with_changes(glossy=True, glossy_strength=0.0)).indirect
    assert np.array_equal(none, plain)
    half, _, _ = glossy_term(pipeline, PLAIN.with_changes(glossy_strength=0.4))
    full, _, _ = glossy_term(pipeline, PLAIN.with_changes(glossy_strength=0.8))
    assert np.allclose(full, 2.0 * half, rtol=1e-5, atol=1e-7)


def test_the_lobe_is_normalised():
    """A grid of uniform radiance L (band 0 only) reflects k_s·L at every roughness: the
    Henyey–Greenstein lobe integrates to 1. A grid holding only light travelling along
    −r (band 1 along it) is seen brighter through sharper lobes: band 1 is scaled by
    g = 1 − roughness."""
    spec = GridSpec((0.0, 0.0, 0.0), 0.5, 4)
    uniform = np.zeros((3, 4, 4, 4, 4))
    uniform[..., 0] = 2.0
    point = np.array([[1.0, 1.0, 1.0]])
    up = np.array([[0.0, 1.0, 0.0]])
    eye = (1.0, 3.0, 1.0)                                  # looking straight down: r = +y
    radiance = 2.0 / (2.0 * np.sqrt(np.pi)) / spec.cell_size**2
    for roughness in (0.0, 0.5, 1.0):
        value = media.glossy([uniform], [spec], point, up, eye, roughness, 0.5, 3)
        assert value == pytest.approx(np.full((1, 3), 0.5 * radiance), rel=1e-12)
    downward = uniform.copy()
    downward[..., 1] = 1.0                  # −c1·y term: more light travelling along −y
    values = [media.glossy([downward], [spec], point, up, eye, roughness, 1.0, 2)[0, 0]
              for roughness in (1.0, 0.5, 0.0)]
    assert values[0] == pytest.approx(radiance)
    assert values[0] < values[1] < values[2]
