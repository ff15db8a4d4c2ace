"""A frame's CPU-side products that only a reader needs are computed when read
(explorer/lpv/deferred.py): the finite checks of the read-back images, the gathered flux
and the RSM's flux sums; reading them gives the numbers an eager frame gave. And a
camera frame makes its scene once."""

import sys

import numpy as np
import pytest

from explorer.lpv.audit import rgb_sums
from explorer.lpv.deferred import Deferred, DeferredField
from explorer.lpv.passes.display import AutoExposure, display_scale, exposed_image
from explorer.lpv.passes.gather import GatherImages
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.scene.model import Scene

TINY = Settings(scene="cornell", grid_size=8, iterations=8, rsm_size=32, width=48,
                height=32)


class Calls:
    """Counts the calls of a module function while it stays patched."""

    def __init__(self, monkeypatch, module: str, name: str) -> None:
        self.count = 0
        original = getattr(sys.modules[module], name)

        def counted(*args, **kwargs):
            self.count += 1
            return original(*args, **kwargs)

        monkeypatch.setattr(sys.modules[module], name, counted)


@pytest.fixture
def pipeline(gl_context, ctx):   # ctx: checks for GL errors
    pipe = Pipeline(TINY, ctx=gl_context)
    pipe.run(TINY)
    pipe.timer.queued = True
    yield pipe
    pipe.release()


def test_a_frame_checks_and_sums_its_images_only_when_read(pipeline, monkeypatch):
    checks = Calls(monkeypatch, "explorer.lpv.guards", "arrays_warnings")
    gathered = Calls(monkeypatch, "explorer.lpv.passes.gather", "rgb_sums")
    rsm_sums = Calls(monkeypatch, "explorer.lpv.light_views", "flux_per_light")
    pipeline.invalidate("rsm")
    job = pipeline.start(TINY)
    job.advance(None)
    result = job.result
    assert (checks.count, gathered.count, rsm_sums.count) == (0, 0, 0)
    # read: each computed once, as the eager frame computed it
    state = pipeline.state
    assert result.warnings == []
    assert checks.count == 5      # rsm, downsample, propagate, gbuffer, gather
    assert np.array_equal(result.audit.gathered, rgb_sums(state.gather.received))
    assert np.array_equal(result.audit.rsm, rgb_sums(result.rsm_flux))
    assert result.audit.rsm_per_light.shape == (1, 3)
    assert (gathered.count, rsm_sums.count) == (1, 1)
    result.warnings, result.audit.gathered, result.audit.rsm_per_light  # noqa: B018
    assert (checks.count, gathered.count, rsm_sums.count) == (5, 1, 1)


def test_a_frame_with_a_nan_warns_when_its_warnings_are_read(pipeline, monkeypatch):
    """The deferred check still finds what the eager one found (here a NaN put into the
    gathered image before anybody read the frame's warnings)."""
    pipeline.invalidate("gbuffer")
    job = pipeline.start(TINY)
    job.advance(None)
    job.result.direct[3, 4, 1] = np.nan        # a view of the gathered image
    warnings = job.result.warnings
    assert len(warnings) == 1 and warnings[0].startswith("the gather pass produced 1 NaN")


def test_debug_nan_still_stops_the_pass(pipeline, monkeypatch):
    checks = Calls(monkeypatch, "explorer.lpv.guards", "arrays_warnings")
    settings = TINY.with_changes(debug_nan=True)
    pipeline.invalidate("rsm")
    pipeline.run(settings)
    assert checks.count == 5          # checked in the passes, not deferred


def test_a_moved_camera_makes_its_scene_once(pipeline, monkeypatch):
    overrides = []
    original = Scene.with_overrides

    def counted(self, *args, **kwargs):
        overrides.append(1)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(Scene, "with_overrides", counted)
    camera = pipeline.scene_state.scene.camera
    moved = TINY.with_changes(camera=((camera.eye[0] + 0.05, *camera.eye[1:]),
                                      camera.target))
    pipeline.run(moved)
    assert len(overrides) == 1        # the grid and G-buffer stages ask for the same scene


def test_deferred_values_are_computed_once_and_defaults_are_per_instance():
    from dataclasses import dataclass, replace

    runs = []

    @dataclass
    class Holder:
        value: list = DeferredField(list)  # type: ignore[assignment]

    a = Holder(Deferred(lambda: runs.append(1) or [1, 2]))
    assert runs == [] and DeferredField.pending(Holder.__dict__["value"], a) is not None
    assert a.value == [1, 2] and a.value == [1, 2] and runs == [1]
    b, c = Holder(), Holder()
    b.value.append(3)
    assert c.value == [] and replace(a).value == [1, 2] and a == replace(a)


def test_the_auto_exposure_meters_the_bits_of_the_exposed_image():
    """AutoExposure adds direct and indirect as whole pixels and lets the luminance take
    the rgb: the same scale, bit for bit, as metering ``exposed_image`` (random images
    with NaN, infinities, zeros and wide ranges)."""
    rng = np.random.default_rng(3)
    for trial in range(60):
        h, w = (int(v) for v in rng.integers(1, 40, 2))
        scale = 10.0 ** rng.uniform(-25, 25)
        direct = (rng.standard_normal((h, w, 4)) * scale).astype(np.float32)
        indirect = (rng.exponential(size=(h, w, 4)) * scale).astype(np.float32)
        if trial % 3 == 0:
            direct.flat[rng.integers(0, direct.size, 4)] = [np.nan, np.inf, -np.inf, -0.0]
        position = rng.uniform(size=(h, w, 4)).astype(np.float32)
        images = GatherImages(direct, indirect, indirect)
        for indirect_only in (False, True):
            with np.errstate(all="ignore"):
                want = display_scale(exposed_image(direct[..., :3], indirect[..., :3], 1.0,
                                                   indirect_only), position[..., 3] > 0.5,
                                     True)
                got = AutoExposure().scale(images, None, indirect_only, position)
            assert np.float64(got).tobytes() == np.float64(want).tobytes(), trial


def test_a_moved_camera_sets_the_gathers_kept_uniforms(pipeline, monkeypatch):
    """Nothing the gather's uniforms are made of changes when the camera moves: the
    gather hands set_uniforms the dict it made, which uploads nothing and stamps nothing."""
    from explorer.gl.call_counter import GlCallCounter

    made = Calls(monkeypatch, "explorer.lpv.passes.gather", "cascade_uniforms")
    stamped = Calls(monkeypatch, "explorer.gl.program", "_value_key")
    camera = pipeline.scene_state.scene.camera
    frames = [TINY.with_changes(camera=((camera.eye[0] + 0.05 * k, *camera.eye[1:]),
                                        camera.target)) for k in (1, 2)]
    pipeline.run(frames[0])
    first, stamps = made.count, stamped.count
    with GlCallCounter() as counter:
        result = pipeline.run(frames[1])
    assert result.stages_run == ("gbuffer", "gather", "display")
    assert made.count == first          # the dict was not made again
    # stamped: the G-buffer's view and projection matrices, nothing of the gather's
    assert stamped.count - stamps == 2
    # uploaded: those two and the display's scale; the scene draw's own two hold the
    # values they held (SceneBuffers.draw compares them as set_uniform does)
    assert counter.tally.calls["uniform uploads"] == 3


def test_a_light_frame_again_sets_the_passes_kept_uniforms(pipeline, monkeypatch):
    """The injection, the propagation and the gather hand set_uniforms the dicts they
    kept for the same grid and switches, and the G-buffer (its stage runs again too) the
    camera's for the same scene: a frame re-run from the injection stamps no uniform and
    uploads only what changes per step (the audit's slot)."""
    from explorer.gl.call_counter import GlCallCounter

    pipeline.invalidate("inject")
    pipeline.run(TINY)
    stamped = Calls(monkeypatch, "explorer.gl.program", "_value_key")
    pipeline.invalidate("inject")
    with GlCallCounter() as counter:
        result = pipeline.run(TINY)
    assert result.stages_run[:1] == ("inject",) and "gather" in result.stages_run
    assert stamped.count == 0
    # the full audit's slot, once per step, and the slots of the flux reductions
    assert counter.tally.calls["uniform uploads"] <= TINY.iterations + 4


@pytest.mark.parametrize("change", [{}, {"indirect_only": True, "exposure": 1.7},
                                    {"fog": True}])
def test_a_frames_size_and_one_pixel_need_not_its_whole_final_image(pipeline, change):
    """The window asks a new frame its size and the hovered pixel's colour: neither
    computes the whole exposed image, and the pixel has its bits."""
    settings = TINY.with_changes(**change)
    result = pipeline.run(settings)
    assert (result.fog is not None) == bool(change.get("fog"))
    assert result.image_size == (TINY.height, TINY.width)
    pixels = [(0, 0), (TINY.height - 1, TINY.width - 1), (11, 17)]
    alone = [result.final_pixel(y, x) for y, x in pixels]
    assert result._final_image is None           # nothing computed the whole image
    for (y, x), value in zip(pixels, alone):
        assert value.dtype == result.final_image.dtype
        assert np.array_equal(value, result.final_image[y, x])
        assert np.array_equal(result.final_pixel(y, x), value)     # from the whole one now
