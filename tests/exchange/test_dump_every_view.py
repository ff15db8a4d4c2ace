"""``render --dump`` writes every light view: each RSM view's arrays (a spot and a point
light's six faces), each VPL's view, each view's light, face and matrices in the sidecar,
and the reader (``view_arrays``) and ``diff`` read them back."""

from __future__ import annotations

import json

import numpy as np
import pytest
from lpv_cases import dump_small

from explorer.cli import main
from explorer.exchange.files import read_npz
from explorer.exchange.stages import view_arrays
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.scene.lights import CUBE_FACE_AXES

SMALL = ["--scene", "cornell", "--lights", "spot,bulb", "--grid", "8", "--iterations", "2",
         "--size", "32x24", "--rsm-size", "16"]
SETTINGS = Settings(scene="cornell", lights=("spot", "bulb"), grid_size=8, iterations=2,
                    width=32, height=24, rsm_size=16)
VIEWS = 7                                     # the spot's one view and the bulb's six faces


@pytest.fixture(scope="module")
def dumped(tmp_path_factory):
    return dump_small(tmp_path_factory.mktemp("views"), SMALL)


@pytest.fixture(scope="module")
def api_frame(gl_context):
    with Pipeline(SETTINGS, gl_context) as pipeline:
        return pipeline.run(keep_steps=True)


def test_every_views_rsm_and_vpls_are_dumped_bit_for_bit(dumped, api_frame):
    _, arrays, _ = dumped
    assert len(api_frame.rsm_views) == len(api_frame.vpl_sets) == VIEWS
    views = view_arrays(arrays)
    assert len(views) == VIEWS
    for k, (view, (position, normal, flux), vpls) in enumerate(
            zip(views, api_frame.rsm_views, api_frame.vpl_sets)):
        for name, value in (("rsm_position", position), ("rsm_normal", normal),
                            ("rsm_flux", flux), ("vpl_position", vpls.positions),
                            ("vpl_normal", vpls.normals), ("vpl_flux", vpls.flux),
                            ("vpl_depth", vpls.depth)):
            assert view[name].dtype == np.asarray(value).dtype, (k, name)
            assert np.array_equal(view[name], value), (k, name)
        assert np.any(view["rsm_position"][..., 3] > 0), k      # each face sees the room
    # the first view stays where a one-light dump has it
    assert np.array_equal(arrays["rsm_flux"], api_frame.rsm_flux)
    assert np.array_equal(arrays["vpl_position"], api_frame.vpls.positions)


def test_sidecar_lists_every_view_with_matrices_that_project_its_rsm(dumped):
    _, arrays, sidecar = dumped
    entries = sidecar["rsm_views"]
    assert [(e["light"], e["kind"], e["face"]) for e in entries] == [
        ("spot", "spot", None)] + [("bulb", "point", f) for f in
                                   ("+x", "-x", "+y", "-y", "+z", "-z")]
    assert sum(e["vpls"] for e in entries) == len(arrays["vpl_position"])
    assert [e["vpl_first"] for e in entries] == list(np.cumsum(
        [0] + [e["vpls"] for e in entries[:-1]]))
    bulb = next(light for light in sidecar["lights"] if light["name"] == "bulb")
    for k, entry in enumerate(entries):
        prefix = f"view{k}_" if k else ""
        assert entry["arrays"] == [prefix + "rsm_position", prefix + "rsm_normal",
                                   prefix + "rsm_flux"]
        view, projection = (np.asarray(entry[m]) for m in ("view_matrix",
                                                           "projection_matrix"))
        if entry["kind"] == "point":          # at the bulb, looking along its face's axis
            assert np.allclose(view @ np.append(bulb["position"], 1.0), [0, 0, 0, 1])
            axis = CUBE_FACE_AXES[k - 1]
            assert np.allclose(view[:3, :3] @ axis, [0, 0, -1], atol=1e-12)
        # every texel's surface point lands in its own texel of this view's frustum
        texels = arrays[prefix + "rsm_position"]
        seen = texels[..., 3] > 0
        rows, cols = np.nonzero(seen)
        clip = (projection @ view @ np.c_[texels[seen][:, :3],
                                          np.ones(seen.sum())].T).T
        ndc = clip[:, :2] / clip[:, 3:4]
        size = entry["size"][0]
        column = np.floor((ndc[:, 0] + 1) / 2 * size)
        row = np.floor((1 - ndc[:, 1]) / 2 * size)            # row 0 at the top
        near = (np.abs(column - cols) <= 1) & (np.abs(row - rows) <= 1)
        assert near.mean() > 0.99, (k, near.mean())


def test_diff_reads_every_view_back_and_finds_a_changed_face_texel(dumped, tmp_path, capsys):
    folder, arrays, _ = dumped
    theirs = dict(arrays)
    flux = theirs["view3_rsm_flux"].copy()               # the bulb's +y face
    row, col = (int(v[0]) for v in np.nonzero(flux[..., 0] > 0))
    flux[row, col, 1] += 1.0
    theirs["view3_rsm_flux"] = flux
    path = tmp_path / "theirs.npz"
    np.savez(path, **theirs)
    capsys.readouterr()
    assert main(["diff", str(path), "--ours", str(folder / "a.npz"), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    stages = {s["stage"]: s for s in report["stages"]}
    assert report["only_theirs"] == report["only_ours"] == []
    assert stages["view3_rsm_flux"]["element"] == "texel"
    assert stages["view3_rsm_flux"]["differing"] == 1
    assert stages["view3_rsm_flux"]["max_error_at"] == [col, row]
    assert stages["vpl_view"]["element"] == "VPL" and stages["vpl_view"]["differing"] == 0
    for k in range(1, VIEWS):
        assert stages[f"view{k}_rsm_position"]["differing"] == 0


def test_every_view_needs_kept_steps_and_a_kept_frame_reads_them_after_a_plain_one(
        gl_context):
    """A frame without keep_steps reads back the first view's RSM only (the window's
    frames stay as cheap); asking for the steps later reads every view, though the RSM
    stage's inputs did not change."""
    with Pipeline(SETTINGS, gl_context) as pipeline:
        plain = pipeline.run()
        kept = pipeline.run(keep_steps=True)
    assert plain.rsm_views == [] and len(plain.light_views) == VIEWS
    assert len(kept.rsm_views) == VIEWS
    assert np.array_equal(kept.rsm_views[0][2], plain.rsm_flux)


def test_handed_in_vpls_have_no_view(dumped, tmp_path):
    folder, _, _ = dumped
    again = tmp_path / "b.npz"
    assert main(["render", *SMALL, "--vpls", str(folder / "a.npz"), "--dump", str(again),
                 "--out", str(tmp_path / "b.png")]) == 0
    arrays = read_npz(again)
    sidecar = json.loads(again.with_suffix(".json").read_text(encoding="utf-8"))
    assert "vpl_view" not in arrays and sidecar["vpls_hand_made"] is True
    assert len(sidecar["rsm_views"]) == VIEWS           # the RSMs still render (shadows)
    assert all(e["vpls"] is None for e in sidecar["rsm_views"])
