"""Scene files (.toml): what they build, their one-line errors, lights put inside closed
meshes, the command-line overrides, and one- or two-sided surfaces in the frame."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh
from lpv_cases import run_frame

from explorer.cli import main
from explorer.lpv.settings import Settings
from explorer.scene import PointLight, SceneError, SpotLight, load_scene
from explorer.scene.placement import light_inside

ROOM = (4.0, 2.0, 3.0)
SMALL = {"width": 48, "height": 36, "grid_size": 8, "rsm_size": 64, "iterations": 4}


def room_mesh(reverse_half: bool = False) -> trimesh.Trimesh:
    """A closed 4 × 2 × 3 m room on the floor y = 0, its walls facing inwards; with
    ``reverse_half`` every other triangle wound the other way (facing outwards)."""
    box = trimesh.creation.box(extents=ROOM)
    box.apply_translation((0.0, ROOM[1] / 2, 0.0))
    faces = np.asarray(box.faces)[:, ::-1].copy()          # inwards
    if reverse_half:
        faces[::2] = faces[::2, ::-1]
    return trimesh.Trimesh(box.vertices, faces, process=False)


def write_room(folder: Path, text: str, reverse_half: bool = False, name="room") -> Path:
    room_mesh(reverse_half).export(folder / f"{name}.obj")
    path = folder / f"{name}.toml"
    path.write_text(text.replace("MESH", f"{name}.obj"))
    return path


ROOM_FILE = """
name = "closed room"
[camera]
eye = [1.5, 1.5, 1.2]
target = [-1.0, 0.6, -1.0]
fov = 70.0
[[meshes]]
path = "MESH"
albedo = [0.7, 0.7, 0.7]
[[lights]]
kind = "point"
name = "bulb"
position = [0.0, 1.6, 0.0]
irradiance = 2.0
target = [0.0, 0.0, 0.0]
"""


def test_a_scene_file_builds_meshes_lights_and_camera(tmp_path):
    scene = load_scene(str(write_room(tmp_path, ROOM_FILE)))
    assert scene.name == "closed room" and scene.triangle_count == 12
    assert scene.camera.eye == (1.5, 1.5, 1.2) and scene.camera.fov_y_degrees == 70.0
    assert np.allclose(scene.albedo, 0.7)
    assert isinstance(scene.light, PointLight) and scene.light.name == "bulb"
    # irradiance 2 W/m² at 1.6 m: Φ = 4π r² E
    assert np.isclose(scene.light.flux, 4 * np.pi * 1.6 ** 2 * 2.0)
    assert scene.notice == ""
    assert scene.one_sided is None                     # OBJ: two-sided unless told


def test_mesh_placement_grid_and_poses(tmp_path):
    room_mesh().export(tmp_path / "room.obj")
    path = tmp_path / "placed.toml"
    path.write_text("""
[grid]
min = [-5.0, -1.0, -5.0]
max = [5.0, 4.0, 5.0]
[[meshes]]
path = "room.obj"
translate = [1.0, 0.0, 0.0]
rotate = [0.0, 90.0, 0.0]
scale = 0.5
two_sided = false
[poses]
"room" = [0.0, 1.0, 0.0]
[[lights]]
kind = "directional"
position = [0.0, 5.0, 0.0]
target = [0.0, 0.0, 0.0]
""")
    scene = load_scene(str(path))
    lo, hi = scene.positions.min(axis=0), scene.positions.max(axis=0)
    # scaled by 0.5 and turned 90° about y: x and z swap their extents; moved by +1 in x,
    # then the pose lifts the object by 1
    assert np.allclose(hi - lo, (1.5, 1.0, 2.0), atol=1e-6)
    assert np.allclose(0.5 * (lo + hi), (1.0, 1.5, 0.0), atol=1e-6)
    assert scene.bounds_min == (-5.0, -1.0, -5.0) and scene.bounds_max == (5.0, 4.0, 5.0)
    assert scene.notice == ""
    # a box too small for the meshes as placed grows to hold them (the poses move objects
    # as the window does: the box does not follow them)
    small = path.read_text().replace("max = [5.0, 4.0, 5.0]", "max = [5.0, 0.5, 5.0]")
    path.write_text(small)
    grown = load_scene(str(path))
    assert grown.bounds_max[1] == pytest.approx(1.0) and "[grid] grown to min" in grown.notice
    assert scene.one_sided is not None and scene.one_sided.all()
    assert scene.light.kind == "directional"


def test_a_builtin_scene_with_its_own_camera_and_lights(tmp_path):
    path = tmp_path / "cornell.toml"
    path.write_text("""
builtin = "cornell"
[camera]
eye = [0.0, 0.0, 3.0]
target = [0.0, 0.0, 0.0]
[[lights]]
kind = "spot"
name = "key"
position = [0.0, 0.9, 0.0]
target = [0.0, -1.0, 0.0]
cone = [30.0, 50.0]
flux = 20.0
colour = [1.0, 0.5, 0.25]
[[lights]]
kind = "point"
name = "fill"
position = [0.5, 0.5, 0.5]
flux = 3.0
on = false
""")
    scene = load_scene(str(path))
    assert scene.triangle_count == load_scene("cornell").triangle_count
    assert scene.camera.eye == (0.0, 0.0, 3.0)
    assert scene.light_names == ("key", "fill") and scene.lights_on == ("key",)
    assert isinstance(scene.light, SpotLight) and scene.light.cone_degrees == (30.0, 50.0)
    assert scene.light.flux == 20.0 and scene.light.colour == (1.0, 0.5, 0.25)


BAD_FILES = [
    ("nmae = 'x'\n[[meshes]]\npath = 'MESH'\n", "the file: unknown key 'nmae'; allowed: name"),
    ("[[meshes]]\npath = 'MESH'\ncolour = [1, 1, 1]\n", "[[meshes]] #1: unknown key 'colour'"),
    ("[[meshes]]\npath = 'missing.obj'\n", "mesh file 'missing.obj' not found"),
    ("[[meshes]]\npath = '.'\n", "mesh path '.' is not a file"),
    ("[[meshes]]\npath = 'loop.obj'\n", "mesh path 'loop.obj' is a symbolic link that leads "
     "nowhere (a loop"),
    ("[[meshes]]\npath = 'bad.toml.obj'\n", "[[meshes]] #1: "),
    ("[[meshes]]\npath = 'other.toml'\n", "must name a mesh file, not a scene file"),
    ("[[meshes]]\nscale = 2.0\n", "[[meshes]] #1 needs path"),
    ("[[meshes]]\npath = 'MESH'\nscale = 0.0\n", "scale must be 3 numbers in [0.01, 100]"),
    ("[[meshes]]\npath = 'MESH'\ntwo_sided = 'yes'\n", "two_sided must be true or false"),
    ("[[meshes]]\npath = 'MESH'\nalbedo = [1.5, 0, 0]\n", "albedo must be 3 numbers in [0, 1]"),
    ("builtin = 'nowhere'\n", "builtin = 'nowhere' is not a built-in scene"),
    ("builtin = [1, 2]\n", "builtin must be non-empty text, got [1, 2]"),
    ("builtin = 'cornell'\n[[meshes]]\npath = 'MESH'\n", "not both"),
    ("name = 'x'\n", "give either builtin = NAME or [[meshes]]"),
    ("builtin = 'cornell'\n[camera]\nfov = 200.0\n", "[camera]: fov must be a number in [1, 170]"),
    ("builtin = 'cornell'\n[camera]\neye = [1, 2]\n", "eye must be 3 numbers"),
    ("builtin = 'cornell'\n[camera]\neye = [0, 0, 0]\ntarget = [0, 0, 0]\n",
     "eye and target must differ"),
    ("builtin = 'cornell'\n[grid]\nmin = [0, 0, 0]\nmax = [1, 0, 1]\n",
     "min must be below max"),
    ("builtin = 'cornell'\n[grid]\nmin = [0, 0, 0]\n", "[grid] needs both min and max"),
    ("builtin = 'cornell'\n[grid]\ncells = [7, 12, 5]\norigin = [0, 0, 0]\n",
     "[grid] gives an exact grid with cells, origin and cell_size together; missing "
     "cell_size"),
    ("builtin = 'cornell'\n[grid]\ncells = [7, 12]\norigin = [0, 0, 0]\ncell_size = 0.1\n",
     "[grid]: cells must be 3 whole numbers in [1, 256]"),
    ("builtin = 'cornell'\n[grid]\ncells = [7, 1.5, 5]\norigin = [0, 0, 0]\ncell_size = 1\n",
     "[grid]: cells must be 3 whole numbers"),
    ("builtin = 'cornell'\n[grid]\ncells = [7, 12, 5]\norigin = [0, 0]\ncell_size = 0.1\n",
     "[grid]: origin must be 3 numbers"),
    ("builtin = 'cornell'\n[grid]\ncells = [7, 12, 5]\norigin = [0, 0, 0]\ncell_size = 0\n",
     "[grid]: cell_size must be a number in (0, 1e+06]"),
    ("builtin = 'cornell'\n[[lights]]\nkind = 'laser'\nposition = [0, 0, 0]\n",
     "kind must be one of spot, point, directional, got 'laser'"),
    ("builtin = 'cornell'\n[[lights]]\nkind = 'spot'\nposition = [0, 0, 0]\n",
     "a spot light needs target"),
    ("builtin = 'cornell'\n[[lights]]\nkind = 'point'\nposition = [0, 0, 0]\nflux = -1.0\n",
     "flux must be a number in (0, 1e+12]"),
    ("builtin = 'cornell'\n[[lights]]\nkind = 'point'\nposition = [0, 0, 0]\nflux = 1.0\n"
     "irradiance = 1.0\n", "give flux or irradiance, not both"),
    ("builtin = 'cornell'\n[[lights]]\nkind = 'point'\nposition = [0, 0, 0]\nirradiance = 1.0\n",
     "a point light's irradiance needs target"),
    ("builtin = 'cornell'\n[[lights]]\nkind = 'spot'\nposition = [0, 1, 0]\ntarget = [0, 0, 0]"
     "\ncone = [50.0, 40.0]\n", "needs inner <= outer"),
    ("builtin = 'cornell'\n[[lights]]\nkind = 'point'\nposition = [0, 1, 0]\ncone = [5, 9]\n",
     "cone is for spot lights, not point ones"),
    ("builtin = 'cornell'\n[[lights]]\nkind = 'point'\nposition = [0, 1, 0]\ncolor = [1,1,1]\n",
     "[[lights]] #1: unknown key 'color'; allowed: kind, name"),
    ("builtin = 'cornell'\n[[lights]]\nkind = 'point'\nposition = [0, 1, 0]\ncolour = [0,0,0]\n",
     "colour must not be all 0"),
    ("builtin = 'cornell'\n[[lights]]\nname = 'a'\nkind = 'point'\nposition = [0, 1, 0]\n"
     "[[lights]]\nname = 'a'\nkind = 'point'\nposition = [0, 1, 0]\n", "the name 'a' is taken"),
    ("builtin = 'cornell'\n[[lights]]\nkind = 'point'\nposition = [0, 1, 0]\non = false\n",
     "1 to 8 lights must be on, got 0"),
    ("builtin = 'cornell'\n[poses]\n'short block' = [0, 0]\n", "[poses] must map object names"),
    ("builtin = 'cornell'\n[poses]\n'no such' = [0, 0, 0]\n", "has no object 'no such'"),
    ("builtin = 'cornell'\n[camera\n", "not valid TOML"),
    ("builtin = 'cornell'\nlights = 3\n", "lights must be one or more [[lights]] tables"),
]


@pytest.mark.parametrize("text, message", BAD_FILES)
def test_scene_file_mistakes_are_one_line_scene_errors(tmp_path, text, message):
    room_mesh().export(tmp_path / "room.obj")
    (tmp_path / "bad.toml.obj").write_text("v 0 0 0\n")       # a mesh without faces
    (tmp_path / "loop.obj").symlink_to("loop.obj")
    path = tmp_path / "bad.toml"
    path.write_text(text.replace("MESH", "room.obj"))
    with pytest.raises(SceneError) as info:
        load_scene(str(path))
    assert message in str(info.value)
    assert "\n" not in str(info.value) and str(path) in str(info.value)


EXACT_GRID = """
builtin = "cornell"
[grid]
cells = [7, 12, 5]
origin = [-1.6, -0.2, -1.3]
cell_size = 0.25
"""


def test_a_scene_file_gives_an_exact_grid_the_command_line_overrides(gl_context, tmp_path):
    path = tmp_path / "exact.toml"
    path.write_text(EXACT_GRID)
    scene = load_scene(str(path))
    assert scene.exact_grid == ((7, 12, 5), (-1.6, -0.2, -1.3), 0.25)
    small = {**SMALL, "scene": str(path), "iterations": 2}
    frame = run_frame(gl_context, Settings(**small))
    assert frame.grid_spec.cells == (7, 12, 5) and frame.grid_spec.cell_size == 0.25
    assert frame.grid_spec.origin == (-1.6, -0.2, -1.3)
    assert frame.accumulated.shape[1:4] == (7, 12, 5)
    assert np.isfinite(frame.final_image).all() and frame.accumulated[..., 0].max() > 0
    given = Settings(**small, grid_cells=(5, 6, 7), grid_origin=(-1.0, 0.0, -1.0),
                     grid_cell_size=0.3)
    frame = run_frame(gl_context, given)
    assert frame.grid_spec.cells == (5, 6, 7) and frame.grid_spec.origin == (-1.0, 0.0, -1.0)


def test_the_command_takes_an_exact_grid(tmp_path, capsys):
    out = tmp_path / "exact.png"
    args = ["render", "--size", "32x24", "--grid", "8", "--iterations", "2", "--rsm-size", "64",
            "--out", str(out)]
    assert main(args + ["--grid-cells", "7,12,5", "--grid-origin", "-1.6,-0.2,-1.3",
                        "--grid-cell-size", "0.25"]) == 0
    assert out.exists()
    assert main(args + ["--grid-cells", "7,12,5"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "grid_cells, grid_origin and grid_cell_size together" \
        in err
    assert main(args + ["--grid-cells", "7,12"]) == 2
    assert "grid_cells must be three whole numbers" in capsys.readouterr().err


def test_the_command_refuses_a_bad_scene_file_in_one_line(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text("builtin = 'cornell'\n[camera]\nfovy = 40.0\n")
    out = tmp_path / "x.png"
    assert main(["render", "--scene", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "unknown key 'fovy'" in err
    assert not out.exists()


def test_a_closed_mesh_without_lights_gets_one_inside(tmp_path):
    room_mesh().export(tmp_path / "room.obj")
    scene = load_scene(str(tmp_path / "room.obj"))
    assert isinstance(scene.light, PointLight)
    position = np.asarray(scene.light.position)
    assert np.all(position > (-2.0, 0.0, -1.5)) and np.all(position < (2.0, 2.0, 1.5))
    assert "inside it" in scene.notice and scene.light.name in scene.notice
    assert light_inside(scene).closed
    # the Cornell box is open at the front, though a point behind its tall block sees
    # walls and blocks only
    cornell = light_inside(load_scene("cornell"))
    assert cornell is not None and not cornell.closed
    # a solid box (faces outwards) encloses no room: the spot above it, said so
    trimesh.creation.box().export(tmp_path / "solid.obj")
    solid = load_scene(str(tmp_path / "solid.obj"))
    assert isinstance(solid.light, SpotLight)
    assert light_inside(solid) is None and "spot light" in solid.notice
    # a room without its front wall: a point light inside, in the box, said open
    room = room_mesh()
    front = np.flatnonzero(np.isclose(room.triangles_center[:, 2], ROOM[2] / 2))
    assert len(front) == 2
    keep = np.setdiff1d(np.arange(len(room.faces)), front)
    trimesh.Trimesh(room.vertices, room.faces[keep], process=False).export(
        tmp_path / "open.obj")
    opened = load_scene(str(tmp_path / "open.obj"))
    placement = light_inside(opened)
    assert placement is not None and not placement.closed and placement.enclosed > 0.5
    assert isinstance(opened.light, PointLight) and "the mesh is open" in opened.notice
    assert np.all(np.asarray(opened.light.position) > (-2.0, 0.0, -1.5))
    assert np.all(np.asarray(opened.light.position) < (2.0, 2.0, 1.5))


def test_the_command_says_where_it_put_the_light(tmp_path, capsys):
    room_mesh().export(tmp_path / "room.obj")
    out = tmp_path / "room.png"
    assert main(["render", "--scene", str(tmp_path / "room.obj"), "--size", "32x24",
                 "--grid", "8", "--rsm-size", "32", "--iterations", "2",
                 "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "point light 'light' is at (" in err and "inside it" in err
    assert out.exists()


@pytest.fixture(scope="module")
def closed_room_frames(gl_context, tmp_path_factory):
    """Final frames of the closed room lit from inside: as written, with half its
    triangles' winding reversed, each one- and two-sided."""
    folder = tmp_path_factory.mktemp("rooms")
    frames = {}
    for reverse in (False, True):
        for sided in ("true", "false"):
            name = f"room-{int(reverse)}-{sided}"
            text = ROOM_FILE.replace('albedo = [0.7, 0.7, 0.7]',
                                     f'albedo = [0.7, 0.7, 0.7]\ntwo_sided = {sided}')
            path = write_room(folder, text, reverse_half=reverse, name=name)
            frames[reverse, sided == "true"] = run_frame(
                gl_context, Settings(scene=str(path), geometry_volume="one-sided", **SMALL))
    return frames


def test_a_closed_room_from_a_scene_file_is_lit_inside(closed_room_frames):
    frame = closed_room_frames[False, True]
    seen = frame.albedo[..., 0] > 0          # every pixel sees a wall of the room
    assert seen.all()
    assert frame.direct.mean() > 0.05 and frame.indirect.mean() > 0.005
    # one-sided walls facing the camera and the light give the same picture
    assert np.array_equal(closed_room_frames[False, False].direct, frame.direct)


def test_reversed_winding_changes_a_one_sided_mesh_not_a_two_sided_one(closed_room_frames):
    two_sided, two_sided_reversed = closed_room_frames[False, True], \
        closed_room_frames[True, True]
    # the same picture: to float rounding only (a triangle's corners in the other order
    # interpolate its attributes in another order, a unit in the last place apart)
    for view in ("direct", "indirect", "albedo"):
        ours, theirs = getattr(two_sided, view), getattr(two_sided_reversed, view)
        assert np.allclose(ours, theirs, rtol=1e-5, atol=1e-6 * float(np.abs(ours).max()))
    one_sided, one_sided_reversed = closed_room_frames[False, False], \
        closed_room_frames[True, False]
    # the reversed triangles face away from the camera and the light: gone from both,
    # so the camera looks out through them into the void and less light stays inside
    holes = one_sided_reversed.albedo[..., 0] == 0
    assert 0.2 < holes.mean() < 0.8
    assert np.abs(one_sided.direct - one_sided_reversed.direct).max() > 0.1
    assert one_sided_reversed.indirect.mean() < 0.9 * one_sided.indirect.mean()


def test_the_geometry_volume_holds_only_the_sides_that_exist(closed_room_frames):
    """The geometry volume is injected from the RSM: a one-sided wall the light sees from
    behind leaves no blocker in it; a two-sided one does, whichever way it is wound."""
    def blocking(frame) -> float:
        return float(np.abs(frame.cascades[0].geometry_volume[..., 0]).sum())

    two_sided = blocking(closed_room_frames[False, True])
    assert two_sided > 0
    assert np.isclose(blocking(closed_room_frames[True, True]), two_sided, rtol=1e-5)
    assert np.isclose(blocking(closed_room_frames[False, False]), two_sided, rtol=1e-5)
    assert blocking(closed_room_frames[True, False]) < 0.8 * two_sided


def test_light_and_camera_overrides_on_the_command_line(tmp_path):
    from explorer.cli import build_parser
    from explorer.commands.options import settings_from_args

    path = write_room(tmp_path, ROOM_FILE)
    parser = build_parser()
    args = parser.parse_args(["render", "--scene", str(path), "--light",
                              "spot:0,1.9,0:0.5,0,0", "--camera", "1,1,1:0,0.5,0:40",
                              "--light-flux", "12"])
    settings = settings_from_args(args)
    assert settings.light == ((0.0, 1.9, 0.0), (0.5, 0.0, 0.0))
    assert settings.light_kind == "spot" and settings.light_flux == 12.0
    assert settings.camera == ((1.0, 1.0, 1.0), (0.0, 0.5, 0.0)) and settings.camera_fov == 40
    scene = load_scene(str(path)).for_settings(settings)
    assert isinstance(scene.light, SpotLight) and scene.light.name == "bulb"
    assert scene.light.position == (0.0, 1.9, 0.0) and scene.light.flux == 12.0
    assert scene.camera.fov_y_degrees == 40.0
    # a new kind without --light-flux: 2 W/m² at the target
    point = load_scene("cornell").with_overrides(light=((0, 0.5, 0), (0, -0.5, 0)),
                                                 light_kind="point")
    assert isinstance(point.light, PointLight) and point.light.position == (0.0, 0.5, 0.0)


@pytest.mark.parametrize("option, message", [
    ("--light laser:0,0,0", "KIND one of spot, point, directional"),
    ("--light spot:0,1,0", "a spot light needs a target"),
    ("--light point:0,x,0", "the light's position must be three numbers"),
    ("--camera 0,0,1", "--camera must look like ex,ey,ez:tx,ty,tz[:fov]"),
    ("--camera 0,0,1:0,0,1", "eye and target must differ"),
    ("--camera 0,0,1:0,0,0:500", "camera_fov must be a finite number in [1, 170]"),
    ("--light-flux -3", "light_flux must be"),
])
def test_bad_overrides_are_one_line(capsys, option, message):
    assert main(["render", *option.split()]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and message in err


def test_a_saved_scene_opens_the_same_again(tmp_path):
    from explorer.scene.scene_writer import write_scene_file

    settings = Settings(camera=((0.2, 0.4, 3.0), (0.0, -0.2, 0.0)), camera_fov=50.0,
                        light=((0.1, 0.8, 0.6), (0.0, -0.6, -0.5)), light_flux=33.0,
                        lights=("spot", "bulb"),
                        object_transforms=(("short block", (0.1, 0.0, -0.2, 0.0, 25.0, 0.0,
                                                            1.0, 1.5, 1.0)),))
    shown = load_scene("cornell").for_settings(settings)
    path = write_scene_file(shown, "cornell", tmp_path / "saved")
    assert path.name == "saved.toml"
    again = load_scene(str(path))
    assert again.camera == shown.camera and again.lights_on == ("spot", "bulb")
    # every light of the rig as shown (those on first, the primary first of them)
    assert {light.name: light for light in again.rig} == \
        {light.name: light for light in shown.rig}
    assert again.light_names[:2] == ("spot", "bulb")
    assert again.light.flux == 33.0 and again.light.position == (0.1, 0.8, 0.6)
    assert np.allclose(again.positions, shown.positions, atol=1e-6)
    assert (again.bounds_min, again.bounds_max) == (shown.bounds_min, shown.bounds_max)


def test_saving_a_posed_scene_file_composes_the_poses(tmp_path):
    from explorer.scene.scene_writer import write_scene_file

    room_mesh().export(tmp_path / "room.obj")
    trimesh.creation.box(extents=(0.4, 0.4, 0.4)).export(tmp_path / "block.obj")
    source = tmp_path / "posed.toml"
    source.write_text("[[meshes]]\npath = 'room.obj'\n[[meshes]]\npath = 'block.obj'\n"
                      "translate = [0.0, 0.2, 0.0]\n[poses]\n'block' = [0.5, 0.0, 0.0, 0.0, "
                      "30.0, 0.0]\n[[lights]]\nkind = 'point'\nposition = [0.0, 1.5, 0.0]\n")
    shown = load_scene(str(source)).posed((("block", (0.0, 0.3, 0.0, 0.0, 15.0, 0.0, 2.0,
                                                      2.0, 2.0)),))
    (tmp_path / "sub").mkdir()
    saved = write_scene_file(shown, str(source), tmp_path / "sub" / "again.toml")
    text = saved.read_text()
    assert 'path = "../room.obj"' in text and "[poses]" in text
    again = load_scene(str(saved))
    assert np.allclose(again.positions, shown.positions, atol=1e-5)


def test_the_example_scene_file_loads_as_its_script_made_it(tmp_path):
    import importlib.util

    root = Path(__file__).resolve().parents[2]
    scene = load_scene(str(root / "examples" / "textured-room" / "scene.toml"))
    assert scene.name == "textured room" and scene.light_names == ("ceiling spot", "bulb")
    assert scene.lights_on == ("ceiling spot",) and scene.camera.fov_y_degrees == 75.0
    assert len(scene.textures) == 1 and scene.textures[0].shape == (64, 64, 3)
    assert scene.one_sided is not None and scene.one_sided.all()      # glTF's default
    assert light_inside(scene).closed                               # a closed room
    # the committed asset is what examples/make_textured_room.py makes
    spec = importlib.util.spec_from_file_location(
        "make_textured_room", root / "examples" / "make_textured_room.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.room().export(tmp_path / "room.glb")
    made = load_scene(str(tmp_path / "room.glb"))
    committed = load_scene(str(root / "examples" / "textured-room" / "room.glb"))
    assert np.array_equal(made.positions, committed.positions)
    assert np.array_equal(made.textures[0], committed.textures[0])
