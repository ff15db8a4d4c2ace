"""The Mitsuba export as data (no Mitsuba needed): the PLY, the spot falloff texture, the
camera frame, the XML and Python writers and the export-mitsuba command."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from explorer.cli import main as cli_main
from explorer.lpv.settings import Settings
from explorer.scene.lights import PointLight, SpotLight, spot_falloff
from explorer.truth.gbuffer import scene_for
from explorer.truth.mitsuba_scene import (
    ExportError,
    export_scene,
    mesh_file_name,
    mesh_ply,
    spot_falloff_texture,
    view_frame,
)


def _read_ply(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    header, body = data.split(b"end_header\n", 1)
    count = int(header.split(b"element vertex ")[1].split()[0])
    vertices = np.frombuffer(body[:count * 36], "<f4").reshape(count, 9)
    faces = np.frombuffer(body[count * 36:], dtype=[("n", "u1"), ("i", "<i4", (3,))])
    return vertices, faces


def test_ply_holds_every_corner_with_its_normal_and_albedo():
    scene = scene_for(Settings(scene="cornell"))
    vertices, faces = _read_ply(mesh_ply(scene))
    assert np.array_equal(vertices[:, :3], scene.positions)
    assert np.array_equal(vertices[:, 3:6], scene.normals)
    assert np.array_equal(vertices[:, 6:9], scene.albedo)
    assert len(faces) == scene.triangle_count and np.all(faces["n"] == 3)
    assert np.array_equal(faces["i"].reshape(-1), np.arange(len(scene.positions)))


def _bilinear(texture: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Lookup with texel centres at (i + ½)/n, as Mitsuba's bitmap (clamped)."""
    n = texture.shape[0]
    x = np.clip(u * n - 0.5, 0, n - 1)
    y = np.clip(v * n - 0.5, 0, n - 1)
    x0, y0 = np.minimum(x.astype(int), n - 2), np.minimum(y.astype(int), n - 2)
    fx, fy = x - x0, y - y0
    t = texture
    return ((1 - fx) * (1 - fy) * t[y0, x0] + fx * (1 - fy) * t[y0, x0 + 1]
            + (1 - fx) * fy * t[y0 + 1, x0] + fx * fy * t[y0 + 1, x0 + 1])


def test_spot_texture_reproduces_the_smoothstep_falloff():
    """Directions across the cone: the texture's bilinear lookup at Mitsuba's uv equals
    the explorer's smoothstep in cos θ to 1e-4 (its largest curvature over a texel)."""
    light = SpotLight((0, 0, 0), (0, 0, -1), 10.0, cone_degrees=(40.0, 70.0))
    texture = spot_falloff_texture(light, 70.0)
    rng = np.random.default_rng(3)
    theta = np.radians(rng.uniform(0.0, 69.9, 4000))
    phi = rng.uniform(0.0, 2 * math.pi, 4000)
    x, y, z = np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)
    t = math.tan(math.radians(70.0))
    u, v = 0.5 + 0.5 * x / (z * t), 0.5 + 0.5 * y / (z * t)
    expected = spot_falloff(np.cos(theta), *light.cone_cosines)
    assert np.max(np.abs(_bilinear(texture.astype(np.float64), u, v) - expected)) < 1e-4


def test_coneless_spot_texture_is_its_square_frustum():
    light = SpotLight((0, 0, 0), (0, 0, -1), 10.0)
    cutoff = math.degrees(math.atan(math.sqrt(2.0))) + 0.5
    texture = spot_falloff_texture(light, cutoff, texels=64)
    t = math.tan(math.radians(cutoff))
    centre = (2 * (np.arange(64) + 0.5) / 64 - 1) * t
    inside = np.abs(centre) <= 1.0
    assert np.array_equal(texture > 0.5, inside[:, None] & inside[None, :])


def test_frames_keep_the_explorer_eye_forward_and_up():
    scene = scene_for(Settings(scene="cornell"))
    view = scene.camera.view_matrix()
    frame = view_frame(view)
    eye, target = np.asarray(scene.camera.eye), np.asarray(scene.camera.target)
    assert np.allclose(frame[:3, 3], eye)
    assert np.allclose(frame[:3, 2], (target - eye) / np.linalg.norm(target - eye))
    assert np.allclose(frame[:3, 1], view[1, :3])           # the same up
    assert np.allclose(frame[:3, 0], -view[0, :3])          # Mitsuba's +x is the left
    assert np.isclose(np.linalg.det(frame[:3, :3]), 1.0)


def test_every_light_kind_exports_with_the_explorer_radiometry():
    scene = scene_for(Settings(scene="cornell", lights=("spot", "lamp", "bulb", "sun")))
    exported = export_scene(scene, 32, 24)
    kinds = [exported.plugins[f"light-{i}"]["type"] for i in range(4)]
    assert kinds == ["spot", "spot", "point", "directional"]
    spot, lamp, bulb, sun = scene.lights
    assert exported.plugins["light-0"]["intensity"][1] == pytest.approx(
        tuple(spot.flux / (4 * math.pi) * np.asarray(spot.colour)))
    assert exported.plugins["light-0"]["cutoff_angle"] == spot.cone_degrees[1]
    assert exported.plugins["light-2"]["intensity"][1] == pytest.approx(
        tuple(bulb.flux / (4 * math.pi) * np.asarray(bulb.colour)))
    assert isinstance(bulb, PointLight)
    irradiance = sun.irradiance(scene.bounds_min, scene.bounds_max)
    assert exported.plugins["light-3"]["irradiance"][1] == pytest.approx(
        tuple(irradiance * np.asarray(sun.colour)))
    assert sorted(exported.files) == ["scene.ply", "spot-0.pfm", "spot-1.pfm"]
    film = exported.plugins["camera"]["film"]
    assert (film["width"], film["height"]) == (32, 24)


def test_export_refuses_a_bad_suffix_and_no_pixels(tmp_path):
    exported = export_scene(scene_for(Settings(scene="cornell")), 8, 8)
    with pytest.raises(ExportError, match=".xml or .py"):
        exported.contents(tmp_path / "scene.obj")
    with pytest.raises(ExportError, match="at least one pixel"):
        export_scene(scene_for(Settings(scene="cornell")), 0, 8)


def test_export_mitsuba_command_writes_xml_and_python(tmp_path, capsys):
    for name in ("room.xml", "room.py"):
        code = cli_main(["export-mitsuba", "room", str(tmp_path / name), "--size", "40x30"])
        assert code == 0, capsys.readouterr().err
    xml = (tmp_path / "room.xml").read_text()
    assert '<shape type="ply">' in xml and '<emitter type="' in xml
    assert '<integer name="width" value="40"/>' in xml
    source = (tmp_path / "room.py").read_text()
    compile(source, "room.py", "exec")               # a valid script, not run here
    assert "mi.load_dict(SCENE)" in source
    assert 'value="room-files/scene.ply"' in xml
    assert (tmp_path / "room-files" / "scene.ply").stat().st_size > 0


def test_export_mitsuba_bad_input_is_one_line(tmp_path, capsys):
    assert cli_main(["export-mitsuba", "no-such-scene", str(tmp_path / "a.xml")]) == 2
    assert cli_main(["export-mitsuba", "cornell", str(tmp_path / "a.obj")]) == 2
    errors = capsys.readouterr().err.strip().splitlines()
    assert len(errors) == 2 and all(line.startswith("lpv-explorer export-mitsuba: error:")
                                    for line in errors)
    assert not list(tmp_path.iterdir())


def test_compare_truth_without_mitsuba_is_one_line(tmp_path, capsys, monkeypatch):
    """A missing Mitsuba (import fails) is one line naming the extra, before rendering."""
    import sys

    monkeypatch.setitem(sys.modules, "mitsuba", None)      # `import mitsuba` raises
    code = cli_main(["compare", "--truth", "mitsuba", "--size", "16x16", "--rsm-size", "8",
                     "--quiet", "--out", str(tmp_path / "cmp")])
    error = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(error) == 1
    assert "Mitsuba 3 is not installed: pip install 'lpv-explorer[truth]'" in error[0]
    assert not (tmp_path / "cmp" / "table.md").exists()


def test_textured_and_one_sided_triangles_get_their_own_shapes():
    """A textured group: its texture times the albedo factor as a bitmap at the corners'
    uv (v flipped for Mitsuba); a one-sided group: its diffuse the front of
    ``lpv_one_sided``, rendered with ``volpath``, the plugin file beside the scene."""
    import dataclasses

    base = scene_for(Settings(scene="cornell"))
    count = base.triangle_count
    uv = np.tile(np.array([[0, 0], [1, 0], [1, 1]], np.float32), (count, 1))
    texture = np.full((4, 4, 3), 0.5, np.float32)
    triangle_texture = np.full(count, -1)
    triangle_texture[:2] = 0                                  # the floor
    one_sided = np.zeros(count, bool)
    one_sided[2:4] = True                                     # the ceiling
    scene = dataclasses.replace(base, uv=uv, textures=(texture,),
                                triangle_texture=triangle_texture, one_sided=one_sided)
    exported = export_scene(scene, 16, 16)
    shapes = {str(p["filename"]): p["bsdf"] for k, p in exported.plugins.items()
              if k.startswith("surfaces")}
    assert shapes["scene-t0.ply"]["material"]["reflectance"]["type"] == "bitmap"
    assert sorted(shapes) == ["scene-one-sided.ply", "scene-t0.ply", "scene.ply"]
    one_sided_bsdf = shapes["scene-one-sided.ply"]
    assert one_sided_bsdf["type"] == "lpv_one_sided"
    assert one_sided_bsdf["front"]["type"] == "diffuse"
    assert exported.integrator == "volpath" and "lpv_one_sided.py" in exported.files
    assert shapes["scene.ply"]["type"] == "twosided"
    header, body = exported.files["scene-t0.ply"].split(b"end_header\n", 1)
    assert b"property float u" in header
    vertices = np.frombuffer(body[:6 * 44], "<f4").reshape(6, 11)
    assert np.allclose(vertices[:, 10], 1.0 - uv[:6, 1])     # v flipped
    assert exported.files["texture-0.pfm"].startswith(b"PF\n4 4\n")


EXAMPLE_ROOM = Path(__file__).resolve().parents[2] / "examples" / "textured-room" / "scene.toml"


def test_a_one_sided_export_carries_its_plugin_and_says_how_to_render(tmp_path, capsys):
    """The textured room (one-sided walls): the XML names ``volpath`` and the plugin,
    the companion folder holds the plugin file, the command says how to render it, and
    a scene without one-sided surfaces keeps ``path`` and no plugin."""
    assert cli_main(["export-mitsuba", str(EXAMPLE_ROOM), str(tmp_path / "r.xml"),
                     "--size", "16x12"]) == 0
    out = capsys.readouterr().out
    assert "python" in out and "r-files/lpv_one_sided.py" in out
    xml = (tmp_path / "r.xml").read_text()
    assert '<integrator type="volpath">' in xml and '<bsdf type="lpv_one_sided"' in xml
    assert "python r-files/lpv_one_sided.py r.xml" in xml
    plugin = (tmp_path / "r-files" / "lpv_one_sided.py").read_text()
    compile(plugin, "lpv_one_sided.py", "exec")
    assert "lpv_one_sided.py" in (tmp_path / "r-files" / ".lpv-explorer-export").read_text()
    assert cli_main(["export-mitsuba", str(EXAMPLE_ROOM), str(tmp_path / "r.py"),
                     "--size", "16x12"]) == 0
    source = (tmp_path / "r.py").read_text()
    compile(source, "r.py", "exec")
    assert "lpv_one_sided.register(mi)" in source and "'volpath'" in source
    assert cli_main(["export-mitsuba", "cornell", str(tmp_path / "c.xml")]) == 0
    assert '<integrator type="path">' in (tmp_path / "c.xml").read_text()
    assert not (tmp_path / "c-files" / "lpv_one_sided.py").exists()


def test_several_colours_under_one_texture_is_a_warning_naming_the_mesh():
    """A textured group whose corners carry two albedo factors is exported sampled at its
    corners; the export says so, naming the group's file."""
    import dataclasses

    base = scene_for(Settings(scene="cornell"))
    count = base.triangle_count
    uv = np.tile(np.array([[0, 0], [1, 0], [1, 1]], np.float32), (count, 1))
    triangle_texture = np.full(count, -1)
    triangle_texture[:4] = 0                           # the floor and the ceiling
    scene = dataclasses.replace(base, uv=uv, textures=(np.full((4, 4, 3), 0.5, np.float32),),
                                triangle_texture=triangle_texture)
    albedo = np.asarray(scene.albedo)
    if len(np.unique(albedo[:12], axis=0)) < 2:
        albedo = albedo.copy()
        albedo[6:12] = 0.25
        scene = dataclasses.replace(scene, albedo=albedo)
    warnings = export_scene(scene, 8, 8).warnings
    assert len(warnings) == 1 and warnings[0].startswith("scene-t0.ply: texture 0")
    assert not export_scene(base, 8, 8).warnings


def test_every_surface_group_has_a_plain_name_of_its_own():
    groups = [(texture, sided) for texture in (-1, 0, 1, 11) for sided in (False, True)]
    names = [mesh_file_name(*group) for group in groups]
    assert len(set(names)) == len(groups), names
    assert all("-1" not in name and name.endswith(".ply") for name in names), names
    assert names[:2] == ["scene.ply", "scene-one-sided.ply"]
