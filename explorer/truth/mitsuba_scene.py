"""An explorer scene as a Mitsuba 3 scene: the same triangles, diffuse albedo, lights and
camera, written as files Mitsuba reads (no Mitsuba needed to write them).

What is exported, and how each explorer quantity maps onto a stock Mitsuba plugin:

* the triangles: a binary PLY per (texture, sidedness) group (``scene.ply`` for the
  untextured two-sided ones, :func:`mesh_file_name`) with per-corner normals and the
  linear albedo as the float vertex colour, read by a ``diffuse`` BSDF through a
  ``mesh_attribute`` texture; a textured group's texture times its albedo factor is a
  ``bitmap`` at the corners' uv;
  ``twosided`` unless the group is one-sided (the explorer's two-sided surfaces turn the
  normal towards the viewer and the light); a one-sided group's diffuse is the ``front``
  of ``lpv_one_sided`` (explorer/truth/mitsuba_one_sided.py, copied beside the scene),
  absent for a view from behind as in the explorer, and the scene then renders with
  ``volpath``, the integrator that lets shadow rays through it. How the albedo reaches
  the BSDF is :func:`surface_bsdf`'s one job;
* a spot light (intensity ``Φ_L/(4π)·colour·f(θ)``, docs/MODEL.md "Spot cone"): a ``spot``
  with ``cutoff_angle = beam_width`` (Mitsuba's own falloff, linear in the angle, is then
  a step at the cutoff) and the explorer's ``f`` as a projected float texture
  (``spot-<index>.pfm``, :func:`spot_falloff_texture`): the smoothstep in cos θ of a cone,
  or 1 inside the 90° square frustum of a cone-less spot (cutoff: the frustum's corner);
* a point light: a ``point`` of intensity ``Φ_L/(4π)·colour``;
* a directional light: a ``directional`` of irradiance ``E·colour``, ``E = flux/(2R)²``;
* the camera: a ``perspective`` sensor with the explorer camera's eye, forward, up and
  vertical field of view at the frame's pixels, with a box pixel filter (each pixel the
  mean over its area).

:class:`MitsubaScene` holds that description as plain data; :meth:`MitsubaScene.write`
writes the XML (``.xml``, what explorer/truth/mitsuba_render.py renders) or a Python
script (``.py``, ``mi.load_dict``), and the PLYs and textures into the scene's own
:func:`companion_folder` (``NAME-files/``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from explorer.scene.lights import DirectionalLight, PointLight, SpotLight, spot_falloff
from explorer.truth import mitsuba_one_sided

MESH_FILE = "scene.ply"
ONE_SIDED_PLUGIN_FILE = "lpv_one_sided.py"
"""The one-sided BSDF's plugin (explorer/truth/mitsuba_one_sided.py) as copied into the
companion folder of a scene that needs it."""
FALLOFF_TEXELS = 512
"""Edge of a spot's falloff texture: the smoothstep varies over hundreds of texels, so
bilinear lookup reproduces it to about 1e-5 (tests/truth/test_mitsuba_export.py)."""
SQUARE_FRUSTUM_CUTOFF_DEGREES = math.degrees(math.atan(math.sqrt(2.0))) + 0.5
"""Cutoff of a cone-less spot: just past the corner of its 90° square frustum
(atan √2 = 54.7° from the axis); the texture is 0 outside the square."""
EXPORT_SUFFIXES = (".xml", ".py")
OWNER_FILE = ".lpv-explorer-export"
"""The file in a companion folder (:func:`companion_folder`) listing what the export put
there: it says the folder is the export's, and which of its files a new export replaces
or removes (never a file of the user's)."""
LISTING_SCENE = "# for "
"""The listing's first lines: the scene files the folder belongs to (``s.xml`` and
``s.py`` share ``s-files/``: an export that would change a file the other still uses is
refused while the other's scene file is there)."""


def companion_folder(path: Path) -> Path:
    """The folder of the meshes and textures of the scene written as ``path``:
    ``NAME-files/`` beside ``NAME.xml`` (a name derived from the user's, so no file beside
    the scene is touched; ``NAME.xml`` and ``NAME.py`` would share it, which the listing's
    :data:`LISTING_SCENE` line prevents)."""
    path = Path(path)
    return path.with_name(f"{path.stem}-files")


class ExportError(ValueError):
    """The scene cannot be exported as asked (the message says why)."""


@dataclass
class MitsubaScene:
    """A Mitsuba scene as data: ``plugins`` maps each top-level name to a plugin
    description (a dict with ``type`` and its parameters; a ``numpy`` (4, 4) array is a
    ``to_world`` transform, a ``("rgb", values)`` tuple an RGB spectrum, ``Path`` a file
    of ``files``); ``files`` maps a file name to the bytes to write beside the scene."""

    plugins: dict[str, dict]
    files: dict[str, bytes] = field(default_factory=dict)
    width: int = 0
    height: int = 0
    integrator: str = "path"
    """Mitsuba's integrator for the scene: ``path``, or ``volpath`` when a one-sided
    surface must let shadow rays through (:mod:`explorer.truth.mitsuba_one_sided`)."""
    warnings: tuple[str, ...] = ()
    """What of the scene Mitsuba renders differently from the explorer (one line each,
    naming the mesh); the export command prints them."""

    def contents(self, path: Path, sharers: tuple[str, ...] = ()) -> dict[Path, bytes]:
        """Every file of the scene written as ``path`` (``.xml`` or ``.py``): the scene
        itself first, then the PLYs and the textures in its :func:`companion_folder`
        (the scene names them relative to its own folder), the folder's
        :data:`OWNER_FILE` last (naming ``path`` and the ``sharers``, other scene files
        using the same folder's identical files)."""
        path = Path(path)
        if path.suffix not in EXPORT_SUFFIXES:
            raise ExportError(f"the Mitsuba scene must be written to a .xml or .py file, got "
                              f"{path.name!r}")
        folder = companion_folder(path)
        placed = replace(self, plugins=_placed(self.plugins, folder.name))
        text = to_xml(placed, folder.name, path.name) if path.suffix == ".xml" else \
            to_python(placed, folder.name)
        listing = "".join(f"{LISTING_SCENE}{name}\n" for name in (path.name, *sharers)) + \
            "".join(f"{name}\n" for name in self.files)
        return {path: text.encode("utf-8"),
                **{folder / name: data for name, data in self.files.items()},
                folder / OWNER_FILE: listing.encode("utf-8")}

    def write(self, path: Path) -> list[Path]:
        """Write the scene to ``path`` (``.xml`` or ``.py``) and its files into its
        companion folder; returns every path written."""
        contents = self.contents(path)
        companion_folder(path).mkdir(exist_ok=True)
        for target, data in contents.items():
            target.write_bytes(data)
        return list(contents)


def _placed(value, folder: str):
    """``value`` (a plugin tree) with each file name (a ``Path``) inside ``folder``."""
    if isinstance(value, dict):
        return {key: _placed(item, folder) for key, item in value.items()}
    if isinstance(value, Path):
        return Path(folder) / value
    return value


# --- the scene -------------------------------------------------------------------------

def mesh_file_name(texture: int, one_sided: bool) -> str:
    """The PLY of one (texture index or −1, one-sided) group: ``scene.ply`` for the
    untextured two-sided surfaces, ``scene-one-sided.ply`` for the untextured one-sided
    ones, ``scene-tK.ply`` and ``scene-tK-one-sided.ply`` for texture K (one name per
    group)."""
    textured = f"-t{texture}" if texture >= 0 else ""
    return f"{Path(MESH_FILE).stem}{textured}{'-one-sided' if one_sided else ''}.ply"


def export_scene(scene, width: int, height: int) -> MitsubaScene:
    """The Mitsuba description of ``scene`` (an ``explorer.scene.Scene`` with its overrides
    applied, e.g. ``scene_for(settings)``) seen at ``width × height`` pixels."""
    if width < 1 or height < 1:
        raise ExportError(f"the image needs at least one pixel, got {width}×{height}")
    files: dict[str, bytes] = {}
    plugins: dict[str, dict] = {"camera": camera_sensor(scene.camera, width, height)}
    warnings: tuple[str, ...] = ()
    groups = surface_groups(scene)
    for key, corners in groups.items():
        texture, one_sided = key
        name = mesh_file_name(texture, one_sided)
        bsdf, texture_file = surface_bsdf(scene, texture, one_sided, corners)
        files[name] = mesh_ply(scene, corners, uv=texture_file is not None)
        if texture_file is not None:
            files[texture_file[0]] = texture_file[1]
        plugins[f"surfaces-{len(plugins)}"] = {"type": "ply", "filename": Path(name),
                                               "bsdf": bsdf}
        warnings += _approximations(scene, texture, corners, name)
    integrator = "path"
    if any(one_sided for _, one_sided in groups):
        files[ONE_SIDED_PLUGIN_FILE] = Path(mitsuba_one_sided.__file__).read_bytes()
        integrator = mitsuba_one_sided.INTEGRATOR
    for index, light in enumerate(scene.lights):
        emitter, texture = light_emitter(light, scene.bounds_min, scene.bounds_max)
        if texture is not None:
            name = f"spot-{index}.pfm"
            files[name] = texture
            emitter["texture"] = {"type": "bitmap", "filename": Path(name), "raw": True,
                                  "filter_type": "bilinear", "wrap_mode": "clamp"}
        plugins[f"light-{index}"] = emitter
    return MitsubaScene(plugins, files, width, height, integrator, warnings)


def _approximations(scene, texture: int, corners: np.ndarray, mesh: str) -> tuple[str, ...]:
    """The warning of a group the export cannot render as the explorer does: a textured
    group whose corners carry several albedo factors gets the texture sampled at its
    corners (Mitsuba reads one factor per bitmap), not per pixel."""
    if texture < 0 or len(np.unique(np.asarray(scene.albedo)[corners], axis=0)) == 1:
        return ()
    return (f"{mesh}: texture {texture} under several material colours is exported "
            f"sampled at the triangles' corners, not per pixel as the explorer draws it",)


def surface_groups(scene) -> dict[tuple[int, bool], np.ndarray]:
    """The scene's corners grouped by (texture index or −1, one-sided): one Mitsuba shape
    each (``Scene.draw_runs``, the runs the explorer draws)."""
    groups: dict[tuple[int, bool], list[np.ndarray]] = {}
    for first, count, texture, one_sided in scene.draw_runs():
        groups.setdefault((int(texture), bool(one_sided)), []).append(
            np.arange(first, first + count))
    return {key: np.concatenate(parts) for key, parts in groups.items()}


def surface_bsdf(scene, texture: int, one_sided: bool, corners: np.ndarray
                 ) -> tuple[dict, tuple[str, bytes] | None]:
    """The BSDF of one group of corners, and the texture file it reads (None: none): a
    Lambertian whose reflectance is the linear albedo per corner (the PLY's vertex
    colour), or, for a textured group whose corners share one albedo factor, the texture
    times that factor as a bitmap at the corners' uv (per pixel, bilinear, repeating, as
    the explorer samples it; a group with several factors gets the texture sampled at its
    corners, ``Scene.corner_albedo``). Two-sided unless the group is one-sided: then the
    diffuse is the front of ``lpv_one_sided``, absent from behind for the camera and the
    lights as in the explorer. The one place that says where the albedo comes from."""
    reflectance: dict = {"type": "mesh_attribute", "name": "vertex_color"}
    texture_file = None
    if texture >= 0:
        factors = np.unique(np.asarray(scene.albedo)[corners], axis=0)
        if len(factors) == 1:
            image = np.asarray(scene.textures[texture], np.float32) * factors[0]
            name = f"texture-{texture}.pfm"
            texture_file = (name, pfm_bytes(image))
            reflectance = {"type": "bitmap", "filename": Path(name), "raw": True,
                           "filter_type": "bilinear", "wrap_mode": "repeat"}
    diffuse = {"type": "diffuse", "reflectance": reflectance}
    if one_sided:
        return {"type": mitsuba_one_sided.PLUGIN, "front": diffuse}, texture_file
    return {"type": "twosided", "material": diffuse}, texture_file


def mesh_ply(scene, corners: np.ndarray | None = None, uv: bool = False) -> bytes:
    """Binary little-endian PLY of the triangle soup (``corners``: which, default all):
    per corner its position, normal and linear albedo (``r g b`` floats, Mitsuba's
    ``vertex_color``; the texture sampled at the corner for a textured one) and, with
    ``uv``, its texture coordinates (``u v``, v flipped: Mitsuba's (0, 0) is the image's
    top-left, the scene's its bottom-left), three corners a face."""
    corners = np.arange(len(scene.positions)) if corners is None else corners
    positions = np.asarray(scene.positions, np.float32)[corners]
    normals = np.asarray(scene.normals, np.float32)[corners]
    albedo = np.asarray(scene.corner_albedo(), np.float32)[corners]
    columns = [positions, normals, albedo]
    names = ["x", "y", "z", "nx", "ny", "nz", "r", "g", "b"]
    if uv:
        coordinates = np.asarray(scene.uv, np.float32)[corners]
        columns.append(np.stack([coordinates[:, 0], 1.0 - coordinates[:, 1]], axis=1))
        names += ["u", "v"]
    count = len(positions)
    header = "\n".join([
        "ply", "format binary_little_endian 1.0", f"element vertex {count}",
        *(f"property float {name}" for name in names),
        f"element face {count // 3}", "property list uchar int vertex_indices",
        "end_header"]) + "\n"
    vertices = np.ascontiguousarray(np.hstack(columns), "<f4")
    faces = np.empty(count // 3, dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"] = 3
    faces["i"] = np.arange(count, dtype=np.int32).reshape(-1, 3)
    return header.encode("ascii") + vertices.tobytes() + faces.tobytes()


def pfm_bytes(image: np.ndarray) -> bytes:
    """A float image as PFM (``Pf`` grey (H, W), ``PF`` colour (H, W, 3); rows stored
    bottom first, little endian)."""
    image = np.asarray(image, np.float32)
    height, width = image.shape[:2]
    kind = "PF" if image.ndim == 3 else "Pf"
    header = f"{kind}\n{width} {height}\n-1.0\n".encode("ascii")
    return header + np.ascontiguousarray(image[::-1], "<f4").tobytes()


def _frame_to_world(eye, forward, up) -> np.ndarray:
    """Mitsuba's ``look_at`` frame as a matrix: local +z along ``forward``, +y ``up``,
    +x to the image's left (Mitsuba's sensors and spots use this frame)."""
    forward = np.asarray(forward, np.float64)
    forward = forward / np.linalg.norm(forward)
    left = np.cross(np.asarray(up, np.float64), forward)
    left /= np.linalg.norm(left)
    true_up = np.cross(forward, left)
    matrix = np.eye(4)
    matrix[:3, 0], matrix[:3, 1], matrix[:3, 2], matrix[:3, 3] = left, true_up, forward, eye
    return matrix


def view_frame(view: np.ndarray) -> np.ndarray:
    """The Mitsuba frame of an explorer view matrix (rows right, up, −forward; look_at in
    explorer/scene/transforms.py): the same eye, forward and up, so the image and a
    square frustum line up with the explorer's."""
    rotation = view[:3, :3]
    eye = -rotation.T @ view[:3, 3]
    return _frame_to_world(eye, -rotation[2], rotation[1])


def camera_sensor(camera, width: int, height: int) -> dict:
    """A perspective sensor with the explorer camera's frame and vertical field of view;
    a box filter makes each pixel the mean over its area, as a supersampled G-buffer."""
    return {"type": "perspective", "fov": float(camera.fov_y_degrees), "fov_axis": "y",
            "to_world": view_frame(camera.view_matrix()),
            "film": {"type": "hdrfilm", "width": int(width), "height": int(height),
                     "pixel_format": "rgb", "rfilter": {"type": "box"}}}


def light_emitter(light, bounds_min, bounds_max) -> tuple[dict, bytes | None]:
    """The emitter of one explorer light and, for a spot, its falloff texture (PFM)."""
    colour = np.asarray(light.colour, np.float64)
    if isinstance(light, PointLight):
        return {"type": "point", "position": tuple(map(float, light.position)),
                "intensity": ("rgb", tuple(light.intensity * colour))}, None
    if isinstance(light, DirectionalLight):
        irradiance = light.irradiance(bounds_min, bounds_max)
        return {"type": "directional", "direction": tuple(map(float, light.direction)),
                "irradiance": ("rgb", tuple(irradiance * colour))}, None
    if isinstance(light, SpotLight):
        cutoff = (light.cone_degrees[1] if light.has_cone
                  else SQUARE_FRUSTUM_CUTOFF_DEGREES)
        return {"type": "spot", "to_world": view_frame(light.view_matrix()),
                "cutoff_angle": float(cutoff), "beam_width": float(cutoff),
                "intensity": ("rgb", tuple(light.intensity * colour))}, \
            pfm_bytes(spot_falloff_texture(light, cutoff))
    raise ExportError(f"light {getattr(light, 'name', light)!r} of kind "
                      f"{getattr(light, 'kind', type(light).__name__)!r} has no Mitsuba "
                      f"counterpart")


def spot_falloff_texture(light: SpotLight, cutoff_degrees: float,
                         texels: int = FALLOFF_TEXELS) -> np.ndarray:
    """(texels, texels) float32: the explorer's falloff ``f`` over the directions Mitsuba's
    spot maps its texture onto. Mitsuba looks texel (u, v) up for the local direction
    ``d`` at ``u = ½ + ½·(d_x/d_z)/tan(cutoff)`` (and v from d_y), so texel centre (u, v)
    is the direction ``((2u − 1)·t, (2v − 1)·t, 1)``, t = tan(cutoff). A cone: the
    smoothstep of cos θ (:func:`spot_falloff`); no cone: 1 inside the square frustum
    ``|x|, |y| ≤ 1`` (texel centres decide, half a texel of 1/512 of the edge)."""
    t = math.tan(math.radians(cutoff_degrees))
    centres = (np.arange(texels) + 0.5) / texels
    x, y = np.meshgrid((2.0 * centres - 1.0) * t, (2.0 * centres - 1.0) * t)
    if light.has_cone:
        cos_axis = 1.0 / np.sqrt(1.0 + x * x + y * y)
        values = spot_falloff(cos_axis, *light.cone_cosines)
    else:
        values = ((np.abs(x) <= 1.0) & (np.abs(y) <= 1.0)).astype(np.float64)
    return values.astype(np.float32)


# --- writers ---------------------------------------------------------------------------

def _xml_value(name: str, value, indent: str) -> list[str]:
    if isinstance(value, dict):
        return _xml_plugin(value, indent, name)
    if isinstance(value, np.ndarray):
        numbers = " ".join(f"{v:.9g}" for v in value.reshape(-1))
        return [f'{indent}<transform name="{name}"><matrix value="{numbers}"/></transform>']
    if isinstance(value, tuple) and value and value[0] == "rgb":
        numbers = ", ".join(f"{v:.9g}" for v in value[1])
        return [f'{indent}<rgb name="{name}" value="{numbers}"/>']
    if isinstance(value, bool):
        return [f'{indent}<boolean name="{name}" value="{str(value).lower()}"/>']
    if isinstance(value, int):
        return [f'{indent}<integer name="{name}" value="{value}"/>']
    if isinstance(value, float):
        return [f'{indent}<float name="{name}" value="{value:.9g}"/>']
    if isinstance(value, tuple):
        numbers = ", ".join(f"{v:.9g}" for v in value)
        return [f'{indent}<point name="{name}" value="{numbers}"/>'] if name == "position" \
            else [f'{indent}<vector name="{name}" value="{numbers}"/>']
    return [f'{indent}<string name="{name}" value="{value}"/>']


_XML_TAGS = {"perspective": "sensor", "hdrfilm": "film", "box": "rfilter", "ply": "shape",
             "twosided": "bsdf", "diffuse": "bsdf", "mesh_attribute": "texture",
             "bitmap": "texture", "point": "emitter", "spot": "emitter",
             "directional": "emitter", "path": "integrator", "volpath": "integrator",
             "independent": "sampler", mitsuba_one_sided.PLUGIN: "bsdf"}


def _xml_plugin(plugin: dict, indent: str, name: str | None = None) -> list[str]:
    tag = _XML_TAGS[plugin["type"]]
    named = f' name="{name}"' if name is not None and tag in ("texture", "bsdf") else ""
    lines = [f'{indent}<{tag} type="{plugin["type"]}"{named}>']
    for key, value in plugin.items():
        if key != "type":
            lines += _xml_value(key, value, indent + "    ")
    return lines + [f"{indent}</{tag}>"]


def to_xml(scene: MitsubaScene, folder: str = ".", name: str = "scene.xml") -> str:
    """The scene as Mitsuba 3 XML (``mitsuba -m scalar_rgb scene.xml`` renders it, all
    bounces; a scene with one-sided surfaces names a plugin that ``python
    folder/lpv_one_sided.py name`` registers before it renders)."""
    lines = ['<scene version="3.0.0">']
    if scene.integrator != "path":
        lines.append(f"    <!-- one-sided surfaces: render with python "
                     f"{folder}/{ONE_SIDED_PLUGIN_FILE} {name} [OUT.exr [SPP]] -->")
    lines.append(f'    <integrator type="{scene.integrator}"><integer name="max_depth" '
                 f'value="-1"/></integrator>')
    for plugin in scene.plugins.values():
        lines += _xml_plugin(plugin, "    ")
    return "\n".join(lines + ["</scene>", ""])


def _py_value(value, indent: str) -> str:
    if isinstance(value, dict):
        inner = indent + "    "
        items = ",\n".join(f"{inner}{key!r}: {_py_value(item, inner)}"
                           for key, item in value.items())
        return "{\n" + items + f"\n{indent}}}"
    if isinstance(value, np.ndarray):
        rows = ", ".join("[" + ", ".join(f"{v:.9g}" for v in row) + "]" for row in value)
        return f"mi.ScalarTransform4f([{rows}])"
    if isinstance(value, tuple) and value and value[0] == "rgb":
        return "{'type': 'rgb', 'value': [" + ", ".join(f"{v:.9g}" for v in value[1]) + "]}"
    if isinstance(value, Path):
        return f"str(HERE / {str(value)!r})"
    if isinstance(value, tuple):
        return "[" + ", ".join(f"{v:.9g}" for v in value) + "]"
    return repr(value)


def to_python(scene: MitsubaScene, folder: str = "") -> str:
    """The scene as a Python script: ``python scene.py [OUT.exr [SPP]]`` loads it with
    ``mi.load_dict`` and renders all bounces (registering the one-sided plugin from the
    companion ``folder`` when the scene needs it)."""
    body = ",\n".join(f"    {name!r}: {_py_value(plugin, '    ')}"
                      for name, plugin in scene.plugins.items())
    plugin = "" if scene.integrator == "path" else (
        f"sys.path.insert(0, str(HERE / {folder!r}))\n"
        f"import lpv_one_sided  # noqa: E402\n\nlpv_one_sided.register(mi)\n")
    return f'''"""A scene exported by lpv-explorer export-mitsuba (Mitsuba 3)."""
import sys
from pathlib import Path

import mitsuba as mi

mi.set_variant("scalar_rgb")
HERE = Path(__file__).resolve().parent
{plugin}SCENE = {{
    "type": "scene",
    "integrator": {{"type": {scene.integrator!r}, "max_depth": -1}},
{body},
}}

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else str(HERE / "render.exr")
    spp = int(sys.argv[2]) if len(sys.argv) > 2 else 256
    image = mi.render(mi.load_dict(SCENE), spp=spp)
    mi.util.write_bitmap(out, image)
    print("wrote", out)
'''
