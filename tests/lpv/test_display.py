"""The display (docs/MODEL.md "Display"): the tone curves and sRGB of shaders/tonemap.glsl
against their numpy twin explorer/lpv/twin/tonemap.py, and the auto exposure's invariants."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from explorer.gl.program import ProgramCache
from explorer.lpv.passes.display import DisplayPass
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import TONE_MAPS, Settings
from explorer.lpv.twin import tonemap

SMALL = Settings(grid_size=8, iterations=2, rsm_size=32, width=48, height=40)


def hdr_image(height: int = 24, width: int = 40) -> np.ndarray:
    """Linear colours from 0 to 20 (every decade the curves treat differently), a few
    negative (the LPV's clamp can leave tiny ones) and exact zeros."""
    rng = np.random.default_rng(7)
    image = 10.0 ** rng.uniform(-4.0, 1.3, size=(height, width, 3))
    image[0] = 0.0
    image[1, :5] = -0.01
    return image.astype(np.float32)


def gpu_display(ctx, image: np.ndarray, scale: float, tone_map: str,
                exposure: float = 1.0) -> np.ndarray:
    """The display pass on ``image`` as the direct light (no indirect light)."""
    height, width = image.shape[:2]
    rgba = np.concatenate([image, np.ones((height, width, 1), np.float32)], axis=-1)
    direct = ctx.texture((width, height), 4, rgba.tobytes(), dtype="f4")
    indirect = ctx.texture((width, height), 4, np.zeros_like(rgba).tobytes(), dtype="f4")
    programs = ProgramCache(ctx)
    display = DisplayPass(ctx, programs)
    try:
        texture = display.run(direct, indirect, exposure, False, tone_map, scale)
        data = np.frombuffer(texture.read(), np.uint8).reshape(height, width, 4)
        return data[..., :3] / 255.0
    finally:
        display.release()
        programs.release()
        direct.release()
        indirect.release()


@pytest.mark.parametrize("tone_map", TONE_MAPS)
@pytest.mark.parametrize("scale, exposure", [(1.0, 1.0), (0.37, 1.0), (0.37, 2.5)])
def test_glsl_display_matches_numpy(ctx, tone_map, scale, exposure):
    """display.glsl = display_encode(exposure·linear, scale, curve): the auto exposure's
    scale multiplies the exposure."""
    image = hdr_image()
    gpu = gpu_display(ctx, image, scale, tone_map, exposure)
    cpu = tonemap.display_encode(exposure * image, scale, tone_map)
    # one RGBA8 step of rounding, half a step of float differences
    assert np.allclose(gpu, cpu, atol=1.5 / 255)
    assert np.all(gpu[0] == 0.0)                       # black stays black
    assert np.all(gpu[1, :5] == 0.0)                   # negative light shows as black


def test_filmic_curve_is_the_aces_fit():
    x = sp.Symbol("x", nonnegative=True)
    a, b, c, d, e = (sp.nsimplify(v) for v in tonemap.ACES_FIT)
    curve = x * (a * x + b) / (x * (c * x + d) + e)
    # it reaches 1 at x = 7/2 + √14 (the GLSL comment), and is clamped there
    top = sp.solve(sp.Eq(curve, 1), x)
    assert len(top) == 1 and sp.simplify(top[0] - (sp.Rational(7, 2) + sp.sqrt(14))) == 0
    xs = np.linspace(0.0, 20.0, 4001)
    f = tonemap.filmic(xs)
    assert f[0] == 0.0 and np.all(np.diff(f) >= 0.0) and f.max() == 1.0
    assert np.allclose(f[xs < 7.2], sp.lambdify(x, curve)(xs[xs < 7.2]), rtol=1e-12)
    # highlights roll off instead of clipping at 1: linear-clip loses everything above 1
    assert tonemap.clipped_fraction(xs[:, None] * np.ones(3), 1.0, "linear-clip") > 0.9
    assert tonemap.clipped_fraction(xs[:, None] * np.ones(3), 1.0, "filmic") < 0.65


def test_auto_exposure_undoes_any_change_of_flux():
    image = hdr_image().astype(np.float64)
    mask = np.ones(image.shape[:2], bool)
    base = tonemap.auto_exposure_scale(image, mask)
    for factor in (1e-3, 0.5, 7.0, 1e4):
        assert tonemap.auto_exposure_scale(factor * image, mask) == pytest.approx(
            base / factor, rel=1e-9)
    # the metered window comes out at the key
    assert tonemap.log_average_luminance(base * image, mask) == pytest.approx(
        tonemap.AUTO_EXPOSURE_KEY, rel=1e-9)
    assert tonemap.auto_exposure_scale(np.zeros_like(image)) == 1.0    # nothing lit


def test_log_average_window():
    # 100 pixels of luminance 1..100: the window 50th..98th percentile by rank holds the
    # pixels 51..98, and the log average is their (δ-shifted) geometric mean
    lum = np.arange(1.0, 101.0)
    image = np.repeat(lum[:, None], 3, axis=1)[None]
    mean = tonemap.log_average_luminance(image, percentiles=(50.0, 98.0))
    delta = tonemap.LOG_AVERAGE_FLOOR * 100.0
    assert mean == pytest.approx(np.exp(np.mean(np.log(delta + np.arange(51.0, 99.0)))))
    everything = tonemap.log_average_luminance(image, percentiles=(0.0, 100.0))
    assert everything == pytest.approx(np.exp(np.mean(np.log(delta + lum))))
    # two lit pixels: the window still holds one (the brighter), never none
    pair = np.array([[[1.0, 1.0, 1.0], [4.0, 4.0, 4.0]]])
    assert tonemap.log_average_luminance(pair) == pytest.approx(4.0 + 4e-4)
    with pytest.raises(ValueError, match="tone_map"):
        tonemap.display_encode(image, 1.0, "sepia")


def test_pipeline_display_texture_is_the_numpy_view(ctx):
    with Pipeline(SMALL, ctx=ctx) as pipeline:
        for settings in (SMALL, SMALL.with_changes(tone_map="linear-clip", exposure=3.0),
                         SMALL.with_changes(auto_exposure=False)):
            result = pipeline.run(settings)
            texture = pipeline.final_texture
            gpu = np.frombuffer(texture.read(), np.uint8).reshape(
                settings.height, settings.width, 4)[::-1, :, :3] / 255.0
            assert np.allclose(gpu, pipeline.view("final"), atol=1.5 / 255)
            if not settings.auto_exposure:
                assert result.display_scale == 1.0


def test_auto_exposure_shows_the_same_image_at_any_flux(ctx):
    with Pipeline(SMALL, ctx=ctx) as pipeline:
        one = pipeline.run(SMALL)
        image = pipeline.view("final")
        scale = one.display_scale
        four = pipeline.run(SMALL.with_changes(light_flux=4.0 * one_flux(pipeline)))
        assert four.display_scale == pytest.approx(scale / 4.0, rel=1e-5)
        assert np.allclose(pipeline.view("final"), image, atol=1e-5)
        # a fixed exposure shows the flux; the override shows a frame at another's scale
        fixed = pipeline.run(SMALL.with_changes(auto_exposure=False))
        assert fixed.display_scale == 1.0
        pipeline.display_scale_override = 0.25
        assert pipeline.run(SMALL).display_scale == 0.25
        assert pipeline.run(SMALL).stages_run == ()


def one_flux(pipeline: Pipeline) -> float:
    return pipeline.base_scene.light.flux


def test_filmic_auto_exposure_clips_less_than_linear_clip_on_the_cornell_box(ctx):
    settings = Settings(width=96, height=96, grid_size=16, iterations=8, rsm_size=64)
    with Pipeline(settings, ctx=ctx) as pipeline:
        result = pipeline.run(settings)
    final = result.final_image
    linear = tonemap.clipped_fraction(final, 1.0, "linear-clip")
    filmic = tonemap.clipped_fraction(final, result.display_scale, "filmic")
    assert filmic == 0.0 and linear >= filmic


def test_exposure_is_a_compensation_on_top_of_the_auto_exposure(ctx):
    """The display stage alone runs for exposure and indirect-only; the auto exposure is
    measured once per gathered frame (an exposure change keeps it) and on what is shown
    (indirect-only meters the indirect light)."""
    with Pipeline(SMALL, ctx=ctx) as pipeline:
        one = pipeline.run(SMALL)
        brighter = SMALL.with_changes(exposure=2.0)
        two = pipeline.run(brighter)
        assert two.stages_run == ("display",) and two.display_scale == one.display_scale
        gpu = np.frombuffer(pipeline.final_texture.read(), np.uint8).reshape(
            SMALL.height, SMALL.width, 4)[::-1, :, :3] / 255.0
        assert np.allclose(gpu, tonemap.display_encode(2.0 * one.final_image,
                                                       one.display_scale, "filmic"),
                           atol=1.5 / 255)
        only = pipeline.run(brighter.with_changes(indirect_only=True))
        assert only.stages_run == ("display",)
        assert only.display_scale == pytest.approx(tonemap.auto_exposure_scale(
            only.indirect, only.gbuffer_position[..., 3] > 0.5), rel=1e-12)
        assert only.display_scale > one.display_scale    # the indirect light alone is dimmer
