"""The Error panel against Mitsuba: a finished measurement is rendered by Mitsuba in a
child process, a change of the settings ends that render, and the lesson placeholders
``{{error.mitsuba_*}}`` read the result. Skipped with the reason without Mitsuba."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from explorer.lpv.settings import Settings
from explorer.truth.mitsuba_render import mitsuba_available
from explorer.truth.progressive import Measurement

MISSING = mitsuba_available()
pytestmark = pytest.mark.skipif(MISSING is not None, reason=str(MISSING))
SMALL = Settings(scene="cornell", width=24, height=24, rsm_size=16, grid_size=8,
                 iterations=2)


def _until(service, ctx, done, calls: int = 4000) -> None:
    import time

    for _ in range(calls):
        service.advance(ctx, 0.01)
        if done():
            return
        time.sleep(0.005)
    raise AssertionError("the measurement did not finish")


def test_error_service_measures_against_mitsuba_and_cancels_on_change(ctx, monkeypatch):
    from explorer.lessons import live_values
    from explorer.truth.mitsuba_job import ErrorReadout
    from explorer.ui.panels import error as panel

    monkeypatch.setattr(panel, "MITSUBA_SPP", 4)
    state = SimpleNamespace(settings=SMALL)
    service = panel.ErrorService(state)
    service.measurement = Measurement(size=24, rsm_size=16, reference="unoccluded")
    service.truth = panel.TRUTHS[1]
    try:
        service.measure()
        _until(service, ctx, lambda: service.result_for() is not None
               and service.truth_job is not None)
        job = service.truth_job
        state.settings = SMALL.with_changes(iterations=3)     # moves on: Mitsuba ends too
        service.advance(ctx, 0.0)
        assert service.truth_job is None and job._process.poll() is not None
        state.settings = SMALL
        _until(service, ctx, lambda: service.truth_for() is not None)
        truth = service.truth_for()
        assert 0.0 < truth.reference.flux_ratio < 2.0 and truth.one_bounce.pixels > 0
        readout = ErrorReadout(service.result_for().stats, truth)
        context = live_values.LiveContext(settings=SMALL, error=readout)
        assert live_values.table()["error.mitsuba_flux_ratio"].read(context) == \
            pytest.approx(truth.one_bounce.flux_ratio)
        assert live_values.table()["error.reference_mitsuba_flux_ratio"].read(context) == \
            pytest.approx(truth.reference.flux_ratio)
        assert live_values.table()["error.flux_ratio"].read(context) == \
            pytest.approx(service.result_for().stats.flux_ratio)
        bare = live_values.LiveContext(settings=SMALL,
                                       error=ErrorReadout(readout.stats, None))
        with pytest.raises(live_values.Unavailable, match="Mitsuba"):
            live_values.table()["error.mitsuba_flux_ratio"].read(bare)
    finally:
        service.release()
