"""App state, settings persistence and the pure image helpers: no window, no GL."""

from __future__ import annotations

import json

import numpy as np
import pytest

from explorer.lpv.settings import PRESETS, Settings
from explorer.ui import camera, images, persist
from explorer.ui.layout_file import LayoutFileError, check_layout
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
    assert persist.state_to_dict(loaded) == persist.state_to_dict(state)


def test_a_file_written_before_the_rename_keeps_the_per_side_exposure(tmp_path):
    """The compare views' per-side exposure was saved as ``auto_exposure`` before Settings
    got an auto exposure of its own; such a file reads it as expose_sides_separately."""
    path = tmp_path / "settings.json"
    path.write_text(json.dumps({"format": 1, "auto_exposure": True}))
    state = AppState()
    assert persist.load_state(state, path) is None
    assert state.expose_sides_separately is True and state.settings.auto_exposure is True
    assert "auto_exposure" not in persist.state_to_dict(state)
    assert persist.state_to_dict(state)["expose_sides_separately"] is True


def _file(**fields) -> str:
    return json.dumps({"format": 1, **fields})


BAD_FILES = [
    # each would stop the window (a traceback) or be accepted without its check
    (_file(split_position="abc"), "split_position must be a finite number in [0.02, 0.98], "
                                  "got 'abc'"),
    (_file(render_scale="big"), "render_scale must be a finite number in [0.25, 2]"),
    (_file(render_scale=[1]), "render_scale must be a finite number in [0.25, 2], got [1]"),
    (_file(settings={"iterations": 1000000}), "settings.iterations must be a whole number in "
                                              "[0, 1024], got 1000000"),
    (_file(settings={"grid_size": 100000}), "settings.grid_size must be a whole number"),
    (_file(settings={"rsm_size": 16384}), "settings.rsm_size must be a whole number in [1, "
                                          "4096]"),
    (_file(inspect={"slice_z": "abc"}), "inspect.slice_z must be a whole number"),
    (_file(inspect={"source": "bogus"}), "inspect.source must be one of 'rsm-position'"),
    (_file(auto_exposure="no"), "expose_sides_separately must be true or false, got 'no'"),
    ('{"format": 1, "settings": {"exposure": NaN}}', "settings.exposure must be a finite"),
    (_file(settings={"exposure": -1}), "settings.exposure must be a finite number in (0,"),
    ('{"format": 1, "settings": {"light_flux": Infinity}}', "settings.light_flux must be"),
    (_file(settings={"light_flux": -2.0}), "settings.light_flux must be a finite number in (0"),
    (_file(settings={"camera": [[0, 0, 0], [0, 0, 0]]}), "settings.camera must be two "
                                                          "different points"),
    (_file(compare_settings={"bounces": 2}), "compare_settings.bounces"),
    (_file(window_size=[100000, 100000]), "window_size must be [width, height], whole numbers "
                                          "in [150, 8192]"),
    (_file(open_panels={"View": "yes"}), "open_panels must be a table of names to true/false"),
    (_file(lesson_id="01"), "unknown field(s) lesson_id"),      # never persisted
    (_file(runtime={}), "unknown field(s) runtime"),
    # and the file's own form
    ("{not json", "Expecting"),
    ("[1, 2]", "JSON object"),
    (_file(settings={"grid_size": "big"}), "grid_size"),
    (_file(settings={"corrections": {"nope": True}}), "nope"),
    (_file(settings={"downsample": "median"}), "downsample"),
    (_file(view_mode="quad"), "view_mode"),
    (_file(settings={"spot_cone_degrees": [50, "wide"]}), "settings.spot_cone_degrees must "
                                                          "be two numbers"),
    (_file(settings={"spot_cone_degrees": [60, 30]}), "0 <= first <= second <= 80, second > "
                                                      "0 or None, got [60, 30]"),
    (_file(settings={"spot_cone_degrees": [0, 0]}), "settings.spot_cone_degrees"),
    (_file(settings={"tone_map": "sepia"}), "settings.tone_map must be one of 'linear-clip', "
                                            "'filmic'"),
    (_file(settings={"shadow_kernel": 0}), "settings.shadow_kernel must be a whole number in "
                                           "[1, 9]"),
    (_file(settings={"auto_exposure": "no"}), "settings.auto_exposure must be true or false"),
    (json.dumps({"format": 99}), "format"),
]


@pytest.mark.parametrize("content, complaint", BAD_FILES)
def test_a_bad_settings_file_is_set_aside_and_the_defaults_used(tmp_path, content, complaint):
    path = tmp_path / "settings.json"
    path.write_text(content)
    state = AppState()
    problem = persist.load_state(state, path)
    assert problem is not None and complaint in problem, problem
    assert "\n" not in problem and "using the default settings" in problem
    aside = list(tmp_path.glob("settings.json.bad-*"))
    assert len(aside) == 1 and aside[0].read_text() == content
    assert f"moved it to {aside[0].name}" in problem
    assert not path.exists()
    assert state.settings == Settings() and state.inspect == AppState().inspect
    assert persist.load_state(AppState(), path) is None      # the next launch starts clean


def test_a_file_from_before_the_schema_still_loads(tmp_path):
    """What the previous version wrote (no difference_scale / follow_view_size keys)."""
    path = tmp_path / "settings.json"
    old = persist.state_to_dict(AppState())
    del old["difference_scale"], old["follow_view_size"]
    path.write_text(json.dumps(old))
    assert persist.load_state(AppState(), path) is None


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


GOOD_LAYOUT = """\
[Window][View]
Pos=433,23
Size=780,762
Collapsed=0
DockId=0x00000005,0

[Docking][Data]
DockSpace       ID=0x6984D733 Window=0x1BBC0F80 Pos=0,23 Size=1600,937 Split=X
  DockNode      ID=0x00000001 Parent=0x6984D733 SizeRef=431,960 Split=Y
    DockNode    ID=0x00000007 Parent=0x00000001 SizeRef=431,555 Selected=0x5A065080
    DockNode    ID=0x00000008 Parent=0x00000001 SizeRef=431,403 Selected=0xE601B12F
  DockNode      ID=0x00000002 Parent=0x6984D733 SizeRef=1167,960 CentralNode=1
"""
"""The shape of what imgui writes (trimmed from a layout the app saved)."""


@pytest.mark.parametrize("change, complaint", [
    (("Parent=0x00000001 SizeRef=431,555", "Parent=0x0000BEEF SizeRef=431,555"),
     "names Parent=0x0000beef, which no earlier line defines"),
    (("Size=1600,937", "Size=-5,937"), "Size=-5,937 must be in [1, 32767]"),
    (("Size=1600,937", "Size=1600,40000"), "must be in [1, 32767]"),
    (("ID=0x00000008", "ID=0x00000007"), "dock node id 0x00000007 is used twice"),
    (("    DockNode    ID=0x00000008 Parent=0x00000001 SizeRef=431,403 Selected=0xE601B12F\n",
      ""), "has 1 child node(s) and Split=Y"),
    (("Split=X", "Split=Z"), "Split must be X or Y"),
    (("Pos=0,23 ", ""), "a root dock node needs Pos=x,y"),
    (("SizeRef=431,960", "SizeRef=431"), "SizeRef must be two integers"),
    (("ID=0x00000002", "ID=0x0000000G"), "ID must be a non-zero id"),
    (("DockSpace ", "Dock "), "expected DockSpace or DockNode"),
])
def test_a_layout_imgui_cannot_use_is_refused_before_imgui_reads_it(change, complaint):
    assert len(check_layout(GOOD_LAYOUT)) == 5
    old, new = change
    assert old in GOOD_LAYOUT
    with pytest.raises(LayoutFileError) as info:
        check_layout(GOOD_LAYOUT.replace(old, new, 1))
    assert complaint in str(info.value) and str(info.value).startswith("line ")


def test_a_bad_layout_file_is_set_aside(tmp_path):
    path = tmp_path / "imgui.ini"
    assert persist.check_layout_file(path) is None                 # none yet: fine
    path.write_text(GOOD_LAYOUT)
    assert persist.check_layout_file(path) is None and path.exists()
    path.write_text(GOOD_LAYOUT.replace("Size=1600,937", "Size=-5,937"))
    problem = persist.check_layout_file(path)
    assert "Size=-5,937" in problem and "using the default layout" in problem
    assert not path.exists() and len(list(tmp_path.glob("imgui.ini.bad-*"))) == 1


def test_what_the_window_saves_always_reads_back(tmp_path):
    """A window dragged smaller than the smallest allowed size, or the last step of a
    "same-distance" finest cascade in the Inspect panel, must not get the whole file set
    aside on the next launch."""
    from explorer.ui.state import MAX_WINDOW_SIZE, MIN_WINDOW_SIZE, fit_window_size

    state = AppState()
    state.window_size = fit_window_size((90, 40000))
    assert state.window_size == (MIN_WINDOW_SIZE, MAX_WINDOW_SIZE)
    state.inspect.iteration = 1024 * 8      # 4 cascades, same-distance: 2^3 × 1024 steps
    path = tmp_path / "settings.json"
    persist.save_state(state, path)
    loaded = AppState()
    assert persist.load_state(loaded, path) is None
    assert loaded.window_size == state.window_size and loaded.inspect.iteration == 8192


def test_the_scene_panel_draws_every_declared_widget_from_its_spec():
    """Every field of Settings and AppState that declares a widget or a group is a control
    of exactly one section; generic widgets take label, range and tooltip from the spec."""
    from explorer.schema import specs
    from explorer.ui.panels.scene import GROUPS, OWNERS, controls
    from explorer.ui.setting_widgets import combo_options, label_of, slider_range, tooltip_of

    drawn = [control for group in GROUPS for control in controls(group)]
    declared = [(owner, name) for owner in OWNERS for name, spec in specs(owner).items()
                if spec.widget or spec.group]
    assert sorted(drawn, key=str) == sorted(declared, key=str) and len(set(drawn)) == len(drawn)
    grid, iterations = specs(Settings)["grid_size"], specs(Settings)["iterations"]
    assert label_of(grid, "grid_size") == "Grid size (cells³)"
    assert combo_options(grid, 40) == [8, 16, 24, 32, 40, 48, 64]   # the current one too
    assert slider_range(iterations) == (0, 64)                      # typing goes to 1024
    assert "a whole number in [0, 1024]" in tooltip_of(iterations)
    offset = specs(Settings)["injection_offset_cells"]
    assert label_of(offset, "injection_offset_cells") == "VPL offset [cells]"
    assert "0 = automatic" in tooltip_of(specs(Settings)["cascade_extent"])
    # look's fields: generic widgets, but the cone pair (a custom two-handled slider)
    assert [name for _, name in controls("Light and shadows")] == [
        "spot_cone", "spot_cone_degrees", "shadow_kernel"]
    assert [name for _, name in controls("Display")] == ["tone_map", "auto_exposure"]
    # beyond diffuse: generic widgets in their own section, the camera occluders with the
    # other leak reductions
    assert [name for _, name in controls("Fog and glossy")] == [
        "fog", "fog_density", "fog_albedo", "fog_phase", "fog_g", "fog_steps", "glossy",
        "glossy_roughness", "glossy_strength", "glossy_samples"]
    assert "camera_occluders" in [name for _, name in controls("Leak reduction and bounces")]
    # the how-far switches: the flux budget among the leak reductions, the volume's
    # visibility beside the volume
    assert "flux_budget" in [name for _, name in controls("Leak reduction and bounces")]
    assert "geometry_visibility" in [name for _, name in controls("Light propagation volume")]
    assert "reprojection" in [name for _, name in controls("Light propagation volume")]
    assert label_of(specs(Settings)["fog_density"], "fog_density") == "Fog density σt [1/m]"
    assert label_of(specs(Settings)["shadow_kernel"], "shadow_kernel") == "Shadow PCF [texels]"


def test_fog_and_glossy_controls_show_only_when_switched_on():
    from explorer.ui.panels.scene import _SHOWN_WHEN

    state = AppState()
    hidden = ("fog_density", "fog_albedo", "fog_phase", "fog_g", "fog_steps",
              "glossy_roughness", "glossy_strength", "glossy_samples", "camera_occluders")
    assert not any(_SHOWN_WHEN[name](state) for name in hidden)
    state.update(fog=True, glossy=True, geometry_volume="one-sided")
    assert all(_SHOWN_WHEN[name](state) for name in hidden)
    state.update(fog_phase="isotropic")          # g means nothing to the isotropic function
    assert not _SHOWN_WHEN["fog_g"](state) and _SHOWN_WHEN["fog_steps"](state)
