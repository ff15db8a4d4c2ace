"""Fuzzing every reader of a user's file: random mutations of the shipped files (and of
small meshes made here) for a bounded time each. Every run must end in a valid load or
in the reader's own one-line error, never another exception and never a hang.

The mutations are seeded (the failing seed is in the message, so a failure reproduces);
each reader gets at most :data:`BUDGET_S` seconds and :data:`MAX_CASES` cases."""

from __future__ import annotations

import random
import signal
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from explorer.resources import lesson_dir

BUDGET_S = 4.0
MAX_CASES = 300

_TOKENS = [b"[", b"]", b"{", b"}", b"=", b"\"", b"'", b"\n", b"#", b"\\", b"\0", b"\xff",
           b"1e999", b"-1", b"nan", b"inf", b"99999999999999999999", b"[[", b"{{", b"}}",
           b"$", b"\\frac{", b"true", b"null", b":", b",", b".", b"f 1 2 3\n", b"v 1e38 0 0\n"]


def mutate(data: bytes, rng: random.Random) -> bytes:
    """One to four random edits: flip, insert, delete, duplicate, truncate, a token."""
    data = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        where = rng.randrange(len(data) + 1)
        kind = rng.randrange(7)
        if kind == 0 and data:
            data[min(where, len(data) - 1)] ^= 1 << rng.randrange(8)
        elif kind == 1:
            data[where:where] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        elif kind == 2:
            del data[where:where + rng.randint(1, 64)]
        elif kind == 3:
            span = data[where:where + rng.randint(1, 200)]
            data[where:where] = span * rng.randint(1, 20)
        elif kind == 4:
            del data[where:]
        else:
            data[where:where] = rng.choice(_TOKENS) * rng.choice((1, 1, 2, 50, 2000))
    return bytes(data)


def _alarm(signum, frame):
    raise TimeoutError("the reader hung")


def fuzz(seed_bytes: bytes, path: Path, read: Callable[[Path], object],
         clear_errors: tuple[type[BaseException], ...]) -> int:
    """Run mutated copies of ``seed_bytes`` through ``read(path)``; returns the cases run.
    A clear error is one of ``clear_errors`` with a one-line, non-empty message."""
    started, cases = time.monotonic(), 0
    previous = signal.signal(signal.SIGALRM, _alarm)
    try:
        while cases < MAX_CASES and time.monotonic() - started < BUDGET_S:
            rng = random.Random(cases)
            path.write_bytes(mutate(seed_bytes, rng))
            signal.alarm(10)
            try:
                read(path)
            except clear_errors as exc:
                text = str(exc)
                assert text and "\n" not in text.strip(), \
                    f"seed {cases}: an error message of several lines: {text!r}"
            except Exception as exc:  # noqa: BLE001 - the point of the test
                raise AssertionError(f"seed {cases}: {type(exc).__name__}: {exc}") from exc
            finally:
                signal.alarm(0)
            cases += 1
    finally:
        signal.signal(signal.SIGALRM, previous)
    return cases


def test_fuzz_the_settings_file(tmp_path):
    from explorer.ui import persist
    from explorer.ui.state import AppState

    seed = tmp_path / "seed.json"
    persist.save_state(AppState(), seed)
    path = tmp_path / "settings.json"

    def read(p: Path) -> None:
        message = persist.load_state(AppState(), p)
        assert message is None or "\n" not in message, message

    assert fuzz(seed.read_bytes(), path, read, ()) > 20


def test_fuzz_the_layout_file(tmp_path):
    from explorer.ui import persist

    seed = (Path(__file__).parent / "data" / "imgui.ini")
    data = seed.read_bytes() if seed.is_file() else _layout_seed()
    path = tmp_path / "imgui.ini"

    def read(p: Path) -> None:
        message = persist.check_layout_file(p)
        assert message is None or "\n" not in message, message

    assert fuzz(data, path, read, ()) > 20


def _layout_seed() -> bytes:
    return (b"[Window][Lesson]\nPos=0,19\nSize=420,941\nCollapsed=0\nDockId=0x00000001,0\n\n"
            b"[Window][View]\nPos=422,19\nSize=800,941\nCollapsed=0\nDockId=0x00000002,0\n\n"
            b"[Docking][Data]\nDockSpace ID=0x8B93E3BD Window=0xA787BDB4 Pos=0,19 "
            b"Size=1600,941 Split=X\n  DockNode ID=0x00000001 Parent=0x8B93E3BD "
            b"SizeRef=420,941 Selected=0x1\n  DockNode ID=0x00000002 Parent=0x8B93E3BD "
            b"SizeRef=1178,941 CentralNode=1\n")


@pytest.mark.parametrize("lesson", sorted(p.name for p in lesson_dir().glob("*.toml"))[:15:4])
def test_fuzz_a_lesson(tmp_path, lesson):
    from explorer.lessons import LessonError, load_lesson

    data = (lesson_dir() / lesson).read_bytes()
    path = tmp_path / lesson
    assert fuzz(data, path, load_lesson, (LessonError,)) > 10


@pytest.mark.parametrize("suffix", [".obj", ".ply", ".stl", ".glb"])
def test_fuzz_a_mesh(tmp_path, suffix):
    import trimesh

    from explorer.scene import SceneError, load_scene

    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    seed = tmp_path / f"seed{suffix}"
    box.export(seed)
    path = tmp_path / f"mesh{suffix}"
    assert fuzz(seed.read_bytes(), path, load_scene, (SceneError,)) > 10


def test_fuzz_a_scene_file(tmp_path):
    """The shipped example scene file, mutated, beside its mesh (docs/SCENES.md)."""
    import shutil

    from explorer.scene import SceneError, load_scene

    example = Path(__file__).resolve().parent.parent / "examples" / "textured-room"
    shutil.copy(example / "room.glb", tmp_path / "room.glb")
    path = tmp_path / "scene.toml"
    assert fuzz((example / "scene.toml").read_bytes(), path, load_scene, (SceneError,)) > 10
