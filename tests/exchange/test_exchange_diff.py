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


# --- tolerances: each mode on a crafted pair -------------------------------------------

def _port_pair() -> tuple[np.ndarray, np.ndarray]:
    """A grid as a float64 port would give it against ours: every value off by 2e-9
    absolute, a near-empty cell (1e-6, just above the relative error's floor) where that is
    0.2 % relative, one bright cell off by 2e-7 more."""
    ours = np.zeros((3, 3, 4, 5, 4))
    ours[..., 0] = 1.0
    ours[:, 0, 1, 2, :] = 1e-6
    theirs = ours + 2e-9
    theirs[1, 1, 2, 3, 0] += 2e-7
    return theirs, ours


def test_atol_passes_the_near_empty_cells_that_fail_the_relative_tolerance():
    from explorer.exchange.tolerances import Tolerances

    theirs, ours = _port_pair()
    old = stage_diff("grid_3", theirs, ours, Tolerances(max_relative=1e-3))
    assert old.passed is False and old.max_relative_at == [0, 1, 2]     # 2e-9 / 1e-6
    assert old.failures == [f"largest relative error {old.max_relative:.3g} > 0.001"]
    loose = stage_diff("grid_3", theirs, ours, Tolerances(atol=1e-6))
    assert loose.passed is True and loose.failing == 0 and loose.worst == []
    tight = stage_diff("grid_3", theirs, ours, Tolerances(atol=1e-7))
    assert tight.passed is False and tight.failing == 1
    assert tight.failures == ["1 cell outside atol + rtol·|ours|"]
    first, = tight.worst
    assert first.at == [1, 2, 3] and first.component == "[g, k=0]"
    assert first.theirs == pytest.approx(1 + 2.02e-7, abs=1e-15) and first.ours == 1.0
    assert first.allowed == pytest.approx(1e-7)
    assert len(first.theirs_element) == len(first.ours_element) == 12
    assert first.ours_element[4] == 1.0                 # colour g, k = 0: index 1·4 + 0


def test_rtol_scales_with_ours_and_allows_nothing_where_ours_is_zero():
    from explorer.exchange.tolerances import Tolerances

    theirs, ours = _port_pair()
    # rtol alone: |Δ| ≤ rtol·|ours|, so every zero coefficient (k = 1..3) off by 2e-9
    # fails, and the near-empty cell's 2e-9 is more than 1e-3 of its 1e-6
    d = stage_diff("grid_3", theirs, ours, Tolerances(rtol=1e-3))
    assert d.failing == 60
    assert d.worst[0].allowed == 0.0 and d.worst[0].ours == 0.0
    both = stage_diff("grid_3", theirs, ours, Tolerances(atol=1e-8, rtol=1e-3))
    assert both.passed is True
    assert stage_diff("grid_3", theirs, ours, Tolerances(atol=1e-8, rtol=1e-7)).failing == 1


def test_the_per_value_test_is_numpys_isclose():
    from explorer.exchange.tolerances import Tolerances

    rng = np.random.default_rng(3)
    ours = rng.normal(size=(3, 4, 4, 4, 9))
    theirs = ours * (1 + rng.normal(scale=1e-4, size=ours.shape)) + rng.normal(
        scale=1e-6, size=ours.shape)
    for atol, rtol in ((1e-6, 3e-4), (2e-6, 2.5e-4), (0.0, 3.5e-4), (4e-4, 0.0)):
        d = stage_diff("accumulated", theirs, ours, Tolerances(atol=atol, rtol=rtol),
                       worst=3)
        close = np.isclose(theirs, ours, rtol=rtol, atol=atol)      # [colour, x, y, z, k]
        assert d.failing == int(np.count_nonzero(~close.all(axis=(0, 4)))), (atol, rtol)
        assert 0 < d.failing < 64
        excess = np.abs(theirs - ours) / (atol + rtol * np.abs(ours))
        worst_cell = np.unravel_index(np.argmax(excess.max(axis=(0, 4))), (4, 4, 4))
        assert d.worst[0].at == [int(i) for i in worst_cell]
        assert d.worst[0].error > d.worst[0].allowed
        assert [w.error / w.allowed for w in d.worst] == sorted(
            (w.error / w.allowed for w in d.worst), reverse=True)


def test_relative_l2_per_stage():
    from explorer.exchange.tolerances import Tolerances

    ours = np.ones((8, 8, 3))
    theirs = ours.copy()
    theirs[2, 5, 1] = 1.5                                # ‖Δ‖ 0.5 over ‖ours‖ √192
    l2 = 0.5 / np.sqrt(192)
    d = stage_diff("indirect", theirs, ours, Tolerances(rel_l2=0.05))
    assert d.relative_l2 == pytest.approx(l2) and d.passed is True
    d = stage_diff("indirect", theirs, ours, Tolerances(rel_l2=0.03))
    assert d.passed is False and d.failures == [f"rel. L2 {l2:.3g} > 0.03"]
    assert d.worst[0].at == [5, 2] and d.worst[0].component == "[g]"
    zero = stage_diff("indirect", theirs - ours, 0 * ours, Tolerances(rel_l2=1.0))
    assert zero.failures == ["rel. L2 infinite (ours all zero, theirs not)"]
    assert stage_diff("indirect", 0 * ours, 0 * ours, Tolerances(rel_l2=0.0)).passed is True


def test_the_table_says_which_stage_fails_and_lists_its_worst_cells():
    from explorer.exchange.diff import format_worst
    from explorer.exchange.tolerances import Tolerances

    theirs, ours = _port_pair()
    pixels = np.ones((2, 3, 3))
    diffs, _, _ = diff_arrays({"grid_3": theirs, "direct": pixels, "grid_0": np.zeros(3)},
                              {"grid_3": ours, "direct": pixels, "grid_0": np.zeros(4)},
                              Tolerances(atol=1e-7), worst=2)
    table = format_table(diffs).splitlines()
    assert table[0].endswith("| rel. L2 | outside | verdict |")
    assert table[2].endswith("| 1 | FAIL: 1 cell outside atol + rtol·|ours| |")
    assert table[3].endswith("| 0 | pass |")
    assert table[4].endswith("| – | FAIL: not compared: shape (3,), ours (4,) |")
    worst = format_worst(diffs).splitlines()
    assert worst[0] == "worst cells of grid_3 (|Δ| against atol + rtol·|ours|):"
    assert worst[1] == ("  cell (1, 2, 3) [g, k=0]: theirs 1.0000002, ours 1 (|Δ| 2.02e-07, "
                        "allowed 1e-07)")
    assert worst[2].startswith("    theirs r [1, 2e-09, 2e-09, 2e-09] g [1.0000002, ")
    assert worst[3].startswith("    ours   r [1, 0, 0, 0] g [1, 0, 0, 0] b ")
    assert len(worst) == 4                              # the passing stage lists nothing
