"""explorer/exchange/diff.py on hand-made arrays: where an error is reported (cell
(x, y, z), pixel (x, y) with y the row from the top, VPL i), the relative error's floor,
and the stages that cannot be compared (shapes, values that are not finite)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from explorer.exchange.diff import diff_arrays, format_table, stage_diff


def test_a_pixel_is_reported_as_x_then_y_from_the_top():
    ours = np.ones((4, 6, 3), np.float32)
    theirs = ours.copy()
    theirs[1, 5] = [1.0, 1.3, 1.0]                         # row 1, column 5
    d = stage_diff("indirect", theirs, ours)
    assert (d.element, d.elements, d.differing) == ("pixel", 24, 1)
    assert d.max_error_at == [5, 1] and d.max_relative_at == [5, 1]
    assert d.max_error == pytest.approx(0.3, rel=1e-6)
    assert d.max_relative == pytest.approx(0.3 / np.sqrt(3), rel=1e-6)


def test_a_cell_error_is_the_norm_over_colours_and_coefficients():
    ours = np.zeros((3, 4, 4, 4, 4))
    ours[..., 0] = 1.0
    theirs = ours.copy()
    theirs[0, 1, 2, 3, 1] = 3.0
    theirs[2, 1, 2, 3, 3] = 4.0
    d = stage_diff("grid_5", theirs, ours)
    assert d.element == "cell" and d.max_error_at == [1, 2, 3] and d.max_error == 5.0
    assert d.max_relative == pytest.approx(5.0 / np.sqrt(3))
    assert d.relative_l2 == pytest.approx(5.0 / np.sqrt(3 * 64))


def test_nearly_empty_cells_do_not_make_the_relative_error():
    ours = np.zeros((3, 2, 2, 2, 4))
    ours[:, 0, 0, 0, 0] = 1.0
    ours[:, 1, 1, 1, 0] = 1e-9                             # below the floor: not relative
    theirs = ours.copy()
    theirs[:, 1, 1, 1, 0] = 2e-9
    theirs[:, 0, 0, 0, 0] = 1.01
    d = stage_diff("accumulated", theirs, ours)
    assert d.max_relative_at == [0, 0, 0] and d.max_relative == pytest.approx(0.01)


def test_what_cannot_be_compared_says_why():
    ours = {"grid_0": np.zeros((3, 2, 2, 2, 4)), "vpl_flux": np.ones((5, 3)),
            "direct": np.zeros((2, 2, 3))}
    theirs = {"grid_0": np.zeros((3, 4, 4, 4, 4)), "vpl_flux": np.ones((5, 3)),
              "direct": np.zeros((2, 2, 3)), "extra": np.zeros(2)}
    theirs["vpl_flux"][3, 1] = np.nan
    diffs, only_theirs, only_ours = diff_arrays(theirs, ours)
    by_name = {d.stage: d for d in diffs}
    assert by_name["grid_0"].problem == "shape (3, 4, 4, 4, 4), ours (3, 2, 2, 2, 4)"
    assert by_name["vpl_flux"].problem == "theirs not finite at 1 VPL, the first at VPL (3)"
    assert by_name["direct"].max_error == 0 and by_name["direct"].problem is None
    assert only_theirs == ["extra"] and only_ours == []
    table = format_table(diffs)
    assert "| grid_0 | – | – | not compared: shape" in table
    assert "| direct | 4 pixels | 0 | 0 | – | – |" in table


def test_a_sidecar_names_its_scene_file_from_its_own_folder(tmp_path, monkeypatch):
    """A dump of a scene file is read back from any working folder: the sidecar names the
    scene relative to itself, and ``diff --settings`` resolves it there."""
    from explorer.exchange.sidecar import read_settings, scene_entry, scene_from_entry

    (tmp_path / "scenes").mkdir()
    scene = tmp_path / "scenes" / "room.toml"
    scene.write_text('builtin = "cornell"\n', encoding="utf-8")
    dumps = tmp_path / "dumps"
    dumps.mkdir()
    monkeypatch.chdir(tmp_path)
    assert scene_entry("scenes/room.toml", dumps) == "../scenes/room.toml"
    assert scene_entry("cornell", dumps) == "cornell"
    (dumps / "frame.json").write_text(
        '{"settings": {"scene": "../scenes/room.toml", "grid_size": 8}}', encoding="utf-8")
    monkeypatch.chdir(dumps.parent / "scenes")          # somewhere else entirely
    settings = read_settings(dumps / "frame.json")
    assert Path(settings.scene).resolve() == scene.resolve() and settings.grid_size == 8
    assert scene_from_entry("cornell", dumps) == "cornell"
    assert scene_from_entry("missing.toml", dumps) == "missing.toml"   # as written
