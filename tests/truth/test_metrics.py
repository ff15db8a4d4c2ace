"""Error metrics on arrays whose answers are known by hand."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.truth.metrics import (
    EmptyRegionError,
    diverging_colormap,
    error_image,
    error_stats,
    flux_ratio,
    rect_mask,
    relative_l2,
    rmse,
)


def constant(value, height=4, width=5):
    return np.full((height, width, 3), float(value))


def test_known_values_over_the_whole_image():
    reference = constant(2.0)
    test = constant(3.0)
    assert relative_l2(test, reference) == pytest.approx(0.5)
    assert rmse(test, reference) == pytest.approx(1.0)
    assert flux_ratio(test, reference) == pytest.approx(1.5)
    np.testing.assert_allclose(flux_ratio(test, reference, per_channel=True), [1.5] * 3)
    stats = error_stats(test, reference)
    assert stats.pixels == 20 and stats.flux_ratio_rgb == pytest.approx((1.5, 1.5, 1.5))


def test_regions_as_masks_and_rectangles():
    reference = constant(1.0)
    test = constant(1.0)
    test[0:2, 0:2] = 4.0  # rows 0-1, columns 0-1 are wrong
    rect = [(0, 0, 2, 2)]
    assert flux_ratio(test, reference, rect) == pytest.approx(4.0)
    assert relative_l2(test, reference, rect) == pytest.approx(3.0)
    elsewhere = ~rect_mask((4, 5), rect)
    assert relative_l2(test, reference, elsewhere) == 0.0
    assert flux_ratio(test, reference, elsewhere) == 1.0
    # whole image: 4 of 20 pixels off by 3 in each channel
    assert rmse(test, reference) == pytest.approx(np.sqrt(4 * 9 / 20))
    # rectangles are clipped to the image and unioned
    assert rect_mask((4, 5), [(-3, -3, 1, 1), (4, 3, 9, 9)]).sum() == 2


def test_empty_region_and_bad_input_raise_clear_errors():
    image = constant(1.0)
    with pytest.raises(EmptyRegionError, match="no pixels"):
        relative_l2(image, image, np.zeros((4, 5), bool))
    with pytest.raises(EmptyRegionError):
        flux_ratio(image, image, [(2, 2, 2, 4)])  # zero width
    with pytest.raises(ValueError, match="mask must have shape"):
        rmse(image, image, np.ones((5, 4), bool))
    with pytest.raises(ValueError, match="differ in shape"):
        rmse(image, constant(1.0, 3, 5))
    with pytest.raises(ValueError, match=r"\(H, W, 3\)"):
        rmse(image[..., 0], image[..., 0])
    nan = image.copy()
    nan[0, 0, 0] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        flux_ratio(nan, image)
    with pytest.raises(ValueError, match="x1 < x0"):
        rect_mask((4, 5), [(3, 0, 1, 2)])


def test_zero_reference_conventions():
    zero = constant(0.0)
    assert relative_l2(zero, zero) == 0.0
    assert flux_ratio(zero, zero) == 1.0
    assert relative_l2(constant(0.1), zero) == np.inf
    assert flux_ratio(constant(0.1), zero) == np.inf
    assert flux_ratio(constant(-0.1), zero) == -np.inf
    assert rmse(constant(0.5), zero) == pytest.approx(0.5)


def test_error_image_colours_and_scale():
    reference = constant(1.0)
    test = constant(1.0)
    test[0, 0] = 4.0   # two stops too bright
    test[3, 4] = 0.25  # two stops too dark
    image = error_image(test, reference, mode="log2-ratio", scale=2.0)
    assert image.rgb.shape == (4, 5, 3) and image.scale == 2.0
    assert image.values[0, 0] == pytest.approx(2.0, abs=1e-2)
    assert image.values[3, 4] == pytest.approx(-2.0, abs=1e-2)
    red, blue, white = image.rgb[0, 0], image.rgb[3, 4], image.rgb[1, 1]
    assert red[0] > red[2] and blue[2] > blue[0] and np.ptp(white) < 1e-9
    diff = error_image(test, reference, mode="difference")
    assert diff.values[0, 0] == pytest.approx(3.0) and diff.scale > 0
    masked = error_image(test, reference, region=[(0, 0, 1, 1)])
    assert np.isnan(masked.values[1, 1]) and np.isfinite(masked.values[0, 0])
    # identical images: a positive scale and an all-white map instead of a division by zero
    same = error_image(reference, reference)
    assert same.scale > 0 and np.all(np.abs(same.values) < 1e-12)
    with pytest.raises(ValueError, match="mode"):
        error_image(test, reference, mode="ratio")


def test_diverging_colormap_ends_and_clipping():
    rgb = diverging_colormap(np.array([-5.0, -1.0, 0.0, 1.0, 5.0]), scale=1.0)
    np.testing.assert_allclose(rgb[0], rgb[1])
    np.testing.assert_allclose(rgb[3], rgb[4])
    assert rgb[1][2] > rgb[1][0] and rgb[3][0] > rgb[3][2]
    with pytest.raises(ValueError, match="scale"):
        diverging_colormap(np.zeros(2), 0.0)
