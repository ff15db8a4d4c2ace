"""The overlay colour bar computes its colours once per map, not each frame, and they are
the map's colours at the bar's step edges (top = the high end)."""

from __future__ import annotations

import numpy as np

from explorer.ui import textures, widgets


def test_the_bar_colours_are_computed_once_per_map_and_match_the_map(monkeypatch):
    calls = []

    def counted(values, scale):
        calls.append(float(values))
        return textures.diverging(values, scale)

    monkeypatch.setattr(widgets, "diverging", counted)
    widgets._scale_bar_colours.cache_clear()
    first = widgets._scale_bar_colours(True)
    again = widgets._scale_bar_colours(True)
    assert again is first and len(calls) == widgets._SCALE_BAR_STEPS + 1
    assert np.allclose(first[0], textures.diverging(np.array(1.0), 1.0))
    assert np.allclose(first[-1], textures.diverging(np.array(-1.0), 1.0))
    heat = widgets._scale_bar_colours(False)
    assert np.allclose(heat[0], textures.heat(1.0)) and np.allclose(heat[-1], textures.heat(0.0))
    widgets._scale_bar_colours.cache_clear()
