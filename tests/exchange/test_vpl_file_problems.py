"""``--vpls FILE``: every problem of the file in one message, each bad row named, not
only the first one found."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.cli import main
from explorer.exchange.files import FileFormatError
from explorer.exchange.inputs import ROWS_NAMED, load_vpls


def _good(count: int = 6) -> dict[str, np.ndarray]:
    normals = np.tile([0.0, 1.0, 0.0], (count, 1))
    return {"vpl_position": np.zeros((count, 3)), "vpl_normal": normals,
            "vpl_flux": np.ones((count, 3)), "vpl_depth": np.ones(count),
            "vpl_texel_area": np.float64(0.01)}


def _problems(tmp_path, arrays: dict, **options) -> str:
    path = tmp_path / "theirs.npz"
    np.savez(path, **arrays)
    with pytest.raises(FileFormatError) as caught:
        load_vpls(path, **options)
    message = str(caught.value)
    assert "\n" not in message and message.startswith(f"--vpls {path}: ")
    return message


def test_every_problem_with_its_rows_in_one_message(tmp_path):
    arrays = _good()
    arrays["vpl_normal"][1] = (0.0, 2.0, 0.0)             # two normals not unit
    arrays["vpl_normal"][4] = (0.0, 0.0, 0.0)
    arrays["vpl_flux"][3, 2] = np.nan                     # flux not finite in rows 3 and 5
    arrays["vpl_flux"][5, 0:2] = np.inf
    arrays["vpl_depth"] = np.ones(5)                      # depth one row short
    arrays["vpl_texel_area"] = np.float64(-1.0)           # area not positive
    arrays["vpl_albedo"] = np.zeros((6, 3), np.int32)     # albedo not floats
    message = _problems(tmp_path, arrays)
    assert ": 5 problems: (1) " in message
    for part in ("vpl_flux is not finite in 2 rows: row 3 (column 2), row 5 (column 0, 1)",
                 "vpl_normal is not unit in 2 rows: row 1 (length 2), row 4 (length 0)",
                 "vpl_depth must have shape (6,), got (5,)",
                 "vpl_texel_area must be positive, got -1.0",
                 "vpl_albedo must be float32 or float64, got int32"):
        assert part in message, (part, message)


def test_missing_arrays_are_all_named(tmp_path):
    message = _problems(tmp_path, {"vpl_position": np.zeros((2, 3))}, geometry_volume=True)
    assert "3 problems" in message
    assert "no array 'vpl_normal'" in message and "no array 'vpl_flux'" in message
    assert "the geometry volume needs vpl_depth" in message


def test_many_bad_rows_name_the_first_and_count_the_rest(tmp_path):
    arrays = _good(100)
    arrays["vpl_normal"][:] = (0.0, 3.0, 0.0)
    message = _problems(tmp_path, arrays)
    assert message.count("(length 3)") == ROWS_NAMED
    assert f"row {ROWS_NAMED - 1} (length 3) and {100 - ROWS_NAMED} more rows" in message
    assert "not unit in 100 rows" in message


def test_one_problem_reads_as_before(tmp_path):
    arrays = _good()
    arrays["vpl_flux"] = np.ones((6, 2))
    message = _problems(tmp_path, arrays)
    assert message.endswith(": vpl_flux must have shape (6, 3), got (6, 2)")


def test_the_command_prints_every_problem_on_one_line(tmp_path, capsys):
    arrays = _good()
    arrays["vpl_normal"][2] = (1.0, 1.0, 0.0)
    arrays["vpl_position"][0, 1] = np.nan
    path = tmp_path / "theirs.npz"
    np.savez(path, **arrays)
    out = tmp_path / "x.png"
    assert main(["render", "--scene", "cornell", "--grid", "8", "--size", "16x16",
                 "--rsm-size", "16", "--vpls", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "2 problems" in err, err
    assert "vpl_position is not finite in 1 row: row 0 (column 1)" in err
    assert "vpl_normal is not unit in 1 row: row 2 (length 1.41421)" in err
    assert not out.exists()
