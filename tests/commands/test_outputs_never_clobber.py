"""A command writes only the files it names: export-mitsuba's meshes and textures go into
a folder named after its output, which it owns; compare replaces in its --out folder only
the files it wrote there; a replaced file keeps its mode; every
screenshot gets a file of its own; a command stopped by INT, TERM or HUP leaves the old
set of outputs whole or the new set whole, never a mix, and nothing hidden behind."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import pytest
from command_cases import StandInPipeline

from explorer.cli import main

ROOT = Path(__file__).resolve().parents[2]
TEXTURED = ROOT / "examples" / "textured-room" / "scene.toml"


def test_export_mitsuba_never_touches_files_beside_its_output(tmp_path, capsys):
    beside = {name: f"the user's {name}" for name in
              ("texture-0.pfm", "scene.ply", "scene-t0.ply", "spot-0.pfm")}
    for name, text in beside.items():
        (tmp_path / name).write_text(text)
    out = tmp_path / "room.xml"
    assert main(["export-mitsuba", str(TEXTURED), str(out), "--size", "16x12"]) == 0, \
        capsys.readouterr().err
    for name, text in beside.items():
        assert (tmp_path / name).read_text() == text, f"{name} was overwritten"
    written = sorted(p.name for p in (tmp_path / "room-files").iterdir())
    assert "texture-0.pfm" in written and ".lpv-explorer-export" in written
    assert 'value="room-files/texture-0.pfm"' in out.read_text()


def test_export_mitsuba_refuses_a_folder_it_did_not_make(tmp_path, capsys):
    folder = tmp_path / "room-files"
    folder.mkdir()
    (folder / "scene.ply").write_text("mine")
    assert main(["export-mitsuba", "cornell", str(tmp_path / "room.xml")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "was not made by export-mitsuba" in err
    assert (folder / "scene.ply").read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["room-files"]


def test_a_second_export_replaces_its_own_files_and_removes_stale_ones(tmp_path, capsys):
    out = tmp_path / "room.xml"
    assert main(["export-mitsuba", "cornell", str(out), "--size", "8x8"]) == 0
    folder = tmp_path / "room-files"
    (folder / "spot-7.pfm").write_text("from an earlier export")
    with open(folder / ".lpv-explorer-export", "a") as listing:
        listing.write("spot-7.pfm\n../escape.txt\n")
    (tmp_path / "escape.txt").write_text("the user's")
    assert main(["export-mitsuba", "cornell", str(out), "--size", "8x8"]) == 0, \
        capsys.readouterr().err
    assert not (folder / "spot-7.pfm").exists()
    assert (tmp_path / "escape.txt").read_text() == "the user's"


def test_an_xml_and_a_py_export_of_one_name_never_share_their_files(tmp_path, capsys):
    """``room.xml`` and ``room.py`` both use ``room-files/``: the same scene twice shares
    it, another scene is refused while the first's scene file is there, and takes the
    folder over once it is gone."""
    xml, py = tmp_path / "room.xml", tmp_path / "room.py"
    assert main(["export-mitsuba", "cornell", str(xml), "--size", "8x8"]) == 0
    assert main(["export-mitsuba", "cornell", str(py), "--size", "8x8"]) == 0
    py.unlink()
    before = {p.name: p.read_bytes() for p in (tmp_path / "room-files").iterdir()}
    capsys.readouterr()
    assert main(["export-mitsuba", "single-source", str(py), "--size", "8x8"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "holds the files of" in err and "room.xml" in err, \
        err
    assert {p.name: p.read_bytes() for p in (tmp_path / "room-files").iterdir()} == before
    assert not py.exists()
    xml.unlink()
    assert main(["export-mitsuba", "single-source", str(py), "--size", "8x8"]) == 0, \
        capsys.readouterr().err


def test_a_replaced_output_keeps_its_mode_and_a_new_one_follows_the_umask(tmp_path):
    old_mask = os.umask(0o022)
    try:
        kept = tmp_path / "kept.xml"
        kept.write_text("old")
        kept.chmod(0o640)
        assert main(["export-mitsuba", "cornell", str(kept), "--size", "8x8"]) == 0
        assert kept.stat().st_mode & 0o777 == 0o640
        assert (tmp_path / "kept-files" / "scene.ply").stat().st_mode & 0o777 == 0o644
    finally:
        os.umask(old_mask)


def test_two_screenshots_in_one_second_get_two_files(tmp_path):
    from explorer.ui.state import default_screenshot_path

    first = default_screenshot_path(tmp_path)
    second = default_screenshot_path(tmp_path)          # before the first is written
    assert first != second
    second.write_bytes(b"png")
    third = default_screenshot_path(tmp_path)
    assert len({first, second, third}) == 3 and second.read_bytes() == b"png"


def test_two_windows_started_in_one_folder_never_name_one_screenshot(tmp_path):
    """Each process's presses are remembered in that process only: the name is also
    reserved on disk, so a second window (another process) pressing F12 in the same second
    gets a name of its own."""
    import subprocess
    import sys

    # both windows' clocks read the same second
    code = ("import sys, datetime; from explorer.ui import state; "
            "state.datetime = type('Clock', (), {'now': staticmethod("
            "lambda: datetime.datetime(2026, 1, 2, 3, 4, 5))}); "
            "print(state.default_screenshot_path(sys.argv[1]))")
    names = [subprocess.run([sys.executable, "-c", code, str(tmp_path)], check=True,
                            capture_output=True, text=True, cwd=ROOT).stdout.strip()
             for _ in range(2)]
    assert names == [str(tmp_path / "lpv-explorer-20260102-030405.png"),
                     str(tmp_path / "lpv-explorer-20260102-030405-2.png")]


def test_a_screenshot_that_cannot_be_written_leaves_no_empty_file(tmp_path):
    from explorer.ui.state import default_screenshot_path, release_screenshot_path

    path = default_screenshot_path(tmp_path)
    release_screenshot_path(path)
    assert not path.exists()
    mine = tmp_path / "mine.png"
    mine.write_bytes(b"")
    release_screenshot_path(mine)           # never a file it did not reserve
    assert mine.exists()


@pytest.mark.parametrize("signum, code", [(signal.SIGTERM, 143), (signal.SIGHUP, 129),
                                          (signal.SIGINT, 130)])
def test_a_signal_mid_command_leaves_the_old_outputs_whole(tmp_path, monkeypatch, capsys,
                                                          signum, code):
    monkeypatch.setattr(StandInPipeline, "on_second_view",
                        staticmethod(lambda: os.kill(os.getpid(), signum)))
    monkeypatch.setattr("explorer.lpv.pipeline.Pipeline", StandInPipeline)
    out = tmp_path / "frame.png"
    olds = {tmp_path / "frame-final.png": b"old final", tmp_path / "frame-direct.png":
            b"old direct"}
    for path, data in olds.items():
        path.write_bytes(data)
    assert main(["render", "--out", str(out), "--view", "final", "--view", "direct"]) == code
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    for path, data in olds.items():
        assert path.read_bytes() == data, f"{path.name} changed"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in olds), \
        "a hidden temporary or backup was left behind"


def test_a_signal_during_the_renames_waits_until_the_new_set_is_whole(tmp_path, monkeypatch,
                                                                      capsys):
    """SIGTERM arriving between two renames is held until all are in place."""
    import explorer.commands.options as options

    real_replace, renames = os.replace, []

    def replace_then_signal(source, target):
        real_replace(source, target)
        if not Path(target).name.startswith("."):   # an output, not a PNG being staged
            renames.append(target)
            if len(renames) == 1:
                os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(options.os, "replace", replace_then_signal)
    monkeypatch.setattr("explorer.lpv.pipeline.Pipeline", StandInPipeline)
    out = tmp_path / "frame.png"
    for view in ("final", "direct"):
        (tmp_path / f"frame-{view}.png").write_bytes(b"old")
    assert main(["render", "--out", str(out), "--view", "final", "--view", "direct"]) == 143
    capsys.readouterr()
    assert len(renames) == 2
    for view in ("final", "direct"):
        assert (tmp_path / f"frame-{view}.png").read_bytes().startswith(b"\x89PNG")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frame-direct.png",
                                                          "frame-final.png"]



COMPARE_TINY = ["--width", "16", "--height", "12", "--rsm-size", "8", "--grid-size", "8",
                "--iterations", "2", "--quiet", "--preset", "corrected"]


@pytest.mark.parametrize("name", ["table.md", "reference.png", "lpv-corrected.png"])
def test_compare_never_replaces_a_file_of_the_users_in_its_folder(tmp_path, capsys, name):
    folder = tmp_path / "cmp"
    folder.mkdir()
    (folder / name).write_text("the user's")
    (folder / "notes.txt").write_text("also the user's")
    assert main(["compare", "--out", str(folder), *COMPARE_TINY]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"holds {name}" in err and "not replaced" in err, err
    assert (folder / name).read_text() == "the user's"
    assert sorted(p.name for p in folder.iterdir()) == sorted([name, "notes.txt"])


def test_a_second_compare_replaces_the_files_it_wrote(tmp_path, capsys):
    folder = tmp_path / "cmp"
    (folder).mkdir()
    (folder / "notes.txt").write_text("the user's")
    assert main(["compare", "--out", str(folder), *COMPARE_TINY]) == 0, \
        capsys.readouterr().err
    listing = (folder / ".lpv-explorer-compare").read_text().split()
    assert "table.md" in listing and "lpv-corrected.png" in listing
    assert "notes.txt" not in listing
    (folder / "table.md").write_text("stale")
    assert main(["compare", "--out", str(folder), *COMPARE_TINY]) == 0, \
        capsys.readouterr().err
    assert (folder / "table.md").read_text().startswith("scene `cornell`")
    assert (folder / "notes.txt").read_text() == "the user's"
