"""A settings file whose every field is valid but whose combination cannot run (more
memory than the budget, cascades on too small a grid) is one line at start, set aside,
and the defaults are used: never a failed first frame with a traceback."""

from __future__ import annotations

import json

import pytest

from explorer.ui import persist
from explorer.ui.state import AppState


@pytest.mark.parametrize("side, changes, words", [
    ("settings", dict(grid_size=256, cascades=4, sh_order=2), "more than the memory budget"),
    ("compare_settings", dict(grid_size=4, cascades=3), "cascades need grid_size"),
])
def test_a_valid_combination_over_the_budget_falls_back_to_the_defaults(tmp_path, side,
                                                                         changes, words):
    path = tmp_path / "settings.json"
    persist.save_state(AppState(), path)
    data = json.loads(path.read_text())
    data[side].update(changes)
    data["view_mode"] = "split"
    path.write_text(json.dumps(data))
    state = AppState()
    message = persist.load_state(state, path)
    assert message is not None and "\n" not in message
    assert message.startswith(f"cannot use {path}: configuration "
                              f"{'A' if side == 'settings' else 'B'}: ")
    assert words in message and "using the default settings" in message
    assert persist.state_to_dict(state) == persist.state_to_dict(AppState())
    assert not path.exists() and len(list(tmp_path.glob("settings.json.bad-*"))) == 1


def test_a_combination_that_fits_is_kept(tmp_path):
    path = tmp_path / "settings.json"
    state = AppState()
    state.settings = state.settings.with_changes(grid_size=64, cascades=2)
    persist.save_state(state, path)
    loaded = AppState()
    assert persist.load_state(loaded, path) is None
    assert loaded.settings.cascades == 2 and loaded.settings.grid_size == 64
