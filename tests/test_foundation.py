"""Settings, grid mapping, resource lookup, the program loader and the CLI entry."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.cli import main as cli_main
from explorer.gl.context import probe
from explorer.gl.program import ShaderError, load_program
from explorer.lpv.grid import GridSpec
from explorer.lpv.settings import PRESETS, Corrections, Settings, preset
from explorer.resources import lesson_dir, shader_dir


def test_presets_differ_in_the_three_formulas_and_the_decimals():
    original, corrected = PRESETS["original"], PRESETS["corrected"]
    differing = {n for n in Corrections.names() if getattr(original, n) != getattr(corrected, n)}
    assert differing == {"injection_pi", "propagation_4pi", "reprojection_pi", "exact_constants"}
    assert corrected.as_uniforms()["u_injection_pi"] == 1
    assert original.as_uniforms()["u_injection_pi"] == 0


def test_unknown_preset_lists_the_names():
    with pytest.raises(KeyError, match="corrected"):
        preset("nope")


def test_settings_reject_bad_choices_and_accept_changes():
    with pytest.raises(ValueError, match="downsample"):
        Settings(downsample="median")
    with pytest.raises(ValueError, match="grid_size"):
        Settings(grid_size=0)
    changed = Settings().with_changes(corrections="original", grid_size=16)
    assert changed.corrections == PRESETS["original"] and changed.grid_size == 16
    flipped = Settings().with_changes(corrections={"side_faces": False})
    assert flipped.corrections.side_faces is False and flipped.corrections.injection_pi


def test_grid_mapping_round_trips_cell_centres():
    spec = GridSpec(origin=(-1.0, -2.0, 0.5), cell_size=0.25, resolution=8)
    index = np.array([[0, 0, 0], [7, 3, 5]])
    centres = spec.cell_centre(index)
    assert np.array_equal(spec.cell_index(centres), index)
    assert np.allclose(spec.grid_coords(centres), index + 0.5)
    assert spec.inside(np.array([[8, 0, 0], [7, 7, 7]])).tolist() == [False, True]


def test_enclosing_grid_contains_the_box_with_margin():
    spec = GridSpec.enclosing((0, 0, 0), (2, 1, 1), resolution=10, margin_cells=1)
    lo = spec.cell_index(np.array([0.0, 0.0, 0.0]))
    hi = spec.cell_index(np.array([2.0, 1.0, 1.0]) - 1e-9)
    assert (lo >= 1).all() and (hi <= 8).all()


def test_resources_are_found_from_the_package():
    assert (shader_dir() / "generated" / "constants.glsl").is_file()
    assert lesson_dir().is_dir()


def test_context_offers_what_the_lpv_needs(ctx):
    caps = probe(ctx)
    assert caps.missing == []
    assert caps.max_3d_texture_size >= 128


def test_loader_reports_a_missing_file(ctx):
    with pytest.raises(ShaderError, match="no shader file"):
        load_program(ctx, "does-not-exist.glsl")


def test_cli_unknown_command_fails(capsys):
    assert cli_main(["no-such-command"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("lpv-explorer: error: argument COMMAND: invalid choice")
    assert len(err.strip().splitlines()) == 1


def test_vpl_arrays_round_trip_through_textures(ctx):
    from explorer.lpv.vpl import VplArrays, VplTextures

    rng = np.random.default_rng(1)
    normals = rng.normal(size=(5, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    vpls = VplArrays(rng.random((5, 3)), normals, rng.random((5, 3)), rng.random(5) + 1,
                     texel_area=4 / 64**2)
    textures = VplTextures.from_arrays(ctx, vpls)
    back = textures.to_arrays()
    textures.release()
    assert np.allclose(back.positions, vpls.positions, atol=1e-6)
    assert np.allclose(back.depth, vpls.depth, atol=1e-6)
    assert np.allclose(vpls.surfel_area(True) / vpls.surfel_area(False), vpls.depth)


def test_vpl_arrays_reject_bad_shapes():
    from explorer.lpv.vpl import VplArrays

    with pytest.raises(ValueError, match=r"shape \(M, 3\)"):
        VplArrays(np.zeros((4, 2)), np.zeros((4, 3)), np.zeros((4, 3)), np.zeros(4), 1.0)


def test_a_headless_context_made_and_released_restores_the_callers_context(ctx):
    """A command or Pipeline that opens and releases its own context (e.g. a CLI call in a
    test or a notebook) must leave the caller's context current and working."""
    from explorer.gl.context import create_headless_context, release_headless_context
    from explorer.gl.egl import current_egl

    before = current_egl()
    assert before is not None
    own = create_headless_context()
    assert current_egl() != before
    release_headless_context(own)
    assert current_egl() == before
    texture = ctx.texture((2, 2), 4, dtype="f4")
    texture.write(np.ones((2, 2, 4), np.float32).tobytes())
    assert np.frombuffer(texture.read(), np.float32).tolist() == [1.0] * 16
    texture.release()


def test_cli_output_into_a_closed_pipe_ends_quietly():
    """`lpv-explorer constants | head -1`: no BrokenPipeError traceback."""
    import subprocess
    import sys

    reader = subprocess.Popen([sys.executable, "-c", "pass"], stdin=subprocess.PIPE)
    reader.wait(timeout=30)            # the read end is gone: every write hits EPIPE
    writer = subprocess.run([sys.executable, "-m", "explorer", "constants"],
                            stdout=reader.stdin, stderr=subprocess.PIPE, timeout=120)
    reader.stdin.close()
    assert b"Traceback" not in writer.stderr, writer.stderr.decode()
    assert writer.returncode == 13
