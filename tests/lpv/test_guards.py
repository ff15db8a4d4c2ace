"""Numeric guards (FrameResult.warnings) and the bounds of every request that costs
memory: checked every run, named in one line."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from explorer.lpv import guards
from explorer.lpv.limits import memory_requests
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import PRESETS, Corrections, Settings

SMALL = Settings(scene="cornell", grid_size=8, iterations=6, rsm_size=16, width=16,
                 height=16)


@pytest.fixture(scope="module")
def pipeline(gl_context):
    pipe = Pipeline(SMALL, ctx=gl_context)
    yield pipe
    pipe.release()


def test_flux_per_step_of_the_presets():
    """π·k_R·k_I·k_P·(covered solid angle)/4π (docs/MODEL.md "Propagation")."""
    assert guards.step_flux_factor(Corrections()) == pytest.approx(1.0, abs=1e-12)
    # the published side-face solid angle is 2.4e-5 too large (docs/MODEL.md "Corrections")
    assert guards.step_flux_factor(PRESETS["original"]) == pytest.approx(1 / (4 * math.pi),
                                                                         rel=1e-4)
    published_injection = replace(Corrections(), injection_pi=False)
    assert guards.step_flux_factor(published_injection) == pytest.approx(math.pi)
    assert guards.growth_explanation(Corrections()) is None
    assert guards.growth_explanation(PRESETS["original"]) is None     # it loses light
    text = guards.growth_explanation(published_injection)
    assert "×3.142 per step" in text and "Injection: intensity = flux / π" in text
    in_place = guards.growth_explanation(replace(Corrections(), ping_pong=False))
    assert "×2 per step" in in_place and "in place" in in_place


def test_a_correct_frame_has_no_warning(pipeline):
    assert pipeline.run(SMALL).warnings == []


def test_published_injection_alone_explains_its_growth(pipeline):
    result = pipeline.run(SMALL.with_changes(iterations=16,
                                             corrections={"injection_pi": False}))
    assert len(result.warnings) == 1
    warning = result.warnings[0]
    assert "×3.142 per step" in warning and "after 16 steps" in warning
    measured = float(np.sum(result.audit.accumulated) / np.sum(result.audit.injected))
    assert measured > 1e6 and f"{measured:.3g}" in warning


def test_overflow_names_the_pass_and_the_switches_without_debug_nan(pipeline):
    """injection_pi and ping_pong off: (1 + π)^64 overflows float32 in place."""
    settings = SMALL.with_changes(iterations=64, corrections={"injection_pi": False,
                                                              "ping_pong": False})
    result = pipeline.run(settings, need_audit=False)
    assert not np.isfinite(result.accumulated).all()
    propagate = [w for w in result.warnings if w.startswith("the propagate pass")]
    assert len(propagate) == 1
    assert "switches off: injection_pi, ping_pong" in propagate[0]
    assert "NaN" in propagate[0] and "×4.142 per step" in propagate[0]
    assert any("beyond float32's range" in w for w in result.warnings)
    with pytest.raises(FloatingPointError, match="propagate"):
        pipeline.run(settings.with_changes(debug_nan=True))


def test_a_nan_at_the_rsm_is_a_warning_naming_the_rsm(pipeline):
    settings = SMALL.with_changes()
    object.__setattr__(settings, "light_flux", float("nan"))   # as a mesh or a file can
    result = pipeline.run(settings)
    assert result.warnings[0].startswith("the rsm pass produced ")
    assert "all corrections on" in result.warnings[0]


@pytest.mark.parametrize("scale, words", [(1e-7, "smaller than 1e-05"),
                                          (1e11, "larger than 1e+09")])
def test_a_mesh_whose_scale_loses_or_overflows_the_light_is_named(tmp_path, gl_context,
                                                                   scale, words):
    trimesh = pytest.importorskip("trimesh")
    from explorer.scene import load_scene

    cornell = load_scene("cornell")
    corners = cornell.positions.reshape(-1, 3).astype(np.float64) * scale
    path = tmp_path / "scaled.ply"
    trimesh.Trimesh(corners, np.arange(len(corners)).reshape(-1, 3), process=False).export(
        path)
    with Pipeline(SMALL, ctx=gl_context) as pipe:
        result = pipe.run(SMALL.with_changes(scene=str(path)))
    found = [w for w in result.warnings if w.startswith("the scene is")]
    assert len(found) == 1 and words in found[0]
    assert f"{2 * scale:.3g} world units across" in found[0]


def test_the_memory_budget_is_checked_before_anything_is_allocated(gl_context):
    with Pipeline(SMALL, ctx=gl_context) as pipe:
        pipe.memory_budget_bytes = 64 << 20
        big = SMALL.with_changes(rsm_size=2048)
        with pytest.raises(ValueError) as error:
            pipe.run(big)
        message = str(error.value)
        assert "\n" not in message
        assert message.startswith("rsm_size 2048 (RSM textures and their read-back) needs")
        assert "memory budget of 64.0 MiB" in message and "lower rsm_size" in message
        assert pipe.keys == {} and pipe.light_views.rsm.passes == []
        requests = {r.name: r.bytes for r in memory_requests(big)}
        assert requests["rsm_size"] > 64 << 20 > requests["grid_size"]
        image = SMALL.with_changes(width=4096, height=4096)
        with pytest.raises(ValueError, match=r"^4096x4096 pixels .* lower width$"):
            pipe.run(image)
        pipe.run(SMALL)                                  # what fits still runs


def test_framebuffers_stay_below_the_drivers_largest(gl_context):
    with Pipeline(SMALL, ctx=gl_context) as pipe:
        pipe.limits = replace(pipe.limits, max_framebuffer_size=64)
        with pytest.raises(ValueError, match="rsm_size 64 must be below .* at most 63"):
            pipe.run(SMALL.with_changes(rsm_size=64))
        pipe.run(SMALL.with_changes(rsm_size=63))
    assert pipe.limits.max_framebuffer_size == 64
    with Pipeline(SMALL, ctx=gl_context) as pipe:          # the real driver's limits
        largest = pipe.limits.max_framebuffer_size
        assert largest <= pipe.limits.max_texture_size
        with pytest.raises(ValueError, match=f"width {largest} must be below"):
            pipe.check_limits(replace_unchecked(SMALL, width=largest))
        pipe.check_limits(replace_unchecked(SMALL, width=largest - 1))


def replace_unchecked(settings: Settings, **changes) -> Settings:
    """Settings with values beyond the schema's range (as an older file could hold)."""
    copy = settings.with_changes()
    for name, value in changes.items():
        object.__setattr__(copy, name, value)
    return copy


def test_an_audit_larger_than_a_storage_block_is_skipped_with_a_warning(gl_context):
    """The per-cell records do not fit: the full audit falls back to the flux per step
    (which needs no records), with a warning."""
    with Pipeline(SMALL, ctx=gl_context) as pipe:
        pipe.limits = replace(pipe.limits, max_storage_block_bytes=1000)
        result = pipe.run(SMALL)
        assert result.audit.mode == "flux" and not result.audit.terms_measured
        assert np.isfinite(result.audit.per_step).all()
        assert result.cascades[0].cell_records is None
        assert any("GL_MAX_SHADER_STORAGE_BLOCK_SIZE" in w for w in result.warnings)
        assert np.isfinite(result.audit.accumulated).all()
        assert pipe.run(SMALL).stages_run == ()          # nothing better can be had
