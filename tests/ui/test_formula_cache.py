"""The typeset formulas' textures stay bounded in a long session: least recently used
first out, a formula in use never re-typeset."""

from __future__ import annotations

import numpy as np

from explorer.ui import formulas


class FakeTextures:
    def __init__(self) -> None:
        self.live: dict[str, int] = {}
        self.uploads = 0

    def upload(self, key, pixels, version=None, nearest=True) -> int:
        self.uploads += 1
        self.live[key] = self.uploads
        return self.uploads

    def discard(self, key) -> None:
        self.live.pop(key, None)


def test_the_cache_keeps_the_most_recently_used_formulas(monkeypatch):
    monkeypatch.setattr(formulas, "MAX_CACHED_FORMULAS", 3)
    monkeypatch.setattr(formulas, "typeset", lambda latex, size, inline=False: (
        type("Rendered", (), {"baseline_y": 1})(), np.ones((2, 3, 4), np.uint8)))
    textures = FakeTextures()
    cache = formulas.FormulaCache(textures)
    cache._tried, cache._ready = True, True          # no MicroTeX needed with the stub
    for latex in ("a", "b", "c"):
        cache.get(latex)
    cache.get("a")                                    # a is now the most recent
    cache.get("d")                                    # b, the least recent, goes
    assert len(textures.live) == 3
    assert not any(":b:" in key for key in textures.live)
    uploads = textures.uploads
    cache.get("a")
    assert textures.uploads == uploads                # kept: not typeset again
