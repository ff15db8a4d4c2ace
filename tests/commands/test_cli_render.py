"""``lpv-explorer render`` on good and bad input."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from explorer.cli import main

SMALL = ["--grid", "8", "--iterations", "3", "--size", "48x40", "--rsm-size", "32"]


@pytest.mark.parametrize("preset", ["corrected", "original"])
def test_render_writes_a_lit_png_for_each_preset(tmp_path, capsys, preset):
    out = tmp_path / f"{preset}.png"
    assert main(["render", "--scene", "cornell", "--preset", preset, "--out", str(out),
                 *SMALL, "--audit"]) == 0
    image = np.asarray(Image.open(out))
    assert image.shape == (40, 48, 3)
    assert image.mean() > 20                      # lit, not black
    printed = capsys.readouterr().out
    assert "wrote" in printed and "injected" in printed


def test_render_writes_one_png_per_view(tmp_path):
    out = tmp_path / "frame.png"
    assert main(["render", "--out", str(out), *SMALL, "--view", "rsm-flux",
                 "--view", "grid-slice", "--slice", "4", "--coefficient", "0"]) == 0
    flux = Image.open(tmp_path / "frame-rsm-flux.png")
    assert flux.size == (256, 256)                # 32² RSM enlarged to at least 256
    assert (tmp_path / "frame-grid-slice.png").is_file()


def test_bad_scene_path_fails_cleanly(tmp_path, capsys):
    missing = tmp_path / "missing.obj"
    assert main(["render", "--scene", str(missing), "--out", str(tmp_path / "x.png"),
                 *SMALL]) == 2
    err = capsys.readouterr().err
    assert "missing.obj" in err and "Traceback" not in err
    corrupt = tmp_path / "corrupt.glb"
    corrupt.write_bytes(b"not a glb file at all")
    assert main(["render", "--scene", str(corrupt), "--out", str(tmp_path / "x.png"),
                 *SMALL]) == 2
    assert "corrupt.glb" in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists()


def test_bad_sizes_are_refused(tmp_path, capsys):
    assert main(["render", "--size", "0x10", "--out", str(tmp_path / "x.png")]) == 2
    assert "width must be a whole number in [1, 8192], got 0" in capsys.readouterr().err
    assert main(["render", "--grid", "0", "--out", str(tmp_path / "x.png")]) == 2
    assert "grid_size" in capsys.readouterr().err
