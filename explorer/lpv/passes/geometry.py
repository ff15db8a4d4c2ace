"""Geometry volume (fuzzy occlusion): occluder surfels from the VPLs in a grid whose cell
centres sit on the light grid's corners (docs/MODEL.md "Geometry volume"). With several
RSM views (several lights, a point light's faces) each view's volume is built alone and
merged per cell by :func:`merge_volumes` (docs/MODEL.md "Several lights"); with camera
occluders the camera's G-buffer pixels that no RSM view sees add their surfels to the
merged volume (docs/MODEL.md "Camera occluders")."""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.lpv.corrections import uniforms_read_by
from explorer.lpv.grid import GridSpec, cube_edge, grid_cells, shape_text
from explorer.lpv.passes.inject import bind_vpl_textures, vpl_count
from explorer.lpv.passes.light_records import LightRecordBuffer
from explorer.lpv.passes.rsm import LightView
from explorer.lpv.passes.textures import (
    LayeredTarget,
    VolumeTexture,
    copied_apart,
    copy_volume,
    default_context,
    dispatch_size,
    draw_points_additively,
    image_format_defines,
    per_context,
    point_batches,
    programs_for,
)
from explorer.lpv.settings import Corrections
from explorer.lpv.vpl import VplArrays, VplTextures
from explorer.scene.transforms import gl_matrix

GEOMETRY_MODES = ("one-sided", "double-sided")
ALBEDO_UNIT = 3
"""Sampler unit of the VPL albedo texture (units 0..2 hold position, normal, flux)."""
CAMERA_UNITS = {"u_surfel_position": 0, "u_surfel_normal": 1, "u_surfel_albedo": 2,
                "u_shadow_position": 3, "u_shadow_normal": 4}
"""Sampler units of the camera-surfel program (G-buffer, then the RSM views' shadow
maps)."""


def volume_size(cells: tuple[int, int, int]) -> tuple[int, int, int]:
    """Texels of the geometry volume of a light grid of ``cells``: one more a side (texel
    ``j`` sits on the light grid's corner ``j``)."""
    return (cells[0] + 1, cells[1] + 1, cells[2] + 1)


def camera_pixel_area(fov_y_degrees: float, height: int) -> float:
    """Area of one camera pixel at view depth 1 on a plane facing the camera,
    ``(2·tan(fov_y/2)/H)²`` (derivation occlusion.camera_surfel_area): a surfel at depth
    ``w`` covers this times ``w²``, the RSM texel's rule."""
    edge = 2.0 * math.tan(math.radians(fov_y_degrees) / 2.0) / int(height)
    return edge * edge


@dataclass(frozen=True)
class CameraSurfels:
    """The camera's G-buffer as occluder surfels, and the RSM views' shadow maps to leave
    out the surfaces any view already holds (docs/MODEL.md "Camera occluders")."""

    position: moderngl.Texture
    """G-buffer world position, w = 1 where a surface was seen."""
    normal: moderngl.Texture
    """G-buffer normal facing the camera."""
    albedo: moderngl.Texture
    view: np.ndarray
    """The camera's 4×4 view matrix (numpy, world → view)."""
    pixel_area: float
    """:func:`camera_pixel_area` of the camera and image height."""
    shadow: VplTextures
    """The RSM (one view) or the RSM atlas: position (w = seen) and normal (w = view depth
    from the light)."""
    views: Sequence[LightView]
    """The RSM views whose shadow maps ``shadow`` holds."""
    tiles: Sequence[tuple[int, int]] | None = None
    """Lower-left texel of each view's map in ``shadow`` (None: one view at (0, 0))."""

    @property
    def count(self) -> int:
        width, height = self.position.size
        return width * height


class GeometryVolume:
    """One RGBA 3D texture of L1 SH blocking, ``(nx+1)×(ny+1)×(nz+1)`` texels for an
    ``nx×ny×nz`` light grid (``cells``; one number: a cube): texel ``j`` is centred on the
    light grid's corner ``j``. A second texture of the same
    size, ``albedo``, holds Σ (A/cell_size²)·(a_r, a_g, a_b, 1) of the cell's surfels
    (docs/MODEL.md "More bounces"); it stays zero where no albedo was injected."""

    def __init__(self, ctx: moderngl.Context, cells: int | Sequence[int],
                 fmt: str = "rgba32f") -> None:
        self.cells = grid_cells(cells)
        corners = volume_size(self.cells)
        self.volume = VolumeTexture(ctx, corners, fmt)
        self.texture: moderngl.Texture3D = self.volume.texture
        self.albedo = VolumeTexture(ctx, corners, fmt)
        self.albedo.clear()

    @property
    def resolution(self) -> int:
        """Cells per axis of the light grid when it is a cube (:func:`cube_edge`)."""
        return cube_edge(self.cells)

    @property
    def format(self) -> str:
        return self.volume.format

    def read(self) -> np.ndarray:
        """float32 ``(nx+1, ny+1, nz+1, 4)``."""
        return self.volume.read()

    def read_albedo(self) -> np.ndarray:
        """float32 ``(nx+1, ny+1, nz+1, 4)``: area-weighted albedo sums and areas."""
        return self.albedo.read()

    def write(self, volume: np.ndarray, albedo: np.ndarray | None = None) -> None:
        """Upload the blocking SH and (optionally; else zero) the albedo sums."""
        self.volume.write(volume)
        if albedo is None:
            self.albedo.clear()
        else:
            self.albedo.write(albedo)

    def clear(self) -> None:
        self.volume.clear()
        self.albedo.clear()

    def use_as_texture(self, location: int) -> None:
        self.texture.use(location)

    def release(self) -> None:
        self.volume.release()
        self.albedo.release()


class GeometryPass:
    """Injects occluder surfels from a VPL texture set (the volume is overwritten)."""

    STAGE = "geometry"
    """Its program reads this stage's correction switches."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._layers: LayeredTarget | None = None
        self._lights = LightRecordBuffer(ctx)

    @staticmethod
    def unit_count(cells: tuple[int, int, int], vpls: int | None,
                   camera: int | None = None) -> int:
        """Units of :meth:`run_units` for a light grid of ``cells``, ``vpls`` VPLs and
        ``camera`` camera surfels (None: not drawn): the surfels' draws, a batch a unit
        (:func:`point_batches`), then each target's copy when its volumes are copied apart
        (:func:`copied_apart`; else with the last draw)."""
        draws = sum(len(point_batches(count)) for count in (vpls, camera) if count is not None)
        return max(draws, 1) + (2 if copied_apart(volume_size(cells)) else 0)

    def run(self, vpls: VplTextures | None, spec: GridSpec, corrections: Corrections,
            mode: str, out: GeometryVolume, camera: CameraSurfels | None = None) -> None:
        """Inject the VPLs' surfels (None: none) and ``camera``'s, when given, into
        ``out``."""
        for _ in self.run_units(vpls, spec, corrections, mode, out, camera):
            pass

    def run_units(self, vpls: VplTextures | None, spec: GridSpec, corrections: Corrections,
                  mode: str, out: GeometryVolume, camera: CameraSurfels | None = None
                  ) -> Iterator[None]:
        """:meth:`run`'s work as a generator of :meth:`unit_count` units (the draws into the
        layers, which keep the sums, then the volume's copy and the albedo's), yielding
        after every unit but its last: the same GL work in the same order."""
        if mode not in GEOMETRY_MODES:
            raise ValueError(f"geometry mode must be one of {GEOMETRY_MODES}, got {mode!r}")
        if out.cells != spec.cells:
            raise ValueError(f"the geometry volume belongs to a {shape_text(out.cells)} grid "
                             f"but the grid spec has {shape_text(spec.cells)} cells")
        if vpls is None and camera is None:
            raise ValueError("the geometry pass needs VPLs, camera surfels or both")
        size = volume_size(spec.cells)
        layers = self._layers
        if layers is None or layers.shape != size or layers.format != out.format:
            if layers is not None:
                layers.release()
            layers = self._layers = LayeredTarget(self.ctx, size, 2, out.format)
        if vpls is not None:
            yield from self._draw_vpl_surfels(vpls, spec, corrections, mode, layers)
        if camera is not None:
            if vpls is not None:
                yield
            yield from self._draw_camera_surfels(camera, spec, corrections, mode, layers,
                                                 clear=vpls is None)
        apart = copied_apart(size)
        for layer, volume in zip(layers.layers, (out.volume, out.albedo)):
            if apart:
                yield
            copy_volume(self.programs, layer, volume)

    def _draw_vpl_surfels(self, vpls: VplTextures, spec: GridSpec, corrections: Corrections,
                          mode: str, layers: LayeredTarget) -> Iterator[None]:
        """Clear ``layers`` and draw the VPLs' surfels into them, a batch a unit
        (:func:`point_batches`; each binds all it reads)."""
        for first, count in point_batches(vpl_count(vpls)):
            if first:
                yield
            program = self.programs.get("geometry_inject.glsl")
            if vpls.albedo is not None:
                vpls.albedo.use(ALBEDO_UNIT)
            set_uniforms(program, {
                **spec.uniforms(), **corrections.as_uniforms(), **bind_vpl_textures(vpls),
                "u_vpl_albedo": ALBEDO_UNIT, "u_has_albedo": vpls.albedo is not None,
                "u_vpl_texel_area": float(vpls.texel_area),
                "u_vpl_orthographic": vpls.projection == "orthographic",
                "u_double_sided": mode == "double-sided",
            }, reads=uniforms_read_by(self.STAGE))
            draw_points_additively(self.ctx, program, layers, count, clear=not first,
                                   first=first)

    def _draw_camera_surfels(self, camera: CameraSurfels, spec: GridSpec,
                             corrections: Corrections, mode: str, layers: LayeredTarget,
                             clear: bool) -> Iterator[None]:
        """Draw the camera's surfels into ``layers`` (added to what they hold unless
        ``clear``), a batch a unit (:func:`point_batches`; each binds all it reads)."""
        textures = (camera.position, camera.normal, camera.albedo, camera.shadow.position,
                    camera.shadow.normal)
        for first, count in point_batches(camera.count):
            if first:
                yield
            program = self.programs.get("geometry_inject.glsl", {"CAMERA_SURFELS": 1})
            for texture, unit in zip(textures, CAMERA_UNITS.values()):
                texture.use(unit)
            light_count = self._lights.bind(camera.views, camera.tiles)
            set_uniforms(program, {
                **spec.uniforms(), **corrections.as_uniforms(), **CAMERA_UNITS,
                "u_light_count": light_count,
                "u_camera_view": gl_matrix(camera.view),
                "u_pixel_area": float(camera.pixel_area),
                "u_double_sided": mode == "double-sided",
            }, reads=uniforms_read_by(self.STAGE))
            draw_points_additively(self.ctx, program, layers, count,
                                   clear=clear and not first, first=first)

    def release(self) -> None:
        if self._layers is not None:
            self._layers.release()
            self._layers = None
        self._lights.release()


def merge_volumes(programs: ProgramCache, merged: GeometryVolume,
                  view: GeometryVolume, add: bool = False) -> None:
    """Fold ``view`` into ``merged`` in place: per geometry cell the volume whose band-0
    coefficient (the surfels' area there) is larger wins, with its albedo sums; with
    ``add``, ``view`` is added instead (the camera occluders' surfels, which no view holds)
    (``shaders/geometry_merge.glsl``). Units 0 and 1 hold ``view`` while it runs."""
    if merged.cells != view.cells or merged.format != view.format:
        raise ValueError("merged geometry volumes must have one shape and format")
    program = programs.get("geometry_merge.glsl", {**image_format_defines(merged.format),
                                                   "MERGE_ADD": int(add)})
    view.volume.texture.use(0)
    view.albedo.texture.use(1)
    merged.volume.bind_image(0, read=True, write=True)
    merged.albedo.bind_image(1, read=True, write=True)
    set_uniforms(program, {"u_view_blocker": 0, "u_view_albedo": 1})
    program.run(*dispatch_size(merged.volume.shape))
    programs.ctx.memory_barrier()


class MergedGeometryPass:
    """The geometry volume of every RSM view, merged per cell (docs/MODEL.md "Several
    lights"), with the camera's surfels added (docs/MODEL.md "Camera occluders"): one
    :class:`GeometryPass` and the scratch volume each further view is built in."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self.single = GeometryPass(ctx, programs)
        self._scratch: GeometryVolume | None = None
        """One view's geometry volume before it is merged (several views)."""

    @staticmethod
    def unit_count(views: Sequence[int], camera: int | None,
                   cells: tuple[int, int, int]) -> int:
        """Units of :meth:`run_units` for RSM views of ``views`` VPLs each and ``camera``
        camera surfels (None: none) in a light grid of ``cells``: the first view's
        :meth:`GeometryPass.unit_count`, then each further view's and (several views) the
        camera's with one more for its merge; when the volumes are not copied apart each
        further run's first draw and its merge join the unit before."""
        alone = len(views) == 1
        count = GeometryPass.unit_count(cells, views[0], camera if alone else None)
        further = [GeometryPass.unit_count(cells, vpls) for vpls in views[1:]]
        if camera is not None and not alone:
            further.append(GeometryPass.unit_count(cells, None, camera))
        apart = copied_apart(volume_size(cells))
        return count + sum(units + 1 if apart else units - 1 for units in further)

    def run(self, occluders: Sequence[VplTextures], spec: GridSpec, corrections: Corrections,
            mode: str, out: GeometryVolume, camera: CameraSurfels | None = None) -> None:
        """Into ``out``: the first view's volume, then each further view's built in the
        scratch volume and folded in by :func:`merge_volumes`; then ``camera``'s surfels,
        added (they hold only surfaces no view holds). With one view they are drawn with
        its surfels (the same sum, no scratch volume)."""
        for _ in self.run_units(occluders, spec, corrections, mode, out, camera):
            pass

    def run_units(self, occluders: Sequence[VplTextures], spec: GridSpec,
                  corrections: Corrections, mode: str, out: GeometryVolume,
                  camera: CameraSurfels | None = None) -> Iterator[None]:
        """:meth:`run`'s work as a generator of :meth:`unit_count` units (each view's
        :meth:`GeometryPass.run_units`, each merge), yielding after every unit but its
        last."""
        alone = len(occluders) == 1
        apart = copied_apart(volume_size(spec.cells))
        yield from self.single.run_units(occluders[0], spec, corrections, mode, out,
                                         camera if alone else None)
        if alone:
            return
        scratch = self._scratch_like(out)
        further: list[tuple[VplTextures | None, CameraSurfels | None]] = [
            (vpls, None) for vpls in occluders[1:]]
        if camera is not None:
            further.append((None, camera))
        for vpls, surfels in further:
            if apart:
                yield
            yield from self.single.run_units(vpls, spec, corrections, mode, scratch, surfels)
            if apart:
                yield
            merge_volumes(self.programs, out, scratch, add=surfels is not None)

    def _scratch_like(self, volume: GeometryVolume) -> GeometryVolume:
        scratch = self._scratch
        if scratch is None or scratch.cells != volume.cells or \
                scratch.format != volume.format:
            if scratch is not None:
                scratch.release()
            scratch = self._scratch = GeometryVolume(self.ctx, volume.cells,
                                                     volume.format)
        return scratch

    def release(self) -> None:
        self.single.release()
        if self._scratch is not None:
            self._scratch.release()
            self._scratch = None


def merged_volume_reference(volumes: list[np.ndarray]) -> np.ndarray:
    """Numpy twin of :func:`merge_volumes` over ``volumes`` ((N+1)³×4 each, in order):
    per cell the first volume with the largest coefficient 0."""
    stack = np.stack([np.asarray(v, np.float64) for v in volumes])
    merged = stack[0].copy()
    for volume in stack[1:]:
        wins = volume[..., 0] > merged[..., 0]
        merged[wins] = volume[wins]
    return merged


def inject_geometry(vpls: VplArrays, spec: GridSpec, corrections: Corrections | None = None,
                    mode: str = "one-sided", ctx: moderngl.Context | None = None,
                    fmt: str = "rgba32f", with_albedo: bool = False):
    """Geometry-volume injection on the GPU from VPL arrays: float32
    ``(nx+1, ny+1, nz+1, 4)``;
    with ``with_albedo`` the pair (volume, albedo sums) (see :class:`GeometryVolume`)."""
    if not isinstance(vpls, VplArrays):
        raise TypeError(f"vpls must be a VplArrays, got {type(vpls).__name__}")
    corrections = corrections or Corrections()
    ctx = ctx or default_context()
    if vpls.count == 0:
        empty = np.zeros(volume_size(spec.cells) + (4,), np.float32)
        return (empty, empty.copy()) if with_albedo else empty
    volume = GeometryVolume(ctx, spec.cells, fmt)
    textures = VplTextures.from_arrays(ctx, vpls)
    try:
        injector = per_context(ctx, "geometry", lambda: GeometryPass(ctx, programs_for(ctx)))
        injector.run(textures, spec, corrections, mode, volume)
        return (volume.read(), volume.read_albedo()) if with_albedo else volume.read()
    finally:
        textures.release()
        volume.release()
