"""Render targets across a change of size (explorer/gl/targets.py): the window alternates
between a drag's reduced size, its previews' and the full one, and a size left is kept so
that coming back makes nothing (making full-size float targets cost a software renderer
tens of milliseconds); at most ``KEPT_SIZES`` others are kept, and ``release`` frees all."""

from __future__ import annotations

import moderngl
import numpy as np

from explorer.gl.targets import KEPT_SIZES, RenderTargets


def _released(texture: moderngl.Texture) -> bool:
    return isinstance(texture.mglo, moderngl.InvalidObject)


def test_a_size_left_is_kept_and_taken_back_with_its_texels(ctx):
    targets = RenderTargets(ctx, ("f4", "f4"), depth=True, enable=moderngl.DEPTH_TEST)
    try:
        targets.allocate((32, 16))
        full = list(targets.textures)
        with targets.drawing():
            ctx.clear(0.25, 0.5, 0.75, 1.0)
        targets.allocate((8, 4))                 # a drag's reduced size
        small = list(targets.textures)
        assert targets.size == (8, 4) and not set(map(id, small)) & set(map(id, full))
        assert not any(_released(texture) for texture in full)
        targets.allocate((32, 16))           # released: the full size again
        assert targets.textures == full and targets.size == (32, 16)
        texels = np.frombuffer(targets.textures[0].read(), "f4").reshape(16, 32, 4)
        assert np.allclose(texels, (0.25, 0.5, 0.75, 1.0))      # as it was left
        with targets.drawing(clear=True):
            pass
        assert not np.frombuffer(targets.textures[0].read(), "f4").any()
    finally:
        targets.release()


def test_only_the_last_sizes_are_kept_and_release_frees_them_all(ctx):
    targets = RenderTargets(ctx, ("f1",))
    sets = []
    for edge in range(4, 4 + 4 * (KEPT_SIZES + 2), 4):
        targets.allocate((edge, edge))
        sets.append(list(targets.textures))
    released = [all(_released(texture) for texture in textures) for textures in sets]
    kept = KEPT_SIZES + 1                        # the current set and KEPT_SIZES others
    assert released == [True] * (len(sets) - kept) + [False] * kept
    targets.release()
    assert all(_released(texture) for textures in sets for texture in textures)
    assert targets.size == (0, 0) and targets.textures == []
