"""``lpv-explorer compare`` on a tiny Cornell box, and on bad input."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from explorer.cli import main as cli_main

TINY = ["--size", "24x20", "--rsm-size", "8", "--grid-size", "8",
        "--iterations", "2", "--quiet"]


def test_compare_prints_the_table_and_writes_the_pngs(tmp_path, capsys, gl_context):
    out = tmp_path / "cmp"
    code = cli_main(["compare", "--scene", "cornell", "--reference", "visible",
                     "--out", str(out), "--region", "0,0,12,10", *TINY])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    table = captured.out
    assert "| preset | iterations | region | rel. L2 | RMSE | flux ratio LPV/ref |" in table
    rows = [line for line in table.splitlines() if line.startswith("| original")
            or line.startswith("| corrected")]
    assert len(rows) == 4  # two presets × (whole image, one region)
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert cells[1] == "2" and cells[2] in ("image", "0,0,12,10")
        rel_l2, rmse, ratio = (float(c) for c in cells[3:6])
        assert np.isfinite([rel_l2, rmse, ratio]).all() and ratio > 0
    for name in ("reference", "lpv-original", "lpv-corrected", "error-original",
                 "error-corrected"):
        image = Image.open(out / f"{name}.png")
        assert image.size[0] == 24 and image.size[1] >= 20
        assert np.asarray(image).max() > 0, f"{name}.png is black"
    assert (out / "table.md").read_text().strip() == table.split("\nwrote")[0].strip()


def test_compare_single_preset_unoccluded(tmp_path, capsys, gl_context):
    code = cli_main(["compare", "--preset", "corrected", "--reference", "unoccluded",
                     "--out", str(tmp_path), *TINY])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert "| corrected | 2 | image |" in captured.out and "| original" not in captured.out
    assert not (tmp_path / "lpv-original.png").exists()


def test_compare_iteration_sweep(tmp_path, capsys, gl_context):
    args = [a for a in TINY if a not in ("--iterations", "2")]
    code = cli_main(["compare", "--preset", "corrected", "--reference", "unoccluded",
                     "--iterations", "0,3", "--out", str(tmp_path), *args])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert "| corrected | 0 | image |" in captured.out
    assert "| corrected | 3 | image |" in captured.out
    assert (tmp_path / "lpv-corrected-it0.png").is_file()
    assert (tmp_path / "error-corrected-it3.png").is_file()


def test_unknown_scene_exits_non_zero_with_a_clear_message(tmp_path, capsys):
    code = cli_main(["compare", "--scene", "no-such-scene", "--out", str(tmp_path), *TINY])
    captured = capsys.readouterr()
    assert code != 0
    assert "no-such-scene" in captured.err and "error" in captured.err


@pytest.mark.parametrize("bad", [["--region", "1,2,3"], ["--size", "0x20"],
                                 ["--min-distance", "-1"], ["--iterations", "2,x"],
                                 ["--error-scale", "0"]])
def test_bad_arguments_exit_non_zero(tmp_path, capsys, bad):
    code = cli_main(["compare", "--out", str(tmp_path), *TINY, *bad])
    captured = capsys.readouterr()
    assert code == 2 and "lpv-explorer compare: error:" in captured.err
