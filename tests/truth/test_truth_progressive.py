"""The tiled, step-by-step reference equals the one-shot reference of the same frame; an
error job measures a configuration and its metrics agree with explorer.truth.metrics."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.lpv.settings import Settings
from explorer.truth.progressive import (
    ErrorJob,
    Measurement,
    ProgressiveReference,
    measured_settings,
    tiles,
)

SMALL = Settings(width=40, height=32, grid_size=12, iterations=4, rsm_size=16)


def test_tiles_cover_the_image_once():
    rects = tiles(70, 33, 16)
    covered = np.zeros((33, 70), int)
    for x0, y0, x1, y1 in rects:
        covered[y0:y1, x0:x1] += 1
    assert (covered == 1).all() and len(rects) == 5 * 3


def test_measured_settings_keep_everything_but_the_sizes():
    base = Settings(grid_size=24, iterations=5, width=800, height=400, rsm_size=256)
    measured = measured_settings(base, Measurement(size=100, rsm_size=32), aspect=2.0)
    assert (measured.width, measured.height, measured.rsm_size) == (100, 50, 32)
    assert measured.with_changes(width=800, height=400, rsm_size=256) == base
    tall = measured_settings(base, Measurement(size=100), aspect=0.5)
    assert (tall.width, tall.height) == (50, 100)
    with pytest.raises(ValueError, match="reference must be one of"):
        Measurement(reference="sometimes")


@pytest.mark.parametrize("visibility", [False, True])
def test_progressive_reference_equals_the_one_shot_reference(ctx, visibility):
    from explorer.lpv.pipeline import Pipeline
    from explorer.truth.render import reference_for_frame

    with Pipeline(SMALL, ctx=ctx) as pipeline:
        frame = pipeline.run(SMALL)
    expected, _ = reference_for_frame(frame, visibility, ctx=ctx)
    job = ProgressiveReference(ctx, frame, visibility, tile=16)
    try:
        steps = 0
        while not job.step():
            steps += 1
            assert 0.0 < job.fraction < 1.0
        assert steps + 1 == len(job.tiles) == 3 * 2
        got = job.radiance()
    finally:
        job.release()
    assert expected.max() > 0
    np.testing.assert_allclose(got, expected, rtol=1e-5, atol=1e-6 * expected.max())


@pytest.mark.parametrize("reference", ["unoccluded", "visible"])
def test_error_job_measures_and_its_metrics_are_the_modules(ctx, reference):
    """The job goes through its stages in small units (with no budget, one per call: a
    unit of the pipeline's job, a BVH node, a dispatch of the reference; a call that sets
    up the next stage does none) and ends on the one-shot reference of its frame."""
    from explorer.lpv.pipeline import Pipeline
    from explorer.truth.metrics import flux_ratio, relative_l2
    from explorer.truth.render import reference_for_frame

    measurement = Measurement(size=24, rsm_size=16, reference=reference)
    job = ErrorJob(SMALL, measurement, aspect=1.0)
    stages, units, fractions = [], [], []
    with Pipeline(job.settings, ctx=ctx) as pipeline:
        assert job.stage == "LPV frame" and job.fraction == 0.0
        while not job.advance(ctx, pipeline, budget_s=0.0):
            units.append(job.units)
            fractions.append(job.fraction)
            if not stages or stages[-1] != job.stage:
                stages.append(job.stage)
        expected, _ = reference_for_frame(job.frame, reference == "visible", ctx=ctx)
    job.release()
    result = job.result
    wanted = ["LPV frame", "building BVH", "reference"] if reference == "visible" else \
        ["LPV frame", "reference"]
    assert stages == wanted and job.fraction == 1.0
    assert set(units) <= {0, 1} and units.count(1) > 10     # the frame alone has more
    assert fractions == sorted(fractions)
    np.testing.assert_array_equal(result.reference, expected)
    assert result.lpv.shape == result.reference.shape == (24, 24, 3)
    assert result.valid.any()
    assert result.stats.relative_l2 == pytest.approx(
        relative_l2(result.lpv, result.reference, result.valid))
    assert result.stats.flux_ratio == pytest.approx(
        flux_ratio(result.lpv, result.reference, result.valid))
    assert 0.0 < result.stats.flux_ratio < 10.0


def test_error_service_cancels_on_change_and_caches_per_settings(ctx):
    """The Error panel's background task: a measurement runs a little per frame, a
    settings change cancels it, every finished one is kept and found again."""
    from types import SimpleNamespace

    from explorer.ui.panels.error import ErrorService

    state = SimpleNamespace(settings=SMALL)
    service = ErrorService(state)
    service.measurement = Measurement(size=24, rsm_size=16, reference="unoccluded")
    try:
        service.measure()
        service.advance(ctx, 0.0)                      # renders the LPV frame
        assert service.running and service.result_for() is None
        state.settings = SMALL.with_changes(iterations=2)
        service.advance(ctx, 0.0)
        assert not service.running                    # the settings moved on: cancelled
        service.measure()
        for _ in range(2000):                         # one small unit per call
            service.advance(ctx, 0.0)
            if not service.running:
                break
        second = service.result_for()
        assert second is not None and second.settings.iterations == 2
        state.settings = SMALL                        # back: nothing cached, nothing asked
        service.advance(ctx, 0.0)
        assert not service.running and service.result_for() is None
        state.settings = SMALL.with_changes(iterations=2, exposure=3.0, width=400,
                                            height=320)  # same measurement (display, aspect)
        assert service.result_for() is second
    finally:
        service.release()
