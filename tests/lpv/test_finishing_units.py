"""The frame that finishes a job (issue #32 item 3: "A done 43 ms" was the longest frame near
an input): the read-backs of the gather and the G-buffer are taken a texture a unit, the
auto exposure is metered and averaged in units of their own, and ``Job.advance``'s
``finishing_ms`` holds the last stage's units to less than the budget. Every split gives
the arrays, the scale and the picture of the one-shot run bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.gl.gpu_sync import DeferredRead, GpuWait
from explorer.lpv.job import FINAL_STAGE
from explorer.lpv.passes.display import (
    METER_BAND_BYTES,
    AutoExposure,
    display_scale,
    exposed_image,
    metered_in_bands,
)
from explorer.lpv.passes.fog import FogImages
from explorer.lpv.passes.gather import GatherImages
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.twin import tonemap
from explorer.lpv.work_units import read_back_later, read_back_units

SMALL = Settings(scene="cornell", grid_size=8, iterations=4, rsm_size=32, width=40, height=32)


def _units(work) -> tuple[list, object]:
    """Run a generator of units to its end: what each unit yielded and what it returned."""
    yielded = []
    while True:
        try:
            yielded.append(next(work))
        except StopIteration as done:
            return yielded, done.value


def test_a_read_back_taken_apart_gives_the_arrays_taken_together(gl_context, ctx):
    rng = np.random.default_rng(3)
    images = [rng.random((5, 7, 4), dtype=np.float32) for _ in range(3)]
    textures = [gl_context.texture((7, 5), 4, image[::-1].tobytes(), dtype="f4")
                for image in images]
    reads = [DeferredRead(gl_context) for _ in textures]
    try:
        together, arrays = _units(read_back_later(reads, textures))
        apart, arrays_apart = _units(read_back_later(reads, textures, apart=True))
        assert len(together) + 1 == read_back_units(3)
        assert len(apart) + 1 == read_back_units(3, apart=True) == 4
        assert isinstance(apart[0], GpuWait) and apart[1:] == [None, None]
        for image, one, other in zip(images, arrays, arrays_apart):
            assert np.array_equal(one, image) and np.array_equal(other, image)
    finally:
        for read in reads:
            read.release()
        for texture in textures:
            texture.release()


@pytest.mark.parametrize("indirect_only", [False, True])
def test_the_auto_exposure_in_two_units_is_the_one_shot_scale(indirect_only):
    rng = np.random.default_rng(5)
    shape = (24, 36, 4)
    gather = GatherImages(*(rng.random(shape, dtype=np.float32) for _ in range(3)))
    position = rng.random(shape, dtype=np.float32)
    yielded, scale = _units(AutoExposure().measure(gather, None, indirect_only, position))
    assert yielded == [None]                       # metered, then averaged
    unexposed = gather.indirect if indirect_only else gather.direct + gather.indirect
    once = display_scale(unexposed, position[..., 3] > 0.5, True)
    assert scale == once == tonemap.auto_exposure_scale(unexposed, position[..., 3] > 0.5)
    exposure = AutoExposure()
    assert exposure.scale(gather, None, indirect_only, position) == once
    # measured already: the same scale in one unit
    assert _units(exposure.measure(gather, None, indirect_only, position)) == ([], once)


@pytest.mark.parametrize("fogged", [False, True])
@pytest.mark.parametrize("indirect_only", [False, True])
def test_the_metering_in_bands_gives_the_whole_frames_values_bit_for_bit(fogged, indirect_only):
    rng = np.random.default_rng(11)
    shape = (41, 960, 4)                 # 960 wide: bands of 17 rows, the last one short
    assert 1 < shape[0] // (METER_BAND_BYTES // (shape[1] * 32)) < shape[0]
    gather = GatherImages(*(rng.random(shape, dtype=np.float32) for _ in range(3)))
    gather.direct[3, 5, 1] = np.nan              # a non-finite pixel counts as 0
    mask = rng.random(shape[:2]) > 0.3
    fog = FogImages(rng.random(shape[:2], dtype=np.float32),
                    rng.random(shape[:2] + (3,), dtype=np.float32),
                    rng.random(shape[:2] + (3,), dtype=np.float32)) if fogged else None
    if fog is None:
        whole = gather.indirect if indirect_only else gather.direct + gather.indirect
    else:
        whole = exposed_image(gather.direct[..., :3], gather.indirect[..., :3], 1.0,
                              indirect_only, fog)
    banded = metered_in_bands(gather, fog, indirect_only, mask)
    assert banded.dtype == np.float64
    assert np.array_equal(banded, tonemap.metered_luminance(whole, mask))


def test_the_last_stage_keeps_to_the_finishing_budget_and_ends_on_the_same_frame(gl_context,
                                                                                 ctx):
    with Pipeline(SMALL, ctx=gl_context) as pipe:
        once = pipe.run(SMALL)
        picture = np.frombuffer(pipe.final_texture.read(), np.uint8).copy()
        toggled = SMALL.with_changes(iterations=6)
        pipe.run(toggled)               # every unit measured once
        job = pipe.start(SMALL)
        calls = []
        while not job.done:
            before = job.progress
            after = job.advance(1e9, finishing_ms=0.0)
            calls.append((before.stage, after.stage, after.done))
        # a budget without end runs up to the last stage, whose units then take a call
        # each (none of them fits a finishing budget of nothing)
        assert calls[0][1] == FINAL_STAGE
        assert len(calls) == 1 + pipe.stage_units(FINAL_STAGE, job)
        assert [stage for stage, _, _ in calls[1:]] == [FINAL_STAGE] * (len(calls) - 1)
        assert np.array_equal(job.result.final_image, once.final_image)
        assert np.array_equal(np.frombuffer(pipe.final_texture.read(), np.uint8), picture)
        # without a finishing budget the same budget finishes the job in one call
        job = pipe.start(toggled)
        assert job.advance(1e9).finished


@pytest.mark.parametrize("albedo", [False, True])
def test_a_large_vpl_set_taken_in_units_gives_the_arrays_taken_at_once(gl_context, ctx,
                                                                       albedo):
    from explorer.lpv.vpl import TAKEN_APART_TEXELS, VplArrays, VplTextures

    rng = np.random.default_rng(7)
    count = TAKEN_APART_TEXELS + 1000
    arrays = VplArrays(rng.random((count, 3), dtype=np.float32),
                       rng.random((count, 3), dtype=np.float32),
                       rng.random((count, 3), dtype=np.float32),
                       rng.random(count, dtype=np.float32), 1e-3,
                       albedo=rng.random((count, 3), dtype=np.float32) if albedo else None)
    textures = VplTextures.from_arrays(gl_context, arrays)
    reads = [DeferredRead(gl_context) for _ in textures.all_textures]
    try:
        textures.read_later(reads)
        once = textures.arrays_taken(reads)
        textures.read_later(reads)
        yielded, apart = _units(textures.arrays_taken_units(reads))
        assert len(yielded) == 5 + albedo     # each compress and copy a unit (6 or 7 units)
        for name in ("positions", "normals", "flux", "depth") + ("albedo",) * albedo:
            assert np.array_equal(getattr(apart, name), getattr(once, name)), name
            assert np.array_equal(getattr(apart, name), getattr(arrays, name)), name
        small = VplTextures.from_arrays(gl_context, VplArrays(
            arrays.positions[:10], arrays.normals[:10], arrays.flux[:10], arrays.depth[:10],
            1e-3))
        small.read_later(reads)
        assert _units(small.arrays_taken_units(reads))[0] == []     # a small set: one unit
        small.release()
    finally:
        for read in reads:
            read.release()
        textures.release()
