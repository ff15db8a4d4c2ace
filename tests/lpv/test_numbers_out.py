"""Numbers out and in (docs: README "Numbers in and out"): ``render --dump`` equals the
Python API to the last bit, its VPLs and grid_0 fed back through ``--vpls`` / ``--grid0``
reproduce the frame, ``diff`` finds a perturbed cell, EXR and NPY round trips, and every
bad file is one line."""

from __future__ import annotations

import json

import numpy as np
import pytest
from lpv_cases import dump_small
from PIL import Image

from explorer.cli import main
from explorer.exchange.files import read_exr, read_npz
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings

SMALL = ["--scene", "cornell", "--grid", "8", "--iterations", "3", "--size", "32x24",
         "--rsm-size", "16", "--geometry-volume", "one-sided"]
SETTINGS = Settings(scene="cornell", grid_size=8, iterations=3, width=32, height=24,
                    rsm_size=16, geometry_volume="one-sided")


@pytest.fixture(scope="module")
def dumped(tmp_path_factory):
    """One dump of the small frame (CLI), read back: (folder, arrays, sidecar)."""
    return dump_small(tmp_path_factory.mktemp("dump"), SMALL)


@pytest.fixture(scope="module")
def api_frame(gl_context):
    with Pipeline(SETTINGS, gl_context) as pipeline:
        return pipeline.run(keep_steps=True)


def api_arrays(r) -> dict[str, np.ndarray]:
    """What the Python API says each dump array is (written out here, not through
    explorer.exchange.stages, so that the dump is checked against the FrameResult)."""
    area = r.gbuffer_normal[..., 3:4]
    irradiance = np.zeros_like(r.received)
    np.divide(r.received, area, out=irradiance, where=area > 0)
    arrays = {"rsm_position": r.rsm_position, "rsm_normal": r.rsm_normal,
              "rsm_flux": r.rsm_flux, "vpl_position": r.vpls.positions,
              "vpl_normal": r.vpls.normals, "vpl_flux": r.vpls.flux, "vpl_depth": r.vpls.depth,
              "vpl_albedo": r.vpls.albedo, "vpl_texel_area": np.float64(r.vpls.texel_area),
              "vpl_orthographic": np.bool_(r.vpls.projection == "orthographic"),
              "vpl_view": np.repeat(np.arange(len(r.vpl_sets), dtype=np.int32),
                                    [v.count for v in r.vpl_sets]),
              "grid_origin": np.asarray(r.grid_spec.origin),
              "grid_cell_size": np.float64(r.grid_spec.cell_size),
              "accumulated": r.accumulated, "geometry_volume": r.geometry_volume,
              "gbuffer_position": r.gbuffer_position, "gbuffer_normal": r.gbuffer_normal,
              "albedo": r.albedo, "received": r.received, "irradiance": irradiance,
              "direct": r.direct, "indirect": r.indirect, "final": r.final_image}
    arrays.update({f"grid_{t}": step for t, step in enumerate(r.steps)})
    return arrays


def test_every_dumped_array_equals_the_python_api(dumped, api_frame):
    _, arrays, _ = dumped
    expected = api_arrays(api_frame)
    assert set(arrays) == set(expected)
    assert [f"grid_{t}" for t in range(4)] == [n for n in arrays if n.startswith("grid_")
                                                and n[5:].isdigit()]
    for name, value in expected.items():
        value = np.asarray(value)
        assert arrays[name].dtype == value.dtype, name
        assert arrays[name].shape == value.shape, name
        assert np.array_equal(arrays[name], value), name       # to 0: the same bits
    assert float(np.abs(arrays["accumulated"]).max()) > 0     # a lit frame, not zeros


def test_sidecar_places_the_grid_and_names_every_array(dumped, api_frame):
    _, arrays, sidecar = dumped
    assert Settings.from_dict(sidecar["settings"]) == SETTINGS
    grid, = sidecar["grids"]
    spec = api_frame.grid_spec
    assert (grid["origin"], grid["cell_size"], grid["resolution"]) == (
        list(spec.origin), spec.cell_size, spec.resolution)
    assert "[colour, x, y, z, k]" in grid["convention"]
    assert set(sidecar["arrays"]) == set(arrays)
    for name, entry in sidecar["arrays"].items():
        assert entry["shape"] == list(arrays[name].shape) and entry["units"], name
    assert sidecar["arrays"]["grid_0"]["units"].startswith("W/sr")
    camera = sidecar["camera"]
    view = np.asarray(camera["view_matrix"])
    eye = np.append(camera["eye"], 1.0)
    assert np.allclose(view @ eye, [0, 0, 0, 1])               # the eye at the view origin
    light = sidecar["lights"][0]
    assert light["kind"] == "spot"
    rsm_view = np.asarray(light["rsm_view_matrix"])          # the light at its view origin
    assert np.allclose(rsm_view @ np.append(light["position"], 1.0), [0, 0, 0, 1])
    assert [c["title"] for c in sidecar["conventions"]][0] == "What a cell stores"


def test_dumped_vpls_fed_back_reproduce_grid_0_exactly(dumped, tmp_path):
    folder, arrays, _ = dumped
    again = tmp_path / "b.npz"
    assert main(["render", *SMALL, "--vpls", str(folder / "a.npz"), "--dump", str(again),
                 "--out", str(tmp_path / "b.png")]) == 0
    fed = read_npz(again)
    for name in ("grid_0", "accumulated", "geometry_volume", "indirect"):
        assert np.array_equal(fed[name], arrays[name]), name


def test_grid0_fed_in_is_propagated_from(dumped, tmp_path):
    """A grid_0 with one cell changed is what the frame propagates: its grid_0 is the file's
    and grid_1 is the numpy twin's step of it (the geometry volume's occlusion too)."""
    from explorer.lpv.twin import light_grid as twin

    folder, arrays, _ = dumped
    grid0 = arrays["grid_0"].copy()
    grid0[:, 4, 4, 4, 0] += 0.5
    given = tmp_path / "given.npz"
    np.savez(given, grid_0=grid0, grid_origin=arrays["grid_origin"],
             grid_cell_size=arrays["grid_cell_size"])
    out = tmp_path / "c.npz"
    assert main(["render", *SMALL, "--grid0", str(given), "--dump", str(out),
                 "--out", str(tmp_path / "c.png")]) == 0
    fed = read_npz(out)
    assert np.array_equal(fed["grid_0"], grid0)
    step, _ = twin.propagation_step(
        grid0.astype(np.float64), SETTINGS.corrections,
        geometry=arrays["geometry_volume"].astype(np.float64))
    scale = float(np.abs(step).max())
    assert np.allclose(fed["grid_1"], step, rtol=0, atol=1e-5 * scale)
    assert not np.allclose(fed["grid_1"], arrays["grid_1"], rtol=0, atol=1e-5 * scale)


def test_diff_reports_the_one_perturbed_cell(dumped, tmp_path, capsys):
    folder, arrays, _ = dumped
    theirs = dict(arrays)
    theirs["grid_2"] = arrays["grid_2"].copy()
    theirs["grid_2"][1, 3, 5, 6, 2] += 0.25
    path = tmp_path / "theirs.npz"
    np.savez(path, **theirs)
    capsys.readouterr()
    assert main(["diff", str(path), "--ours", str(folder / "a.npz"), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    stages = {entry["stage"]: entry for entry in report["stages"]}
    assert stages["grid_2"]["element"] == "cell"
    assert stages["grid_2"]["differing"] == 1
    assert stages["grid_2"]["max_error"] == pytest.approx(0.25, rel=1e-6)
    assert stages["grid_2"]["max_error_at"] == [3, 5, 6]
    assert stages["grid_2"]["max_relative_at"] == [3, 5, 6]
    assert all(entry["max_error"] == 0 for name, entry in stages.items() if name != "grid_2")
    # rendered ours (the settings from theirs' sidecar), and a failing tolerance
    (tmp_path / "theirs.json").write_text((folder / "a.json").read_text(encoding="utf-8"))
    assert main(["diff", str(path), "--tolerance", "1e-3"]) == 1
    table = capsys.readouterr().out
    line, = [row for row in table.splitlines() if row.startswith("| grid_2 |")]
    assert "at cell (3, 5, 6)" in line and "| 1 |" in line


def test_exr_and_npy_hold_the_float_view(tmp_path, api_frame):
    assert main(["render", *SMALL, "--view", "final", "--view", "grid-slice", "--out",
                 str(tmp_path / "f.exr")]) == 0
    assert main(["render", *SMALL, "--view", "indirect", "--out", str(tmp_path / "i.npy")]) == 0
    assert np.array_equal(read_exr(tmp_path / "f-final.exr"), api_frame.final_image)
    assert np.array_equal(np.load(tmp_path / "i.npy", allow_pickle=False), api_frame.indirect)
    flux = read_exr(tmp_path / "f-grid-slice.exr")        # 2√π·c0 of slice z = 4, y up
    from explorer.lpv.constants import SH_FLUX_FACTOR
    expected = SH_FLUX_FACTOR * api_frame.accumulated[:, :, :, 4, 0]
    assert np.allclose(flux, np.transpose(expected, (2, 1, 0))[::-1], rtol=1e-6, atol=0)


def test_grid_slice_png_has_its_scale_bar(tmp_path):
    out = tmp_path / "slice.png"
    assert main(["render", *SMALL, "--view", "grid-slice", "--out", str(out)]) == 0
    image = np.asarray(Image.open(out).convert("RGB")).astype(int)
    assert image.shape[0] > image.shape[1] == 256            # the bar under the 256² slice
    ramp = image[258, :, 0]                                  # the ramp row: dark -> white
    assert ramp[0] < 10 and ramp[-1] > 245 and np.all(np.diff(ramp) >= 0)


@pytest.mark.parametrize("arrays, message", [
    ({"vpl_position": np.zeros((2, 3))}, "no array 'vpl_normal'"),
    ({"vpl_position": np.zeros((2, 3)), "vpl_normal": np.zeros((2, 2)),
      "vpl_flux": np.zeros((2, 3))}, "vpl_normal must have shape (2, 3), got (2, 2)"),
    ({"vpl_position": np.zeros((2, 3), np.int64), "vpl_normal": np.zeros((2, 3)),
      "vpl_flux": np.zeros((2, 3))}, "vpl_position must be float32 or float64, got int64"),
    ({"vpl_position": np.zeros((2, 3)), "vpl_normal": np.tile([0.0, 2.0, 0.0], (2, 1)),
      "vpl_flux": np.zeros((2, 3))}, "vpl_normal is not unit in 2 rows: row 0 (length 2), row 1 "
                                       "(length 2)"),
    ({"vpl_position": np.zeros((1, 3)), "vpl_normal": np.array([[0.0, 1.0, 0.0]]),
      "vpl_flux": np.array([[np.nan, 0.0, 0.0]])}, "vpl_flux is not finite in 1 row: row 0 "
                                                   "(column 0)"),
    ({"vpl_position": np.zeros((1, 3)), "vpl_normal": np.array([[0.0, 1.0, 0.0]]),
      "vpl_flux": np.ones((1, 3))}, "the geometry volume needs vpl_depth"),
    ({"vpl_position": np.array([None, None], dtype=object)}, "never unpickled"),
])
def test_bad_vpl_files_are_one_line_errors(tmp_path, capsys, arrays, message):
    path = tmp_path / "vpls.npz"
    np.savez(path, **arrays)
    assert main(["render", *SMALL, "--vpls", str(path), "--out", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1, err
    assert not (tmp_path / "x.png").exists()


def test_bad_grid0_files_are_one_line_errors(tmp_path, capsys, dumped):
    path = tmp_path / "g.npz"
    np.savez(path, grid_0=np.zeros((3, 16, 16, 16, 4), np.float32))
    assert main(["render", *SMALL, "--grid0", str(path)]) == 2
    assert "grid_0 is a 16³ grid, the frame's is 8³ (set --grid-size 16)" in \
        capsys.readouterr().err
    np.savez(path, grid_0=np.zeros((3, 8, 8, 8, 4), np.float32), grid_origin=np.zeros(3))
    assert main(["render", *SMALL, "--grid0", str(path), "--out", str(tmp_path / "y.png")]) == 2
    assert "grid_origin [0.0, 0.0, 0.0] is not the frame's grid" in capsys.readouterr().err
    assert not (tmp_path / "y.png").exists()
    assert main(["render", *SMALL, "--grid0", str(path), "--cascades", "2"]) == 2
    assert "use --cascades 1" in capsys.readouterr().err


def test_exr_without_openexr_says_how_to_get_it(tmp_path, capsys, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "OpenEXR", None)       # import OpenEXR now fails
    assert main(["render", *SMALL, "--out", str(tmp_path / "f.exr")]) == 2
    err = capsys.readouterr().err
    assert "pip install 'lpv-explorer[exr]'" in err and err.count("\n") == 1


def test_compare_json_and_dump_hold_the_reference(tmp_path, capsys):
    """``compare --json`` prints only JSON on stdout; its last row's relative L2 error is
    the one the dump's own indirect and reference images give."""
    from explorer.truth.metrics import error_stats

    dump = tmp_path / "cmp.npz"
    capsys.readouterr()
    assert main(["compare", "--scene", "cornell", "--width", "32", "--height", "24",
                 "--rsm-size", "16", "--grid-size", "8", "--iterations", "2", "--quiet",
                 "--out", str(tmp_path / "cmp"), "--json", "--dump", str(dump)]) == 0
    report = json.loads(capsys.readouterr().out)
    assert [(r["preset"], r["iterations"]) for r in report["rows"]] == [
        ("original", 2), ("corrected", 2)]
    assert json.loads((tmp_path / "cmp" / "table.json").read_text()) == report
    arrays = read_npz(dump)
    assert arrays["reference"].shape == arrays["indirect"].shape == (24, 32, 3)
    valid = arrays["gbuffer_position"][..., 3] > 0.5
    stats = error_stats(arrays["indirect"].astype(np.float64), arrays["reference"], valid)
    assert stats.relative_l2 == pytest.approx(report["rows"][-1]["relative_l2"], rel=1e-12)
    assert json.loads(dump.with_suffix(".json").read_text())["arrays"]["reference"]["units"]
