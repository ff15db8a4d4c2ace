"""The files a mesh names (OBJ ``mtllib``/``map_Kd``, glTF buffers and image ``uri``, a
PLY's texture) go through the safe reader: a FIFO is refused at once, never waited on; a
damaged or oversized texture is a warning naming it and the mesh is drawn without it; a
glTF whose layout claims more bytes than its buffers hold is one line naming the file."""

from __future__ import annotations

import json
import os
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest
import trimesh
from PIL import Image

from explorer.scene import SceneError, load_scene

TRIANGLE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n"


pytestmark = pytest.mark.usefixtures("no_hang")     # a FIFO would block forever


def textured_obj(folder: Path, texture: str = "tex.png") -> Path:
    (folder / "m.mtl").write_text(f"newmtl a\nKd 1 1 1\nmap_Kd {texture}\n")
    path = folder / "m.obj"
    path.write_text("mtllib m.mtl\nusemtl a\n" + TRIANGLE_OBJ)
    return path


def test_a_fifo_named_as_material_library_is_refused_not_waited_on(tmp_path):
    os.mkfifo(tmp_path / "fifo.mtl")
    path = tmp_path / "m.obj"
    path.write_text("mtllib fifo.mtl\n" + TRIANGLE_OBJ)
    scene = load_scene(path)
    assert len(scene.warnings) == 1
    assert "fifo.mtl" in scene.warnings[0] and "FIFO" in scene.warnings[0]


def test_a_fifo_named_as_texture_is_a_warning(tmp_path):
    os.mkfifo(tmp_path / "tex.png")
    scene = load_scene(textured_obj(tmp_path))
    assert scene.textures == ()
    assert any("tex.png" in w and "FIFO" in w for w in scene.warnings), scene.warnings


def test_a_missing_texture_is_a_warning_naming_it(tmp_path):
    scene = load_scene(textured_obj(tmp_path, "gone.png"))
    assert scene.textures == ()
    assert any("gone.png" in w and "no such file" in w for w in scene.warnings)


def test_a_truncated_png_texture_is_a_warning_not_a_traceback(tmp_path):
    Image.fromarray(np.full((64, 64, 3), 200, np.uint8)).save(tmp_path / "full.png")
    data = (tmp_path / "full.png").read_bytes()
    (tmp_path / "tex.png").write_bytes(data[:len(data) // 2])
    scene = load_scene(textured_obj(tmp_path))
    assert scene.textures == ()
    assert len(scene.warnings) == 1 and "tex.png" in scene.warnings[0], scene.warnings
    assert "\n" not in scene.warnings[0]


def test_a_png_claiming_too_many_pixels_is_refused_before_decoding(tmp_path):
    Image.fromarray(np.zeros((2, 2, 3), np.uint8)).save(tmp_path / "small.png")
    data = bytearray((tmp_path / "small.png").read_bytes())
    data[16:24] = struct.pack(">II", 100_000, 100_000)     # IHDR width and height
    data[29:33] = struct.pack(">I", zlib.crc32(bytes(data[12:29])))   # and its CRC
    (tmp_path / "tex.png").write_bytes(bytes(data))
    scene = load_scene(textured_obj(tmp_path))
    assert scene.textures == ()
    assert any("tex.png" in w and "pixels" in w for w in scene.warnings), scene.warnings


def _gltf(tmp_path: Path, buffer_uri: str, image_uri: str | None = None,
          count: int = 3, byte_length: int = 36) -> Path:
    header = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"uri": buffer_uri, "byteLength": byte_length}],
        "bufferViews": [{"buffer": 0, "byteLength": byte_length}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": count,
                       "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
    }
    if image_uri is not None:
        header["images"] = [{"uri": image_uri}]
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps(header))
    return path


def test_a_gltf_buffer_that_is_a_fifo_is_one_line(tmp_path):
    os.mkfifo(tmp_path / "data.bin")
    with pytest.raises(SceneError, match=r"data\.bin: is a FIFO") as error:
        load_scene(_gltf(tmp_path, "data.bin"))
    assert "\n" not in str(error.value)


def test_a_gltf_image_uri_that_is_a_fifo_is_a_warning(tmp_path):
    np.float32([0, 0, 0, 1, 0, 0, 0, 1, 0]).tofile(tmp_path / "data.bin")
    os.mkfifo(tmp_path / "tex.png")
    scene = load_scene(_gltf(tmp_path, "data.bin", image_uri="tex.png"))
    assert len(scene.positions) == 3
    assert any("tex.png" in w for w in scene.warnings), scene.warnings


@pytest.mark.parametrize("count, byte_length, claim", [
    (10**11, 36, "accessors claim more"),          # 1.2 TB of positions from 36 bytes
    (4, 36, "accessor 0 claims 4 items"),          # one more than the buffer holds
    (3, 10**9, r"buffer 0 \(data\.bin\) claims 1000000000 bytes"),  # its length lies
])
def test_a_gltf_whose_layout_claims_more_than_its_buffer_is_refused(tmp_path, count,
                                                                     byte_length, claim):
    np.float32([0, 0, 0, 1, 0, 0, 0, 1, 0]).tofile(tmp_path / "data.bin")
    with pytest.raises(SceneError, match=claim):
        load_scene(_gltf(tmp_path, "data.bin", count=count, byte_length=byte_length))


def test_a_glb_whose_header_claims_more_than_the_file_is_refused(tmp_path):
    seed = tmp_path / "seed.glb"
    trimesh.creation.box().export(seed)
    data = bytearray(seed.read_bytes())
    data[8:12] = struct.pack("<I", 10**9)
    (tmp_path / "m.glb").write_bytes(bytes(data))
    with pytest.raises(SceneError, match="GLB header claims 1000000000 bytes"):
        load_scene(tmp_path / "m.glb")


def test_a_ply_texture_that_is_a_fifo_is_a_warning(tmp_path):
    os.mkfifo(tmp_path / "tex.png")
    path = tmp_path / "m.ply"
    path.write_text("ply\nformat ascii 1.0\ncomment TextureFile tex.png\nelement vertex 3\n"
                    "property float x\nproperty float y\nproperty float z\n"
                    "property float s\nproperty float t\nelement face 1\n"
                    "property list uchar int vertex_indices\nend_header\n"
                    "0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n")
    scene = load_scene(path)
    assert any("tex.png" in w for w in scene.warnings), scene.warnings


def test_a_scene_file_passes_its_meshes_warnings_on(tmp_path):
    textured_obj(tmp_path, "gone.png")
    (tmp_path / "scene.toml").write_text('[[meshes]]\npath = "m.obj"\n')
    scene = load_scene(tmp_path / "scene.toml")
    assert any("gone.png" in w for w in scene.warnings), scene.warnings


def test_a_binary_stl_whose_count_lies_is_one_line(tmp_path):
    path = tmp_path / "m.stl"
    path.write_bytes(bytes(80) + struct.pack("<I", 4_000_000_000) + bytes(100))
    with pytest.raises(SceneError, match="claims 4,000,000,000 triangles"):
        load_scene(path)
