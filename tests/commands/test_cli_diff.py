"""``lpv-explorer diff`` with the tolerances engines use, on a crafted pair of dumps
(``--ours``, so nothing is rendered): ``--atol``/``--rtol`` as numpy's isclose, ``--rel-l2``
per stage, the older ``--tolerance`` unchanged, the per-stage verdict and the worst cells
with their values on both sides, in the table and in the JSON."""

from __future__ import annotations

import json

import numpy as np
import pytest

from explorer.cli import main


@pytest.fixture
def pair(tmp_path):
    """Ours (float32, as a dump) and theirs (a float64 port): grid_2 off by 1e-9 in every
    value, a near-empty cell (3e-6) where that is a relative 3e-4, one cell off by 4e-6;
    direct equal to the last bit."""
    grid = np.zeros((3, 7, 6, 5, 4), np.float32)
    grid[..., 0] = 0.5
    grid[:, 6, 0, 1, :] = 3e-6
    direct = np.linspace(0, 1, 4 * 5 * 3, dtype=np.float32).reshape(4, 5, 3)
    theirs_grid = grid.astype(np.float64) + 1e-9
    theirs_grid[2, 3, 4, 2, 1] += 4e-6
    np.savez(tmp_path / "ours.npz", grid_2=grid, direct=direct)
    np.savez(tmp_path / "theirs.npz", grid_2=theirs_grid, direct=direct.astype(np.float64))
    return str(tmp_path / "theirs.npz"), str(tmp_path / "ours.npz")


def diff(capsys, pair, *argv: str) -> tuple[int, str]:
    theirs, ours = pair
    capsys.readouterr()
    code = main(["diff", theirs, "--ours", ours, *argv])
    return code, capsys.readouterr().out


def test_atol_and_rtol_hold_every_value_as_isclose(capsys, pair):
    code, out = diff(capsys, pair, "--atol", "1e-5")
    assert code == 0 and "2 of 2 stages pass" in out
    code, out = diff(capsys, pair, "--atol", "1e-6", "--rtol", "1e-6")
    assert code == 1
    line, = [row for row in out.splitlines() if row.startswith("| grid_2 |")]
    assert line.endswith("| 1 | FAIL: 1 cell outside atol + rtol·|ours| |")
    assert "1 of 2 stages pass; failing: grid_2" in out
    assert "worst cells of grid_2 (|Δ| against atol + rtol·|ours|):" in out
    assert "  cell (3, 4, 2) [b, k=1]: theirs 4.001e-06, ours 0 (|Δ| 4e-06, allowed 1e-06)" \
        in out
    # rtol alone allows nothing where ours is 0: every cell's zero coefficients fail
    code, out = diff(capsys, pair, "--rtol", "0.5", "--json")
    report = json.loads(out)
    assert code == 1 and report["rtol"] == 0.5 and report["atol"] is None
    grid = report["stages"][0]
    assert grid["failing"] == 7 * 6 * 5 - 1 and grid["passed"] is False
    assert report["failed"] == ["grid_2"] and report["within_tolerance"] is False


def test_relative_l2_per_stage(capsys, pair):
    code, out = diff(capsys, pair, "--rel-l2", "1e-3", "--json")
    report = json.loads(out)
    assert code == 0 and [s["passed"] for s in report["stages"]] == [True, True]
    l2 = report["stages"][0]["relative_l2"]
    values = 3 * 7 * 6 * 5 * 4                       # ‖Δ‖: 1e-9 everywhere, 4.001e-6 once
    delta = np.sqrt((values - 1) * 1e-18 + 4.001e-6 ** 2)
    norm = np.sqrt((3 * 7 * 6 * 5 - 3) * 0.25 + 3 * 4 * 9e-12)   # 0.5s but the empty cell
    assert l2 == pytest.approx(delta / norm, rel=1e-6)
    code, out = diff(capsys, pair, "--rel-l2", "1e-7")
    assert code == 1 and f"FAIL: rel. L2 {l2:.3g} > 1e-07" in out


def test_the_older_tolerance_is_unchanged_and_fails_the_near_empty_cell(capsys, pair):
    code, out = diff(capsys, pair, "--tolerance", "1e-4", "--json")
    report = json.loads(out)
    grid = report["stages"][0]
    assert code == 1 and grid["max_relative_at"] == [6, 0, 1]     # 1e-9 / 3e-6
    assert grid["failures"] == [f"largest relative error {grid['max_relative']:.3g} > 0.0001"]
    assert report["tolerance"] == 1e-4
    # what a port wants instead: the near-empty cell passes an absolute floor
    assert diff(capsys, pair, "--atol", "1e-8", "--rtol", "1e-4")[0] == 1     # the 4e-6 cell
    assert diff(capsys, pair, "--atol", "1e-5", "--rtol", "1e-4")[0] == 0


def test_the_json_lists_the_worst_cells_with_both_sides(capsys, pair):
    code, out = diff(capsys, pair, "--atol", "1e-7", "--json", "--worst", "3")
    grid = json.loads(out)["stages"][0]
    assert code == 1 and grid["failing"] == 1 and len(grid["worst"]) == 1
    worst, = grid["worst"]
    assert worst["at"] == [3, 4, 2] and worst["component"] == "[b, k=1]"
    assert worst["ours"] == 0.0 and worst["theirs"] == pytest.approx(4.001e-6)
    assert worst["ours_element"][8:] == [0.5, 0.0, 0.0, 0.0]         # colour b, k = 0..3
    assert worst["theirs_element"][9] == pytest.approx(4.001e-6)
    # no tolerance: no verdict, the largest differences listed per differing stage
    code, out = diff(capsys, pair, "--worst", "2")
    assert code == 0 and "verdict" not in out and "stages pass" not in out
    assert "worst cells of grid_2 (largest |Δ| first):" in out
    assert "worst pixels of direct" not in out                    # equal: nothing to list


def test_help_says_how_tolerance_differs_from_rtol(capsys):
    capsys.readouterr()
    main(["diff", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--atol A" in text and "--rtol R" in text and "--rel-l2 X" in text
    assert "(numpy.isclose with ours as the reference" in text
    assert "Unchanged from before; it is not --rtol" in text
    assert main(["diff", "x.npz", "--atol", "-1"]) == 2
    assert "atol must be" in capsys.readouterr().err
