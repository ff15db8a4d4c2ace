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
SHORT_BUDGET_S, SHORT_CASES = 1.0, 15
"""The budget of the fuzzing of each file a mesh names and of the npz reader, and the
cases each runs however long they take (many small targets; the bad files named inside
files are also tried one by one, below)."""
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
         clear_errors: tuple[type[BaseException], ...], budget_s: float = BUDGET_S,
         min_cases: int = 0) -> int:
    """Run mutated copies of ``seed_bytes`` through ``read(path)`` for ``budget_s``
    seconds (but at least ``min_cases`` cases, however busy the machine); returns the
    cases run. A clear error is one of ``clear_errors`` with a one-line, non-empty
    message."""
    started, cases = time.monotonic(), 0
    previous = signal.signal(signal.SIGALRM, _alarm)
    try:
        while cases < min_cases or (cases < MAX_CASES
                                    and time.monotonic() - started < budget_s):
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


# --- binary loaders and the files named inside files -------------------------------------

def test_fuzz_an_npz(tmp_path):
    """``--vpls``, ``--grid0``, ``diff``: mutated archives, headers and zip directories
    included, end in a clear error or a load, never in a big allocation or a hang."""
    import numpy as np

    from explorer.exchange.files import FileFormatError, read_npz

    seed = tmp_path / "seed.npz"
    np.savez(seed, vpl_position=np.zeros((16, 3), np.float32),
             vpl_flux=np.ones((16, 3), np.float32), grid_0=np.zeros((3, 2, 2, 2, 4)))
    path = tmp_path / "mutated.npz"
    assert fuzz(seed.read_bytes(), path, read_npz, (FileFormatError,), SHORT_BUDGET_S,
                SHORT_CASES) >= SHORT_CASES


def _textured_obj(folder: Path) -> dict[str, Path]:
    """An OBJ naming a material library naming a PNG texture; the three paths."""
    import numpy as np
    from PIL import Image

    Image.fromarray(np.full((8, 8, 3), 180, np.uint8)).save(folder / "tex.png")
    (folder / "m.mtl").write_text("newmtl a\nKd 1 1 1\nmap_Kd tex.png\n")
    (folder / "m.obj").write_text("mtllib m.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                  "vt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n")
    return {"obj": folder / "m.obj", "mtl": folder / "m.mtl", "png": folder / "tex.png"}


def _gltf(folder: Path) -> dict[str, Path]:
    """A glTF triangle whose positions are in an external buffer and which names a PNG."""
    import json

    import numpy as np
    from PIL import Image

    np.float32([0, 0, 0, 1, 0, 0, 0, 1, 0]).tofile(folder / "data.bin")
    Image.fromarray(np.full((8, 8, 3), 180, np.uint8)).save(folder / "img.png")
    header = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
              "nodes": [{"mesh": 0}],
              "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
              "buffers": [{"uri": "data.bin", "byteLength": 36}],
              "bufferViews": [{"buffer": 0, "byteLength": 36}],
              "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3,
                             "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
              "images": [{"uri": "img.png"}]}
    (folder / "m.gltf").write_text(json.dumps(header))
    return {"gltf": folder / "m.gltf", "bin": folder / "data.bin", "png": folder / "img.png"}


def _load_or_clear(main: Path) -> None:
    """``load_scene(main)`` loads (its warnings one line each) or is a clear SceneError."""
    from explorer.scene import SceneError, load_scene

    try:
        scene = load_scene(main)
    except SceneError:
        raise
    for warning in scene.warnings:
        assert warning and "\n" not in warning, warning


def _textured_ply(folder: Path) -> dict[str, Path]:
    """An ASCII PLY triangle with texture coordinates naming a PNG (``TextureFile``)."""
    import numpy as np
    from PIL import Image

    Image.fromarray(np.full((8, 8, 3), 180, np.uint8)).save(folder / "tex.png")
    (folder / "m.ply").write_text(
        "ply\nformat ascii 1.0\ncomment TextureFile tex.png\nelement vertex 3\n"
        "property float x\nproperty float y\nproperty float z\nproperty float s\n"
        "property float t\nelement face 1\nproperty list uchar int vertex_indices\n"
        "end_header\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n")
    return {"ply": folder / "m.ply", "png": folder / "tex.png"}


NAMED = [(_textured_obj, "obj", "mtl"), (_textured_obj, "obj", "png"),
         (_gltf, "gltf", "gltf"), (_gltf, "gltf", "bin"), (_gltf, "gltf", "png"),
         (_textured_ply, "ply", "png")]
"""(how the files are made, the file loaded, the file damaged)."""

@pytest.mark.parametrize("make, main, named", NAMED)
def test_fuzz_the_files_a_mesh_names(tmp_path, make, main, named):
    """Each file an OBJ or a glTF names (material library, texture, buffer, image), and
    the glTF itself, mutated in place beside the others."""
    from explorer.scene import SceneError

    paths = make(tmp_path)
    seed = paths[named].read_bytes()
    cases = fuzz(seed, paths[named], lambda _: _load_or_clear(paths[main]), (SceneError,),
                 SHORT_BUDGET_S, SHORT_CASES)
    assert cases >= SHORT_CASES


def _bad_file(path: Path, kind: str) -> None:
    """Replace ``path`` with a bad file of ``kind``."""
    import os
    import struct
    import zlib

    data = path.read_bytes()
    path.unlink()
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "device":
        os.symlink("/dev/zero", path)
    elif kind == "loop":        # a symbolic link to itself
        os.symlink(path.name, path)
    elif kind == "folder":
        path.mkdir()
    elif kind == "truncated":
        path.write_bytes(data[:len(data) // 3])
    elif kind == "cut pixels":  # the header whole, the pixel data cut in half
        import io

        import numpy as np
        from PIL import Image

        noise = np.random.default_rng(0).integers(0, 256, (64, 64, 3), dtype=np.uint8)
        encoded = io.BytesIO()
        Image.fromarray(noise).save(encoded, "PNG")
        path.write_bytes(encoded.getvalue()[:len(encoded.getvalue()) // 2])
    elif kind == "header lie":
        if data.startswith(b"\x89PNG"):
            lie = bytearray(data)
            lie[16:24] = struct.pack(">II", 200_000, 200_000)
            lie[29:33] = struct.pack(">I", zlib.crc32(bytes(lie[12:29])))
            path.write_bytes(bytes(lie))
        else:
            path.write_bytes(data.replace(b'"byteLength": 36', b'"byteLength": 3600000000')
                             .replace(b'"count": 3', b'"count": 300000000000'))
    else:                       # a huge claim: a sparse file far over every cap
        with open(path, "wb") as handle:
            handle.truncate(600 * 1024 * 1024)


BAD_KINDS = ("fifo", "device", "loop", "folder", "truncated", "cut pixels", "header lie",
             "huge")


@pytest.mark.parametrize("make, main, named, kind", [
    (*case, kind) for case in NAMED for kind in BAD_KINDS
    # a material library and a raw buffer have no header to lie in; only images have pixels
    if not (kind == "header lie" and case[2] in ("mtl", "bin"))
    and not (kind == "cut pixels" and case[2] != "png")])
def test_a_bad_file_named_inside_a_file_is_one_line_naming_it(tmp_path, no_hang, make, main,
                                                              named, kind):
    """A FIFO, a device, a loop of symbolic links, a folder, a truncated file, a header
    that lies or a file far over its cap, wherever a mesh names it: a one-line error
    naming it, or the mesh loaded and a
    warning naming it (a texture), within seconds."""
    from explorer.scene import SceneError, load_scene

    paths = make(tmp_path)
    _bad_file(paths[named], kind)
    try:
        scene = load_scene(paths[main])
    except SceneError as exc:
        said = [str(exc)]
    else:
        said = list(scene.warnings)
        if kind == "truncated" and named == "mtl":
            return              # a shorter material library is still a material library
        assert said, f"{named} as {kind}: loaded without a word"
    assert all("\n" not in line for line in said)
    assert any(paths[named].name in line for line in said), said
