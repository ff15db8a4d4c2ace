"""The reference radiance at one pixel (the window's picked pixel): a 1×1 tile of the
frame's own image with the frame's own VPLs equals that pixel of the full reference
image, with and without shadow rays."""

from __future__ import annotations

import numpy as np
import pytest
from lpv_cases import run_frame

from explorer.lpv.settings import Settings
from explorer.truth.progressive import pixel_reference

SMALL = Settings(width=40, height=32, grid_size=12, iterations=4, rsm_size=16)


@pytest.fixture(scope="module")
def frame(gl_context):
    return run_frame(gl_context, SMALL)


@pytest.mark.parametrize("visibility", [False, True], ids=["unoccluded", "visible"])
def test_one_pixel_equals_the_full_reference_images_pixel(ctx, frame, visibility):
    from explorer.truth.render import reference_for_frame

    full, gbuffer = reference_for_frame(frame, visibility, ctx=ctx)
    valid = np.asarray(gbuffer.valid, bool)
    lit = np.argwhere(valid & (full.max(axis=2) > 0))
    rng = np.random.default_rng(3)
    picks = [tuple(lit[i]) for i in rng.choice(len(lit), 6, replace=False)]
    picks.append(tuple(np.unravel_index(np.argmax(full.max(axis=2)), valid.shape)))
    for y, x in picks:
        got = pixel_reference(ctx, frame, int(x), int(y), visibility)
        assert got.shape == (3,)
        np.testing.assert_allclose(got, full[y, x], rtol=1e-5, atol=1e-7 * full.max())
    background = np.argwhere(~valid)
    if len(background):
        y, x = background[0]
        assert not np.any(pixel_reference(ctx, frame, int(x), int(y), visibility))


def test_a_pixel_outside_the_frame_is_refused(ctx, frame):
    with pytest.raises(ValueError, match="outside the 40x32 frame"):
        pixel_reference(ctx, frame, 40, 0, False)


def test_the_windows_service_computes_caches_and_describes_a_pixel(ctx, frame):
    from explorer.ui.overlays.describe import pixel_rows
    from explorer.ui.overlays.picking import pick_pixel
    from explorer.ui.overlays.pixel_reference import PixelReferences

    valid = np.argwhere(frame.gbuffer_position[..., 3] > 0.5)
    y, x = (int(v) for v in valid[len(valid) // 2])
    service = PixelReferences()
    service.request(frame, (x, y))
    service.request(frame, (x, y))                    # queued once
    assert len(service.pending) == 2 and service.computing(frame, (x, y))
    calls = 0
    while service.running and calls < 10:
        service.advance(ctx, 1.0)
        calls += 1
    # a setup only ever starts a call: the scene and its BVH, then each mode's gather
    assert calls == 3
    assert not service.pending and not service.computing(frame, (x, y))
    found = dict(service.values(frame, (x, y)))
    for mode, visibility in (("visible", True), ("unoccluded", False)):
        np.testing.assert_array_equal(found[mode], pixel_reference(ctx, frame, x, y,
                                                                   visibility))
    service.request(frame, (x, y))
    assert not service.pending                        # cached per (settings, pixel, mode)
    other = frame.settings.with_changes(iterations=2)
    assert service.value(type("F", (), {"settings": other})(), (x, y), "visible") is None
    with pytest.raises(ValueError, match="mode must be one of"):
        service.request(frame, (x, y), modes=("sometimes",))
    from dataclasses import replace

    pick = replace(pick_pixel(frame, x, y), references=service.values(frame, (x, y)))
    rows = dict(pixel_rows(pick))
    assert "reference (visible)" in rows and "indirect / reference (unoccluded)" in rows
    ratio = frame.indirect[y, x] / found["visible"]
    assert rows["indirect / reference (visible)"] == \
        "(" + ", ".join(f"{v:.3g}" for v in ratio) + ")"


def test_the_service_works_in_units_of_one_bvh_node_or_one_vpl_chunk(ctx, frame):
    """No call does much: with no time budget every advance does exactly one unit (the
    scene posed and its BVH started, one BVH node, a pixel's gather started or read back,
    one chunk of VPLs), in that order; the BVH has as many nodes as the one-shot build,
    each pixel as many chunks as its VPLs fill, and the values are the one-shot ones."""
    from explorer.truth.bvh import build_bvh
    from explorer.truth.gbuffer import scene_for, scene_triangles
    from explorer.truth.render import lit_vpls
    from explorer.ui.overlays.pixel_reference import PixelReferences

    valid = np.argwhere(frame.gbuffer_position[..., 3] > 0.5)
    y, x = (int(v) for v in valid[len(valid) // 3])
    chunk = 8
    service = PixelReferences(vpl_chunk=chunk)
    try:
        service.request(frame, (x, y))
        kinds, texts = [], set()
        for _ in range(10000):
            service.advance(ctx, 0.0)
            done = [kind for kind, count in service.units.items() if count]
            assert sum(service.units.values()) == 1, service.units
            kinds.append(done[0])
            texts.add((service.progress() or "").split("…")[0])
            if not service.running:
                break
        assert not service.running and service.problem is None
        nodes = len(build_bvh(scene_triangles(scene_for(frame.settings))).nodes)
        chunks = -(-lit_vpls(frame.vpls).count // chunk)
        per_pixel = ["pixels"] + ["VPL chunks"] * chunks + ["pixels"]
        assert kinds == ["scene"] + ["BVH nodes"] * nodes + per_pixel * 2   # both modes
        assert {"building BVH", "gathering the reference", ""} <= texts
        for mode, visibility in (("visible", True), ("unoccluded", False)):
            np.testing.assert_allclose(service.value(frame, (x, y), mode),
                                       pixel_reference(ctx, frame, x, y, visibility),
                                       rtol=1e-5, atol=1e-9)
        # the BVH is kept for the same geometry: another pixel starts with its gather
        service.request(frame, (x + 1, y), modes=("visible",))
        service.advance(ctx, 0.0)
        assert dict(service.units) == {"pixels": 1}
    finally:
        service.release()
