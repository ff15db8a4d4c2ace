"""Non-finite or absurd mesh coordinates (in the file, or once a scene file places the
mesh) are refused in one line naming the file and the mesh."""

from __future__ import annotations

import pytest

from explorer.scene import SceneError, load_scene

FACE = "f 1 2 3\n"


@pytest.mark.parametrize("first_vertex, words", [
    ("v 1e30 0 0", "a vertex coordinate is 1e+30, beyond the 1e+18"),
    ("v nan 0 0", "vertex position(s) are NaN or infinite"),
    ("v 0 inf 0", "vertex position(s) are NaN or infinite"),
])
def test_absurd_coordinates_in_a_mesh_are_refused_naming_it(tmp_path, first_vertex, words):
    path = tmp_path / "far.obj"
    path.write_text(f"{first_vertex}\nv 1 0 0\nv 0 1 0\n{FACE}")
    with pytest.raises(SceneError) as error:
        load_scene(path)
    text = str(error.value)
    assert str(path) in text and words in text and "\n" not in text


def test_a_scene_file_placing_a_mesh_beyond_the_range_is_refused(tmp_path):
    (tmp_path / "m.obj").write_text(f"v 1e17 0 0\nv 0 1e17 0\nv 0 0 1e17\n{FACE}")
    (tmp_path / "scene.toml").write_text('[[meshes]]\npath = "m.obj"\nscale = [100, 100, 100]\n')
    with pytest.raises(SceneError, match=r"scene\.toml: mesh .* placed in the world: a "
                                         r"vertex coordinate is 1e\+19"):
        load_scene(tmp_path / "scene.toml")
