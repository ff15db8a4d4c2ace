"""The split of an LPV frame's light by source and receiver surface
(explorer/truth/self_light.py): every VPL on a surface, the sets add up to the frame, the
reference's self terms are zero and the LPV's are not (the self-illumination that makes
blue too bright, docs/ERRORS.md)."""

from __future__ import annotations

import numpy as np

from explorer.lpv.settings import Settings
from explorer.truth.gbuffer import scene_for
from explorer.truth.self_light import format_report, measure, vpl_surfaces


def test_every_corner_of_the_cornell_box_lies_on_its_own_surface():
    scene = scene_for(Settings(scene="cornell"))
    from explorer.scene.parts import surface_names

    triangles = np.asarray(scene.positions, np.float64).reshape(-1, 3, 3)
    centres = triangles.mean(axis=1)
    normals = np.asarray(scene.normals, np.float64).reshape(-1, 3, 3)[:, 0]
    found = vpl_surfaces(scene, centres, normals)
    # the blocks' bottoms lie in the floor's plane, where no light reaches: left out
    seen = ~((np.abs(centres[:, 1] + 1.0) < 1e-6) & (normals[:, 1] < -0.99))
    assert seen.sum() == len(seen) - 4
    assert np.array_equal(found[seen], surface_names(scene).triangle_names[seen])


def test_self_light_of_a_small_cornell_box(gl_context):
    settings = Settings(scene="cornell", width=32, height=32, rsm_size=16, grid_size=8,
                        iterations=4)
    result = measure(settings, gl_context)
    assert np.allclose(result.closure, 1.0, atol=0.05)      # the clamp, coarse 8³ cells
    index = np.arange(len(result.names))
    # no surface lights itself (a block: float rounding at its edges, 1e-15)
    assert np.all(result.reference[index, index] < 1e-9 * result.reference.sum())
    assert result.lpv[index, index].sum() > 0.0               # the LPV's do
    shares = result.shares()
    white = [result.names.index(n) for n in ("floor", "back wall", "tall block")]
    own = result.lpv[white, white]                            # white light on white albedo
    assert np.allclose(own[:, 0], own[:, 2]) and np.allclose(own[:, 1], own[:, 2])
    assert shares["lpv self"][2] > 0 and "| floor |" in format_report(result)


def test_the_net_flux_split_adds_up_to_the_frame(gl_context):
    """With the net-flux gather each surface's own exitance counts as its light onto itself
    once, so the sources still add up to the frame (up to the gather's clamp)."""
    settings = Settings(scene="cornell", width=32, height=32, rsm_size=16, grid_size=8,
                        iterations=4, gather_net_flux=True)
    result = measure(settings, gl_context)
    assert np.allclose(result.closure, 1.0, atol=0.1)
    index = np.arange(len(result.names))
    assert np.all(result.lpv[index, index].sum(axis=1) > 0)   # the exitance is the self term
