"""App state, settings persistence and the pure image helpers: no window, no GL."""

from __future__ import annotations

import json

import numpy as np
import pytest

from explorer.lpv.settings import PRESETS, Settings
from explorer.ui import camera, images, persist
from explorer.ui.state import AppState


def test_settings_round_trip_through_json(tmp_path):
    state = AppState()
    state.settings = Settings(grid_size=16, iterations=4, corrections=PRESETS["original"],
                              camera=((1.0, 2.0, 3.0), (0.0, 0.5, 0.0)), light_flux=7.5,
                              spot_cone_degrees=(20.0, 50.0), shadow_kernel=5,
                              tone_map="linear-clip", auto_exposure=False)
    state.view_mode = "split"
    state.split_position = 0.3
    state.inspect.source = "grid-slice"
    path = tmp_path / "settings.json"
    persist.save_state(state, path)
    loaded = AppState()
    assert persist.load_state(loaded, path) is None
    assert loaded.settings == state.settings
    assert loaded.view_mode == "split" and loaded.split_position == pytest.approx(0.3)
    assert loaded.inspect.source == "grid-slice"


@pytest.mark.parametrize("content, complaint", [
    ("{not json", "Expecting"),
    ("[1, 2]", "JSON object"),
    (json.dumps({"format": 1, "settings": {"grid_size": "big"}}), "grid_size"),
    (json.dumps({"format": 1, "settings": {"corrections": {"nope": True}}}), "nope"),
    (json.dumps({"format": 1, "settings": {"downsample": "median"}}), "downsample"),
    (json.dumps({"format": 1, "view_mode": "quad"}), "view_mode"),
    (json.dumps({"format": 1, "settings": {"spot_cone_degrees": [50, "wide"]}}),
     "spot_cone_degrees"),
    (json.dumps({"format": 1, "settings": {"spot_cone_degrees": [60, 30]}}),
     "spot_cone_degrees"),
    (json.dumps({"format": 1, "settings": {"tone_map": "sepia"}}), "tone_map"),
    (json.dumps({"format": 1, "settings": {"shadow_kernel": 0}}), "shadow_kernel"),
    (json.dumps({"format": 99}), "format"),
])
def test_a_bad_settings_file_falls_back_to_defaults_and_says_why(tmp_path, content, complaint):
    path = tmp_path / "settings.json"
    path.write_text(content)
    state = AppState()
    problem = persist.load_state(state, path)
    assert problem is not None and complaint in problem and "default" in problem
    assert state.settings == Settings()


def test_config_dir_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path))
    assert persist.settings_path() == tmp_path / "lpv-explorer" / "settings.json"
    assert persist.layout_path().parent == tmp_path / "lpv-explorer"


def test_orbit_keeps_distance_and_target():
    eye, target = (0.0, 1.0, 4.0), (0.0, 1.0, 0.0)
    new_eye, new_target = camera.orbit(eye, target, 90.0, 0.0)
    assert new_target == target
    assert np.allclose(new_eye, (4.0, 1.0, 0.0), atol=1e-9)
    closer, _ = camera.dolly(eye, target, 0.5)
    assert np.allclose(closer, (0.0, 1.0, 2.0), atol=1e-9)
    top, _ = camera.orbit(eye, target, 0.0, 200.0)        # clamped short of the pole
    assert camera.to_angles(top, target)[1] == pytest.approx(89.0)


def test_grid_slice_shows_the_evaluated_intensity_and_signed_coefficients():
    n = 4
    grid = np.zeros((3, n, n, n, 4), np.float32)
    grid[:, 1, 2, 3, 0] = 1.0           # isotropic intensity in cell (1, 2, 3)
    grid[:, 1, 2, 3, 3] = -0.5
    image, top = images.grid_slice(grid, 3, "intensity", (0.0, 1.0, 0.0))
    assert image.shape == (n, n, 3) and top > 0
    # rows are y from the top: cell y=2 is row n-1-2 = 1, column x = 1
    bright = np.argwhere(image.sum(-1) > 0)
    assert bright.tolist() == [[1, 1]]
    coeff, top = images.grid_slice(grid, 3, "sh3")
    assert top == pytest.approx(0.5)
    assert coeff[1, 1, 2] > coeff[1, 1, 0]  # negative: blue dominates
    assert images.flux_of_grid(grid) == pytest.approx(3 * 2 * np.sqrt(np.pi), rel=1e-6)
    with pytest.raises(ValueError, match=r"\(3, N, N, N, 4\)"):
        images.grid_slice(grid[0], 0, "sh0")


def test_difference_and_auto_exposure():
    a = np.zeros((8, 8, 3), np.float32)
    b = a.copy()
    b[:, 4:] = 0.5
    image, top = images.difference(a, b)
    assert top == pytest.approx(0.5)
    assert image[:, :4].max() < 0.05 < image[:, 4:].min()
    exposure = images.auto_exposure(b * 2.0, exposure_used=2.0)
    assert exposure == pytest.approx(0.85 / 0.5, rel=1e-3)
    with pytest.raises(ValueError, match="shape"):
        images.difference(a, b[:4])


def test_vpl_groups_colour_by_flux_and_drop_dark_ones():
    positions = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], np.float32)
    flux = np.array([[1, 0, 0], [0, 1, 0], [1, 1, 1], [0, 0, 0]], np.float32)
    groups = images.vpl_groups(positions, flux)
    colours = {rgb: pts[:, 0].tolist() for rgb, pts in groups}
    assert colours == {(1.0, 0.15, 0.15): [0.0], (0.15, 1.0, 0.15): [1.0], (1.0, 1.0, 1.0): [2.0]}
    many = images.vpl_groups(np.random.rand(5000, 3), np.ones((5000, 3)), max_points=100)
    assert sum(len(p) for _, p in many) == 100
    with pytest.raises(ValueError, match="differ"):
        images.vpl_groups(positions, flux[:2])
