"""Scenes: built-ins, meshes trimesh writes, and broken input."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from explorer.scene import BUILTIN_SCENES, DirectionalLight, SceneError, SpotLight, load_scene


@pytest.mark.parametrize("name", sorted(BUILTIN_SCENES))
def test_builtin_scenes_are_well_formed(name):
    scene = load_scene(name)
    assert scene.triangle_count > 0
    assert np.allclose(np.linalg.norm(scene.normals, axis=1), 1.0, atol=1e-5)
    assert scene.albedo.min() >= 0.0 and scene.albedo.max() <= 1.0
    lo, hi = np.array(scene.bounds_min), np.array(scene.bounds_max)
    assert np.all(scene.positions >= lo - 1e-5) and np.all(scene.positions <= hi + 1e-5)
    assert scene.light.flux > 0
    # the normals agree with the counter-clockwise winding (the shaders rely on it)
    corners = scene.positions.reshape(-1, 3, 3)
    winding = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    assert np.all(np.einsum("ij,ij->i", winding, scene.normals[::3]) > 0)


def test_cornell_walls_are_red_and_green_and_face_inwards():
    scene = load_scene("cornell")
    left = np.isclose(scene.positions[:, 0], -1.0) & np.isclose(scene.normals[:, 0], 1.0)
    right = np.isclose(scene.positions[:, 0], 1.0) & np.isclose(scene.normals[:, 0], -1.0)
    assert left.any() and right.any()
    assert np.all(scene.albedo[left, 0] > 3 * scene.albedo[left, 1])     # red
    assert np.all(scene.albedo[right, 1] > 3 * scene.albedo[right, 0])   # green
    assert isinstance(scene.light, SpotLight)
    assert isinstance(load_scene("room").light, DirectionalLight)


def _box_with_colours() -> trimesh.Trimesh:
    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    box.visual.face_colors = np.tile([255, 0, 0, 255], (len(box.faces), 1))
    return box


@pytest.mark.parametrize("suffix", [".obj", ".stl", ".glb", ".ply"])
def test_meshes_load_with_normals_pointing_out(tmp_path, suffix):
    path = tmp_path / f"box{suffix}"
    trimesh.creation.box(extents=(1.0, 2.0, 3.0)).export(path)
    scene = load_scene(str(path))
    assert scene.triangle_count == 12
    assert np.allclose(scene.bounds_min, (-0.5, -1.0, -1.5), atol=1e-6)
    # flat normals computed from the faces: unit, pointing away from the box centre
    centroids = scene.positions.reshape(-1, 3, 3).mean(axis=1)
    normals = scene.normals[::3]
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-5)
    assert np.all(np.einsum("ij,ij->i", normals, centroids) > 0)
    assert np.allclose(scene.albedo, 0.6)           # no colour in the file: fallback grey


def test_face_colours_become_linear_albedo(tmp_path):
    path = tmp_path / "red.ply"
    path.write_bytes(trimesh.exchange.ply.export_ply(_box_with_colours()))
    scene = load_scene(str(path))
    assert np.allclose(scene.albedo, [1.0, 0.0, 0.0])


def test_vertex_colours_are_decoded_from_srgb(tmp_path):
    box = trimesh.creation.box()
    box.visual.vertex_colors = np.tile([128, 255, 0, 255], (len(box.vertices), 1))
    path = tmp_path / "green.ply"
    path.write_bytes(trimesh.exchange.ply.export_ply(box))
    scene = load_scene(str(path))
    # sRGB 128/255 decodes to about 0.2158 linear
    assert np.allclose(scene.albedo[:, 0], ((128 / 255 + 0.055) / 1.055) ** 2.4, atol=1e-4)
    assert np.allclose(scene.albedo[:, 1], 1.0)


def test_default_camera_and_light_frame_the_mesh(tmp_path):
    path = tmp_path / "box.obj"
    trimesh.creation.box().export(path)
    scene = load_scene(str(path))
    centre = 0.5 * (np.array(scene.bounds_min) + np.array(scene.bounds_max))
    assert np.allclose(scene.camera.target, centre)
    assert np.allclose(scene.light.target, centre)
    assert np.linalg.norm(np.subtract(scene.light.position, centre)) > 1.0


def test_overrides_move_camera_and_light():
    scene = load_scene("cornell").with_overrides(
        camera=((0, 0, 5), (0, 0, 0)), light=((0, 0.5, 0), (0, -1, 0)), light_flux=7.0)
    assert scene.camera.eye == (0.0, 0.0, 5.0)
    assert scene.light.position == (0.0, 0.5, 0.0) and scene.light.flux == 7.0


@pytest.mark.parametrize("content, suffix, message", [
    (None, ".obj", "no built-in scene or mesh file"),
    (b"", ".obj", "the file is empty"),
    (b"glTF" + bytes(range(60)), ".glb", "the GLB header claims 117835012 bytes"),
    (b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", ".obj", "no triangles"),
    (b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", ".obj", "no normals can be computed"),
])
def test_bad_meshes_raise_scene_error(tmp_path, content, suffix, message):
    path = tmp_path / f"bad{suffix}"
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(SceneError, match=message) as info:
        load_scene(str(path))
    assert str(path) in str(info.value) or "no built-in scene" in str(info.value)


def test_a_folder_is_not_a_scene(tmp_path):
    with pytest.raises(SceneError, match="not a file"):
        load_scene(str(tmp_path))


def test_texture_and_material_colours(tmp_path):
    from PIL import Image

    textured = trimesh.creation.box()
    textured.visual = trimesh.visual.TextureVisuals(
        uv=np.full((len(textured.vertices), 2), 0.5), image=Image.new("RGB", (4, 4),
                                                                      (0, 0, 255)))
    textured.export(tmp_path / "textured.glb")
    scene = load_scene(str(tmp_path / "textured.glb"))
    # trimesh writes the image as baseColorTexture with baseColorFactor 0.4 (its default
    # diffuse): glTF's albedo is the factor (linear) times the texture (sRGB decoded)
    assert np.allclose(scene.albedo, 0.4) and len(scene.textures) == 1
    assert np.allclose(scene.corner_albedo(), [0.0, 0.0, 0.4])
    material = trimesh.visual.material.PBRMaterial(baseColorFactor=[0, 255, 0, 255])
    plain = trimesh.creation.box()
    plain.visual = trimesh.visual.TextureVisuals(material=material)
    plain.export(tmp_path / "material.glb")
    assert np.allclose(load_scene(str(tmp_path / "material.glb")).albedo, [0.0, 1.0, 0.0])
