"""Every file the explorer reads is opened safely and every file it writes can fail
cleanly: FIFOs, devices and folders refused at once, size and nesting caps named in the
message, decompression bombs stopped, unique temporaries, nothing of the user's lost.

A FIFO test that hangs would hang the suite: each runs under an alarm that fails it."""

from __future__ import annotations

import bz2
import json
import os
import subprocess
import sys
import threading
import zipfile
from pathlib import Path

import pytest

from explorer import safe_files
from explorer.safe_files import UserFileError

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture
def fifo(tmp_path):
    path = tmp_path / "pipe"
    os.mkfifo(path)
    return path


def test_only_regular_files_are_read(tmp_path, fifo, no_hang):
    with pytest.raises(UserFileError, match="is a FIFO, not a lesson file"):
        safe_files.read_bytes(fifo, "lesson")
    with pytest.raises(UserFileError, match="is a device"):
        safe_files.read_bytes("/dev/zero", "settings file")
    with pytest.raises(UserFileError, match="is a folder"):
        safe_files.read_bytes(tmp_path, "scene file")
    with pytest.raises(UserFileError, match="cannot read the mesh .No such file"):
        safe_files.read_bytes(tmp_path / "missing.obj", "mesh")
    dangling = tmp_path / "link"
    dangling.symlink_to(tmp_path / "nowhere")
    with pytest.raises(UserFileError, match="cannot read"):
        safe_files.read_bytes(dangling, "lesson")


def test_the_refusals_name_the_kind_of_file_in_good_english(tmp_path, fifo, no_hang):
    """"an array file", never "a array file file"; "an export listing file"."""
    with pytest.raises(UserFileError, match=r"is a FIFO, not an array file$"):
        safe_files.read_bytes(fifo, "array file")
    with pytest.raises(UserFileError, match=r"is a device, not an export listing file$"):
        safe_files.read_bytes("/dev/zero", "export listing")
    big = tmp_path / "big.npz"
    big.write_bytes(b"0" * 2048)
    with pytest.raises(UserFileError, match=r"over the 1 KB an array file may have$"):
        safe_files.read_bytes(big, "array file", cap=1024)


def test_a_file_just_over_its_cap_never_reads_as_the_cap(tmp_path):
    """1.4 MB over a 1 MB cap is "1.5 MB, over the 1 MB", not "1 MB, over the 1 MB"."""
    big = tmp_path / "imgui.ini"
    big.write_bytes(b"#" * int(1.44 * 1024 * 1024))
    with pytest.raises(UserFileError, match=r"is 1.5 MB, over the 1 MB a layout file may"):
        safe_files.read_text(big, "layout file")


def test_sizes_are_capped_with_the_cap_in_the_message(tmp_path):
    big = tmp_path / "big.toml"
    big.write_bytes(b"#" * (300 * 1024))
    with pytest.raises(UserFileError, match=r"300 KB, over the 256 KB a lesson may have"):
        safe_files.read_text(big, "lesson")
    assert safe_files.read_text(big, "lesson", cap=400 * 1024).startswith("#")


def test_a_stray_byte_is_named_by_its_line(tmp_path):
    path = tmp_path / "x.json"
    path.write_bytes(b'{\n"a":\n"caf\xe9"}')
    with pytest.raises(UserFileError, match=r"x.json:3: the settings file is not UTF-8 "
                                            r"text \(byte 0xe9\)"):
        safe_files.read_text(path, "settings file")


@pytest.mark.parametrize("text", ["[" * 100_000 + "]" * 100_000,
                                  '{"a":' * 5000 + "1" + "}" * 5000,
                                  "[" * 40 + "]" * 40])
def test_deep_json_is_refused_not_a_recursion_error(text):
    with pytest.raises(UserFileError, match="nests deeper than the 32 levels"):
        safe_files.parse_json(text, "settings.json")


def test_deep_toml_is_refused_not_a_recursion_error():
    deep = "a = " + "[" * 5000 + "]" * 5000
    with pytest.raises(UserFileError, match="nests deeper"):
        safe_files.parse_toml(deep, "lesson.toml")
    assert safe_files.parse_toml("a = [[1, 2], [3]]", "x") == {"a": [[1, 2], [3]]}


def test_the_shipped_files_are_within_every_cap():
    from explorer.resources import lesson_dir, shader_dir

    for path in lesson_dir().glob("*.toml"):
        safe_files.parse_toml(safe_files.read_text(path, "lesson"), path)
    for path in shader_dir().rglob("*.glsl"):
        safe_files.read_text(path, "shader")


def test_writes_use_a_unique_temporary_and_leave_a_user_file_of_that_name_alone(tmp_path):
    from explorer.commands.options import Outputs

    target = tmp_path / "shot.png"
    users_own = tmp_path / ".shot.partial.png"       # a predictable temporary name
    users_own.write_text("mine")
    with Outputs() as outputs:
        outputs.write(outputs.file(target), lambda p: p.write_bytes(b"png"))
    assert target.read_bytes() == b"png" and users_own.read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == [".shot.partial.png", "shot.png"]


def test_an_interrupt_between_two_outputs_puts_the_users_files_back(tmp_path):
    from explorer.commands.options import Outputs

    first, second, third = (tmp_path / f"{name}.png" for name in ("a", "b", "c"))
    first.write_text("old a")
    second.write_text("old b")
    with pytest.raises(KeyboardInterrupt):
        with Outputs() as outputs:
            outputs.write(outputs.file(first), lambda p: p.write_text("new a"))
            outputs.write(outputs.file(third), lambda p: p.write_text("new c"))
            assert first.read_text() == "old a"     # nothing changes before the end
            raise KeyboardInterrupt        # Ctrl-C before b is written
    assert first.read_text() == "old a" and second.read_text() == "old b"
    assert not third.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png", "b.png"]


def test_a_full_disk_is_one_line_and_leaves_nothing(tmp_path):
    from explorer.commands.options import CommandError, Outputs

    def full(path):
        path.write_bytes(b"half")
        raise OSError(28, "No space left on device")

    target = tmp_path / "x.png"
    target.write_text("before")
    with pytest.raises(CommandError, match=r"cannot write .*x.png: No space left on device"):
        with Outputs() as outputs:
            outputs.write(outputs.file(target), full)
    assert target.read_text() == "before"
    assert [p.name for p in tmp_path.iterdir()] == ["x.png"]


def test_a_name_longer_than_the_file_system_allows_is_refused_up_front(tmp_path):
    from explorer.commands.options import CommandError, Outputs

    with pytest.raises(CommandError, match="the file name is 304 bytes long, over the 255"):
        Outputs().file(tmp_path / ("n" * 300 + ".png"))


def test_two_windows_saving_settings_at_once_never_show_an_empty_file(tmp_path):
    from explorer.ui import persist
    from explorer.ui.state import AppState

    path = tmp_path / "settings.json"
    persist.save_state(AppState(), path)
    failures: list[BaseException] = []
    stop = threading.Event()

    def save():
        try:
            for _ in range(150):
                persist.save_state(AppState(), path)
        except BaseException as exc:  # noqa: BLE001 - collected and asserted below
            failures.append(exc)

    def read():
        while not stop.is_set():
            try:
                json.loads(path.read_text())
            except BaseException as exc:  # noqa: BLE001
                failures.append(exc)
                return

    reader = threading.Thread(target=read)
    reader.start()
    writers = [threading.Thread(target=save) for _ in range(2)]
    for thread in writers:
        thread.start()
    for thread in writers:
        thread.join()
    stop.set()
    reader.join()
    assert failures == []
    assert [p.name for p in tmp_path.iterdir()] == ["settings.json"]


def test_settings_and_layout_files_that_are_fifos_or_nest_deeply_are_set_aside(
        tmp_path, no_hang):
    from explorer.ui import persist
    from explorer.ui.state import AppState

    settings = tmp_path / "settings.json"
    os.mkfifo(settings)
    message = persist.load_state(AppState(), settings)
    assert "is a FIFO" in message and "moved it to settings.json.bad-" in message
    assert message.count(str(settings)) == 1, f"the file named twice: {message}"
    settings.write_text('{"format": 1, "x": ' + "[" * 3000 + "]" * 3000 + "}")
    message = persist.load_state(AppState(), settings)
    assert "nests deeper" in message and not settings.exists()
    layout = tmp_path / "imgui.ini"
    os.mkfifo(layout)
    text, problem = persist.load_layout(layout)
    assert text is None and "is a FIFO" in problem


def test_a_config_folder_that_cannot_be_made_means_running_without_saving(tmp_path,
                                                                         monkeypatch):
    from explorer.ui import persist

    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.setenv("XDG_CONFIG_HOME", str(blocker))
    message = persist.writable_config_dir()
    assert "Not a directory" in message and "running without saving settings" in message
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "fine"))
    assert persist.writable_config_dir() is None
    assert (tmp_path / "fine" / "lpv-explorer").is_dir()
    assert list((tmp_path / "fine" / "lpv-explorer").iterdir()) == []


def test_lessons_that_are_fifos_nest_deeply_or_ask_for_huge_widths_are_refused(
        tmp_path, fifo, no_hang):
    from explorer.lessons import LessonError, load_lesson

    with pytest.raises(LessonError, match="FIFO"):
        load_lesson(fifo, check_formula=None)
    deep = tmp_path / "deep.toml"
    deep.write_text("x = " + "[" * 4000 + "]" * 4000 + "\n")
    with pytest.raises(LessonError, match="nests deeper"):
        load_lesson(deep, check_formula=None)
    shipped = (ROOT / "lessons" / "01-overview.toml").read_text(encoding="utf-8")
    wide = tmp_path / "01-overview.toml"
    wide.write_text(_with_wide_number(shipped), encoding="utf-8")
    with pytest.raises(LessonError, match="more than 40 columns"):
        load_lesson(wide)


def _with_wide_number(text: str) -> str:
    """The first live number of ``text`` given a billion-column format."""
    import re

    match = re.search(r"\{\{(audit|settings|frame|derived)\.([\w.]+)(:[^}]*)?\}\}", text)
    return text[:match.start()] + "{{" + match.group(1) + "." + match.group(2) + \
        ":>1000000000}}" + text[match.end():]


def test_format_values_never_print_a_gigantic_field():
    from explorer.lessons.live_values import format_value

    assert len(format_value(1.5, ">1000000000")) < 10


def test_a_compressed_mesh_that_unpacks_past_the_cap_is_refused(tmp_path, monkeypatch):
    from explorer.scene import SceneError, load_scene, mesh_limits

    monkeypatch.setattr(mesh_limits, "MAX_UNPACKED_BYTES", 1024 * 1024)
    bomb = tmp_path / "bomb.stl.bz2"
    bomb.write_bytes(bz2.compress(b"\0" * (3 * 1024 * 1024)))
    assert bomb.stat().st_size < 1000
    with pytest.raises(SceneError, match="unpacks to more than 1 MB"):
        load_scene(bomb)
    archive = tmp_path / "bomb.zip"
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as out:
        out.writestr("a.obj", b"#" * (3 * 1024 * 1024))
    with pytest.raises(SceneError, match="unpacks to more than 1 MB"):
        load_scene(archive)


def test_a_mesh_that_is_a_fifo_is_refused_at_once(fifo, no_hang):
    from explorer.scene import SceneError, load_scene

    target = fifo.with_suffix(".obj")
    os.rename(fifo, target)
    with pytest.raises(SceneError, match="not a file|FIFO"):
        load_scene(target)


@pytest.mark.parametrize("redirect, reason", [(">/dev/full", "No space left on device"),
                                              (">&-", "standard output is closed")])
def test_standard_output_full_or_closed_is_one_line_and_exit_1(redirect, reason):
    command = f"{sys.executable} -m explorer lessons {redirect}"
    done = subprocess.run(["bash", "-c", command], cwd=ROOT, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 1
    lines = done.stderr.strip().splitlines()
    assert lines == [f"lpv-explorer lessons: error: cannot write to standard output: "
                     f"{reason}"], done.stderr


def test_ctrl_c_between_two_views_of_one_render_keeps_the_users_files(tmp_path, monkeypatch,
                                                                      capsys):
    """The real render command, interrupted while it writes its second view: both files
    that were there before hold what they held, and nothing else is left."""
    from explorer.cli import main
    from explorer.commands import render

    first, second = tmp_path / "shot-final.png", tmp_path / "shot-direct.png"
    first.write_bytes(b"the user's final")
    second.write_bytes(b"the user's direct")
    real = render.write_png
    calls = []

    def interrupted(image, path, **kwargs):
        calls.append(path)
        if len(calls) == 2:
            raise KeyboardInterrupt
        real(image, path, **kwargs)

    monkeypatch.setattr(render, "write_png", interrupted)
    code = main(["render", "--grid", "8", "--iterations", "2", "--rsm-size", "32",
                 "--size", "64x48", "--view", "final", "--view", "direct",
                 "--out", str(tmp_path / "shot.png")])
    assert code == 130 and len(calls) == 2
    assert first.read_bytes() == b"the user's final"
    assert second.read_bytes() == b"the user's direct"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["shot-direct.png", "shot-final.png"]


def test_a_window_screenshot_onto_a_full_disk_is_a_message_not_a_crash(tmp_path,
                                                                       monkeypatch):
    from window_cases import display_problem

    problem = display_problem()
    if problem is not None:
        pytest.skip(str(problem))
    from PIL import Image

    from explorer.ui.app import App
    from explorer.ui.state import AppState
    from explorer.ui.window_options import WindowOptions

    def full(self, fp, format=None, **params):
        Path(fp).write_bytes(b"half a png")
        raise OSError(28, "No space left on device")

    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "config"))
    app = App(AppState(), WindowOptions(width=640, height=480, visible=False, vsync=False,
                                        persist_settings=False, pipeline_class=None))
    try:
        app.frame()
        monkeypatch.setattr(Image.Image, "save", full)
        app.state.requests.screenshot = tmp_path / "shots" / "full.png"
        app.frame()
        app.frame()
        errors = [m.text for m in app.state.messages if m.level == "error"]
        assert any("No space left on device" in text for text in errors), errors
    finally:
        app.close()
    assert list((tmp_path / "shots").iterdir()) == []


def test_a_lesson_too_large_to_draw_fluidly_is_refused_with_the_cap(tmp_path):
    from explorer.lessons import MAX_STEP_TEXT, LessonError, load_lesson

    shipped = (ROOT / "lessons" / "01-overview.toml").read_text(encoding="utf-8")
    long_step = tmp_path / "01-overview.toml"
    marker = "text = '''"
    assert marker in shipped
    long_step.write_text(shipped.replace(marker, marker + "word " * (MAX_STEP_TEXT // 4), 1),
                         encoding="utf-8")
    with pytest.raises(LessonError, match=f"over the {MAX_STEP_TEXT} one step may have"):
        load_lesson(long_step)


def test_the_window_starts_with_fifos_for_its_settings_and_layout(tmp_path, monkeypatch,
                                                                  no_hang):
    """settings.json and imgui.ini both FIFOs: the window opens (no wait), says once that
    each was set aside, and saves real files when it closes."""
    from window_cases import display_problem

    problem = display_problem()
    if problem is not None:
        pytest.skip(str(problem))
    from explorer.ui.app import App
    from explorer.ui.window_options import WindowOptions

    config = tmp_path / "config" / "lpv-explorer"
    config.mkdir(parents=True)
    os.mkfifo(config / "settings.json")
    os.mkfifo(config / "imgui.ini")
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "config"))
    app = App(None, WindowOptions(width=640, height=480, visible=False, vsync=False,
                                  pipeline_class=None))
    try:
        app.frame()
        warnings = [m.text for m in app.state.messages if m.level == "warning"]
        assert sum("is a FIFO" in text for text in warnings) == 2, warnings
    finally:
        app.close()
    assert (config / "settings.json").is_file() and (config / "imgui.ini").is_file()


def test_the_window_starts_when_its_config_folder_cannot_be_made(tmp_path, monkeypatch):
    from window_cases import display_problem

    problem = display_problem()
    if problem is not None:
        pytest.skip(str(problem))
    from explorer.ui.app import App
    from explorer.ui.window_options import WindowOptions

    blocker = tmp_path / "not-a-folder"
    blocker.write_text("")
    monkeypatch.setenv("XDG_CONFIG_HOME", str(blocker))
    app = App(None, WindowOptions(width=640, height=480, visible=False, vsync=False,
                                  pipeline_class=None))
    try:
        app.frame()
        warnings = [m.text for m in app.state.messages if m.level == "warning"]
        assert any("running without saving settings" in text for text in warnings)
    finally:
        app.close()
    assert blocker.is_file()


def test_a_folder_that_vanishes_mid_write_is_one_line(tmp_path):
    import shutil

    from explorer.commands.options import CommandError, Outputs

    folder = tmp_path / "out"

    def vanish(path):
        path.write_bytes(b"png")
        shutil.rmtree(folder)

    with pytest.raises(CommandError, match=r"cannot write .*x.png: No such file"):
        with Outputs() as outputs:
            outputs.write(outputs.file(folder / "x.png"), vanish)
    assert list(tmp_path.iterdir()) == []
