"""Live numbers: each name is one quantity, and its value is that quantity computed from
the frame (checked here against the FrameResult's own arrays), the settings, the error
measurement or the derivation table."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from lpv_cases import run_frame

from explorer import derived
from explorer.lessons import live_values as lv
from explorer.lpv.settings import PRESETS, Settings

SMALL = Settings(width=48, height=40, grid_size=12, iterations=5, rsm_size=24)
FOG_NAMES = ("frame.fog_lpv_share", "frame.fog_transmittance")
"""Quantities of the fog, which SMALL does not have (test_fog_numbers reads them)."""


@pytest.fixture(scope="module")
def frame(gl_context):
    return run_frame(gl_context, SMALL)


def test_names_are_checked_and_close_matches_offered():
    assert lv.lookup("audit.injected").unit == "W"
    assert lv.lookup("settings.grid_size").source == "settings"
    with pytest.raises(KeyError, match="did you mean audit.injected"):
        lv.lookup("audit.injectd")
    with pytest.raises(KeyError, match="no derivation result"):
        lv.lookup("derived.sh.c9")
    with pytest.raises(KeyError, match="a formula"):
        lv.lookup("derived.sh.lobe")                 # no numeric value
    with pytest.raises(KeyError, match="no figure with id 'lobe'"):
        lv.lookup("figure.lobe.l1_energy", figure_ids=("faces",))
    assert lv.lookup("figure.lobe.l1_energy", figure_ids=("lobe",)).measured
    # the pipeline's stage count is read with the frame but no setting changes it: its
    # tooltip must not call it measured (lesson 15 step 4 quotes it next to stages_ran)
    assert lv.lookup("frame.stages").constant and not lv.lookup("frame.stages").measured
    assert lv.lookup("frame.stages_ran").measured
    with pytest.raises(ValueError, match="does not apply"):
        lv.check_format(".3q", lv.lookup("audit.injected"))


def test_every_fixed_name_reads_a_value_from_a_real_frame(frame):
    from types import SimpleNamespace

    from explorer.truth.metrics import ErrorStats
    from explorer.truth.mitsuba_job import ErrorReadout

    stats = ErrorStats(0.5, 0.01, 0.9, (0.8, 0.9, 1.0), 100)
    truth = SimpleNamespace(one_bounce=stats, multi_bounce=stats, reference=stats)
    context = lv.LiveContext(settings=SMALL, result=frame, error=ErrorReadout(stats, truth),
                             renderer="llvmpipe")
    for name in lv.table():
        if name.startswith("frame.time.") and name != "frame.time.total" and \
                name.rsplit(".", 1)[1] not in frame.timings_ms:
            # a pass that did not run (no downsampling, no geometry volume): no time
            assert lv.render(name, "", context) == lv.PENDING
            continue
        if name in FOG_NAMES:                       # the frame has no fog: nothing to read
            assert lv.render(name, "", context) == lv.PENDING
            continue
        text = lv.render(name, "", context)
        assert text != lv.PENDING and text, name


def test_audit_numbers_are_the_frames_own_sums(frame):
    context = lv.LiveContext(settings=SMALL, result=frame)
    audit = frame.audit

    def value(name):
        return lv.lookup(name).value(context)

    for name in ("rsm", "injected", "accumulated", "gathered", "border_loss", "clamp_gain",
                 "occluded"):
        assert value(f"audit.{name}") == pytest.approx(float(np.sum(getattr(audit, name))))
    per_step = np.asarray(audit.per_step).sum(axis=1)
    assert value("audit.step_ratio") == pytest.approx(per_step[1] / per_step[0])
    assert value("audit.last_over_first") == pytest.approx(per_step[-1] / per_step[0])
    assert value("audit.max_over_first") == pytest.approx(per_step.max() / per_step[0])
    assert value("audit.injected_over_rsm") == pytest.approx(
        np.sum(audit.injected) / np.sum(audit.rsm))
    # corrected formulas: the grid receives what the RSM reflects (docs/MODEL.md)
    assert value("audit.injected_over_rsm") == pytest.approx(1.0, rel=1e-4)
    assert value("audit.budget_withheld") == 0.0              # no flux budget here


def test_the_flux_budgets_term_is_quoted_from_the_frame(ctx):
    """Under the flux budget ``audit.budget_withheld`` is the audit's own term, and with
    the corrected formulas it equals the clamp gain (the budget keeps the step's flux)."""
    from explorer.lpv.pipeline import Pipeline

    settings = SMALL.with_changes(flux_budget=True)
    with Pipeline(settings, ctx=ctx) as pipeline:
        result = pipeline.run(settings)
    context = lv.LiveContext(settings=settings, result=result)

    def value(name):
        return lv.lookup(name).value(context)

    withheld = float(np.sum(result.audit.budget_withheld))
    assert withheld > 0 and value("audit.budget_withheld") == pytest.approx(withheld)
    assert value("audit.budget_withheld_share") == pytest.approx(
        withheld / float(np.sum(result.audit.injected)))
    assert value("audit.budget_withheld_over_clamp_gain") == pytest.approx(1.0, rel=1e-4)
    assert lv.audit_needed("audit.budget_withheld_share") == "full"


def test_frame_numbers(frame):
    from explorer.lpv.cascades import texture_bytes

    context = lv.LiveContext(settings=SMALL, result=frame)

    def value(name):
        return lv.lookup(name).value(context)

    lit = np.asarray(frame.vpls.flux).sum(axis=1) > 0
    assert value("frame.vpls") == frame.vpls.count
    assert value("frame.lit_vpls") == int(lit.sum())
    assert value("frame.vpl_depth_max") == pytest.approx(float(frame.vpls.depth[lit].max()))
    assert value("frame.cell_size") == pytest.approx(frame.grid_spec.cell_size)
    assert value("frame.cells") == 12 ** 3
    assert value("frame.rsm_texels") == 24 ** 2 * len(frame.vpl_sets)
    assert value("frame.vpls") <= value("frame.rsm_texels")
    assert tuple(value(f"frame.grid_origin_{axis}") for axis in "xyz") == \
        pytest.approx(value("frame.grid_origin"))
    assert value("frame.face_evaluations") == 30 * 12 ** 3 * 5
    assert value("frame.lpv_memory_mib") == pytest.approx(
        texture_bytes(12, 1, "rgba32f", False) / 2 ** 20)
    assert value("frame.time.propagate") == pytest.approx(frame.timings_ms["propagate"])
    assert value("frame.time.total") == pytest.approx(sum(frame.timings_ms.values()))
    assert value("frame.timer") in ("GPU timer queries", "the wall clock")


def test_settings_switches_derived_and_error():
    original = SMALL.with_changes(corrections="original")
    context = lv.LiveContext(settings=original)
    assert lv.render("settings.grid_size", "", context) == "12"
    assert lv.render("settings.geometry_volume", "", context) == "off"
    assert lv.render("corrections.injection_pi", "", context) == "off"
    assert lv.render("corrections.preset", "", context) == "original"
    custom = lv.LiveContext(settings=SMALL.with_changes(corrections={"side_faces": False}))
    assert lv.render("corrections.preset", "", custom) == "custom"
    assert lv.render("derived.sh.c0", ".10f", context) == f"{derived.get('sh.c0').value:.10f}"
    assert lv.render("derived.corrections.clamp_front_face.lobe_behind", ".2f",
                     context) == "−0.25"                   # a true minus sign
    assert lv.render("error.relative_l2", ".2f", context) == lv.PENDING
    stats = SimpleNamespace(relative_l2=0.714, flux_ratio=0.5, rmse=0.1,
                            flux_ratio_rgb=(0.4, 0.5, 0.6))
    measured = lv.LiveContext(settings=SMALL, error=stats)
    assert lv.render("error.relative_l2", ".2f", measured) == "0.71"
    assert lv.render("error.flux_ratio_blue", ".1f", measured) == "0.6"
    assert PRESETS["corrected"] == SMALL.corrections


def test_nothing_is_read_before_a_frame():
    context = lv.LiveContext()
    for name in ("audit.injected", "frame.vpls", "frame.time.rsm", "settings.iterations",
                 "figure.x.y"):
        ids = ("x",) if name.startswith("figure") else ()
        assert lv.render(name, "", context, ids) == lv.PENDING


def test_format_value():
    assert lv.format_value(True, "") == "on"
    assert lv.format_value(-0.5, ".2f") == "−0.50"
    assert lv.format_value(math.inf, ".2f") == "∞"
    assert lv.format_value((1.0, -2.0), ".1f") == "(1.0, −2.0)"
    assert lv.format_value(12345, ",d") == "12,345"
    assert lv.format_value("room", "") == "room"


def test_fog_numbers(gl_context):
    from explorer.lpv.pipeline import Pipeline
    from explorer.lpv.twin.tonemap import luminance

    foggy = SMALL.with_changes(fog=True, fog_density=0.8, fog_steps=6)
    gl_context.__enter__()
    with Pipeline(foggy, ctx=gl_context) as pipeline:
        result = pipeline.run(foggy)
    context = lv.LiveContext(settings=foggy, result=result)
    lpv, direct = luminance(result.fog.lpv).sum(), luminance(result.fog.direct).sum()
    share = lv.lookup("frame.fog_lpv_share").value(context)
    assert share == pytest.approx(lpv / (lpv + direct)) and 0 < share < 1
    seen = result.gbuffer_position[..., 3] > 0.5
    assert lv.lookup("frame.fog_transmittance").value(context) == pytest.approx(
        float(result.fog.transmittance[seen].mean()))
    assert lv.render("frame.time.fog", ".1f", context) != lv.PENDING


@pytest.mark.parametrize("mode", ["flux", "off"])
def test_terms_the_audit_mode_did_not_measure_wait_with_a_reason(gl_context, frame, mode):
    """A frame propagated with the flux-only audit (or none) has no border loss, clamp
    gain, occlusion or reflection: those numbers (and ratios of them) show "…" and say
    why, while what the mode measures reads as on the full audit's frame."""
    from explorer.ui.article_numbers import uses_audit

    cheap = run_frame(gl_context, SMALL, need_audit=mode)
    context = lv.LiveContext(settings=SMALL, result=cheap)
    full = lv.LiveContext(settings=SMALL, result=frame)
    for name in lv.table():
        if not name.startswith("audit."):
            continue
        needed = lv.audit_needed(name)
        if needed == "full" or (needed == "flux" and mode == "off"):
            assert lv.render(name, "", context) == lv.PENDING, name
            reason = lv.pending_reason(name, context)
            assert f"audit mode {mode}" in reason and "full energy audit" in reason, name
        else:
            assert lv.lookup(name).value(context) == pytest.approx(
                lv.lookup(name).value(full), rel=1e-5), name
    for name in ("audit.border_loss", "audit.clamp_gain_share", "audit.reflected"):
        assert lv.audit_needed(name) == "full"
    assert lv.audit_needed("audit.step_ratio") == "flux"
    assert lv.audit_needed("audit.injected_over_rsm") == "off"
    # a lesson step asks the window for what its numbers and figures need
    step = SimpleNamespace(text="{{audit.step_ratio:.3f}}", try_this=(), figures=())
    assert uses_audit(step) == "flux"
    step.text += " and {{audit.border_loss_share:.2%}}"
    assert uses_audit(step) == "full"
    step = SimpleNamespace(text="{{audit.accumulated:.3g}}", try_this=(),
                           figures=(SimpleNamespace(kind="flux-per-step", caption=""),))
    assert uses_audit(step) == "flux"
    step.figures += (SimpleNamespace(kind="energy-audit", caption=""),)
    assert uses_audit(step) == "full"
