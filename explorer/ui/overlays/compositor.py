"""The main view's picture with the overlays drawn in the scene.

:meth:`Compositor.compose` is the one entry point the View panel calls, once per side
(A, and B in split view): it copies the image the view would show into an offscreen
framebuffer together with the depth of the frame's surfaces (the G-buffer's world positions
projected with the frame's camera, ``shaders/overlay_background.glsl``), then draws the
enabled overlays depth-tested against it and returns the texture to show.

Nothing here runs an LPV pass: every overlay reads FrameResult arrays, uploaded to the GPU
only when the array (or the overlay setting that derives from it) changes, and the whole
picture is redrawn only when the result, the base image or an overlay setting changed.
"""

from __future__ import annotations

import time
from dataclasses import astuple

import moderngl
import numpy as np

from explorer.gl.fullscreen import FullscreenTriangle
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import scoped
from explorer.lpv.grid import GridSpec
from explorer.scene.transforms import gl_matrix
from explorer.ui.camera import view_axes
from explorer.ui.overlays import quantities as Q
from explorer.ui.overlays.glyphs import GlyphRenderer
from explorer.ui.overlays.lines import LineRenderer
from explorer.ui.overlays.picking import cell_at, pixel_of, view_projection
from explorer.ui.overlays.slice import SliceRenderer
from explorer.ui.overlays.splats import SplatRenderer
from explorer.ui.state import OverlayState
from explorer.ui.weak_version import WeakVersion

BACKGROUND = "overlay_background.glsl"
LATTICE_COLOUR = (1.0, 1.0, 1.0, 0.35)
CASCADE_COLOURS = ((0.35, 0.9, 1.0, 0.95), (1.0, 0.72, 0.3, 0.95), (0.6, 1.0, 0.4, 0.95),
                   (1.0, 0.45, 0.8, 0.95))
PICK_COLOUR = (1.0, 0.95, 0.25, 1.0)
LIFT_CELLS = 0.05
"""Discs lying on a surface are lifted by this many cells along their normal."""
SHADER_POLL_S = 0.5
MAX_SPLAT_CELLS = 1.0
"""No VPL disc is wider than this many cells (one VPL of a coarse RSM can be large)."""


_VALUES = (int, float, str, bool, bytes, tuple, type(None), GridSpec)
"""Version parts compared by value; anything else (arrays, results) by identity."""


def vpl_radius_scale(size: float, drawn: int, total: int) -> float:
    """Disc radius over surfel radius when ``drawn`` of ``total`` VPLs are shown: each disc
    stands for total/drawn surfels, so the radius grows by √(total/drawn) and the discs
    cover ``size²`` of the lit surfaces at any density."""
    return size * (total / drawn) ** 0.5 if drawn > 0 else size


class _Target:
    """An RGBA8 colour and a depth texture in one framebuffer."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int]) -> None:
        self.size = size
        self.colour = ctx.texture(size, 4, dtype="f1")
        self.colour.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.depth = ctx.depth_texture(size)
        self.depth.compare_func = ""          # read as plain values (overlay_background)
        self.depth.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self.framebuffer = ctx.framebuffer([self.colour], self.depth)

    def release(self) -> None:
        for item in (self.framebuffer, self.colour, self.depth):
            item.release()


class _Side:
    """Framebuffers, renderers and upload versions of one side of the view.

    Two layers, so that moving the slice does not redraw what does not depend on it: the
    static layer holds the frame with its depth, the blockers and the VPLs (tens of
    thousands of discs); the output layer copies it and adds the glyphs, wireframes, the
    slice and the picked point."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.slice = SliceRenderer(ctx, programs)
        self.glyphs = GlyphRenderer(ctx, programs)
        self.splats = SplatRenderer(ctx, programs)
        self.lines = LineRenderer(ctx, programs)
        self.static: _Target | None = None     # the frame + overlays tied to the frame
        self.output: _Target | None = None     # the static layer + the slice's overlays
        self.position: moderngl.Texture | None = None
        self.key: WeakVersion | None = None
        """The picture in :attr:`output` (its frame held weakly: the compositor keeps no
        frame alive, the frame on screen is the controller's)."""
        self.static_key: WeakVersion | None = None
        self.static_notes: list[str] = []
        self.field: Q.SliceField | None = None   # the slice of the last picture, if shown
        self.field_cache: Q.SliceField | None = None
        self._versions: dict[str, WeakVersion] = {}

    def stale(self, name: str, *parts) -> bool:
        """Whether the upload ``name`` is out of date for ``parts`` (objects compared by
        identity through weak references: an upload never keeps its frame alive, and a
        freed one's id names no version). Records ``parts`` as the new version."""
        version = self._versions.get(name)
        if version is not None and version.matches(parts):
            return False
        self._versions[name] = WeakVersion(parts, _VALUES)
        return True

    def forget(self, name: str) -> None:
        self._versions.pop(name, None)

    def allocate(self, size: tuple[int, int]) -> None:
        if self.output is not None and self.output.size == size:
            return
        self.release_targets()
        self.static, self.output = _Target(self.ctx, size), _Target(self.ctx, size)

    def release_targets(self) -> None:
        for target in (self.static, self.output):
            if target is not None:
                target.release()
        self.static = self.output = None
        self.key = self.static_key = None

    def release(self) -> None:
        self.release_targets()
        if self.position is not None:
            self.position.release()
            self.position = None
        for renderer in (self.slice, self.glyphs, self.splats, self.lines):
            renderer.release()
        self._versions.clear()


class Compositor:
    def __init__(self, ctx: moderngl.Context, programs: ProgramCache | None = None) -> None:
        self.ctx = ctx
        self._owns_programs = programs is None
        self.programs = programs or ProgramCache(ctx)
        self._triangle = FullscreenTriangle(ctx)
        self._sides: dict[str, _Side] = {}
        self._external: dict[int, moderngl.Texture] = {}
        self.notes: dict[str, list[str]] = {}
        """Per side, why an enabled overlay is not drawn (e.g. the steps are not kept)."""
        self.compositions = 0
        """How many pictures were drawn (an unchanged request reuses the last one)."""
        self._shader_poll = 0.0
        self.static_draws = 0
        """How many times a static layer (frame, blockers, VPLs) was drawn."""

    # ------------------------------------------------------------------ entry point
    def compose(self, side: str, result, base_texture: int, base_top_first: bool,
                overlays: OverlayState, base_version: object = None) -> int:
        """The GL name of a texture (row 0 at the bottom, as GL draws) holding the view's
        image of ``result`` (``base_texture``, stored top row first if ``base_top_first``)
        with the overlays drawn in the scene. ``base_version``: what the base texture
        holds, when the same texture is redrawn with other contents (the view composer's
        images: a new exposure, a progressive picture)."""
        self._reload_shaders()
        height, width = result.image_size
        layers = self._sides.get(side)
        if layers is None:
            layers = self._sides[side] = _Side(self.ctx, self.programs)
        shared = self._shared_top(side, overlays)
        key = (result, int(base_texture), base_version, bool(base_top_first),
               astuple(overlays), (width, height), shared)
        if layers.key is not None and layers.key.matches(key) and layers.output is not None:
            return layers.output.colour.glo
        layers.allocate((width, height))
        layers.key = WeakVersion(key, _VALUES)
        layers.shared_top = shared
        o = overlays
        static_key = (result, int(base_texture), base_version, bool(base_top_first),
                      (width, height), o.vpls, o.vpl_density, o.vpl_size, o.blockers,
                      o.cascade)
        vp = view_projection(result)
        notes: list[str] = []
        try:
            if layers.static_key is None or not layers.static_key.matches(static_key):
                self._background(layers, result, base_texture, base_top_first, vp)
                self._static_overlays(layers, result, overlays, vp, layers.static_notes)
                layers.static_key = WeakVersion(static_key, _VALUES)
                self.static_draws += 1
            notes += layers.static_notes
            self._copy(layers.static, layers.output)
            self._draw_overlays(layers, result, overlays, vp, notes)
        finally:
            self.ctx.depth_func = "<"
        self.notes[side] = notes
        self.compositions += 1
        return layers.output.colour.glo

    def _reload_shaders(self) -> None:
        """Hot reload: recompile the overlay programs whose files changed (polled every
        SHADER_POLL_S; a failed compile keeps the last good program, its log in
        ``self.programs.errors``) and redraw every side."""
        now = time.monotonic()
        if now - self._shader_poll < SHADER_POLL_S:
            return
        self._shader_poll = now
        if self.programs.reload_if_changed():
            for layers in self._sides.values():
                layers.key = layers.static_key = None

    def _shared_top(self, side: str, overlays: OverlayState) -> float | None:
        """The top of A's slice scale when ``side`` is another side of a comparison that
        shares it (``overlays.shared_scale``), else None (its own scale)."""
        if side == "A" or not overlays.slice or not overlays.shared_scale:
            return None
        field = self.slice_field("A")
        if field is None or field.colour_map != Q.resolved_colour_map(overlays):
            return None
        return field.high

    def slice_field(self, side: str) -> Q.SliceField | None:
        """The slice's field of the last picture of ``side`` (for its colour bar)."""
        layers = self._sides.get(side)
        return None if layers is None else layers.field

    def read(self, side: str) -> np.ndarray:
        """The last picture of ``side`` as (H, W, 3) uint8, top row first."""
        colour = self._sides[side].output.colour
        width, height = colour.size
        data = np.frombuffer(colour.read(), np.uint8).reshape(height, width, 4)
        return np.ascontiguousarray(data[::-1, :, :3])

    def release(self) -> None:
        for layers in self._sides.values():
            layers.release()
        self._sides.clear()
        self._external.clear()     # the view's textures belong to their owners
        self._triangle.release()
        if self._owns_programs:
            self.programs.release()

    def forget_base(self, glo: int) -> None:
        """Drop the wrapper of a base texture its owner is about to release (a texture
        made for one composition, e.g. the web site's frames), so that a later texture
        given the same GL name is wrapped anew."""
        self._external.pop(glo, None)

    # ------------------------------------------------------------------ passes
    def _base(self, glo: int, size: tuple[int, int]) -> moderngl.Texture:
        texture = self._external.get(glo)
        if texture is None:
            texture = self._external[glo] = self.ctx.external_texture(glo, size, 4, 0, "f1")
        return texture

    def _background(self, layers: _Side, result, base_texture: int, top_first: bool,
                    vp: np.ndarray) -> None:
        position = result.gbuffer_position
        if layers.stale("position", position):
            height, width = position.shape[:2]
            rows = np.ascontiguousarray(np.asarray(position, np.float32)[::-1])
            if layers.position is None or layers.position.size != (width, height):
                if layers.position is not None:
                    layers.position.release()
                layers.position = self.ctx.texture((width, height), 4, dtype="f4")
                layers.position.filter = (moderngl.NEAREST, moderngl.NEAREST)
            layers.position.write(rows.tobytes())
        layers.static_notes = []
        self._fill(layers.static, self._base(base_texture, layers.static.size), top_first,
                   depth_from=layers.position, view_projection=vp)

    def _copy(self, source: _Target, target: _Target) -> None:
        """``target`` := ``source``, colour and depth."""
        self._fill(target, source.colour, False, depth_from=source.depth)

    def _fill(self, target: _Target, colour: moderngl.Texture, top_first: bool,
              depth_from: moderngl.Texture, view_projection: np.ndarray | None = None
              ) -> None:
        """Write every pixel of ``target``: the colour of ``colour`` and the depth of
        ``depth_from``, a G-buffer position texture projected with ``view_projection``,
        or (without one) a depth texture."""
        program = self.programs.get(BACKGROUND)
        colour.use(0)
        depth_from.use(1)
        projected = view_projection is not None
        set_uniforms(program, {
            "u_base": 0, "u_position": 1, "u_depth": 1, "u_base_top_first": int(top_first),
            "u_depth_is_position": int(projected),
            "u_view_projection": gl_matrix(view_projection if projected else np.eye(4))})
        framebuffer = target.framebuffer
        with scoped(self.ctx, framebuffer, moderngl.DEPTH_TEST):
            framebuffer.viewport = (0, 0, *target.size)
            self.ctx.depth_func = "1"      # write every pixel's colour and depth
            self._triangle.draw(program)
            self.ctx.depth_func = "<"

    def _static_overlays(self, layers: _Side, result, overlays: OverlayState,
                         vp: np.ndarray, notes: list[str]) -> None:
        """The overlays of the static layer: blockers and VPLs."""
        target = layers.static.framebuffer
        specs = result.cascade_specs or [result.grid_spec]
        cascade = int(np.clip(overlays.cascade, 0, len(specs) - 1))
        lift = LIFT_CELLS * specs[0].cell_size
        if overlays.blockers:
            self._blockers(layers, result, cascade, vp, lift, notes)
        if overlays.vpls:
            if layers.stale("vpls", result.vpls, specs[0].cell_size):
                layers.splats.upload("vpls", Q.vpl_splats(
                    result.vpls, MAX_SPLAT_CELLS * specs[0].cell_size))
            total = layers.splats.count("vpls")
            count = int(round(overlays.vpl_density * total))
            layers.splats.draw(target, vp, "vpls", count, lift,
                               vpl_radius_scale(overlays.vpl_size, count, total))

    def _draw_overlays(self, layers: _Side, result, overlays: OverlayState, vp: np.ndarray,
                       notes: list[str]) -> None:
        """The overlays of the output layer: glyphs, wireframes, slice, picked point."""
        specs = result.cascade_specs or [result.grid_spec]
        cascade = int(np.clip(overlays.cascade, 0, len(specs) - 1))
        spec = specs[cascade]
        layer = Q.slice_layer(overlays, Q.layers_along(spec, overlays.slice_axis))
        if overlays.glyphs:
            self._glyphs(layers, result, overlays, vp, notes)
        self._wireframes(layers, specs, overlays, spec, layer, vp)
        layers.field = None
        if overlays.slice:
            self._slice(layers, result, overlays, vp, notes)
        self._picked(layers, result, overlays, vp, LIFT_CELLS * specs[0].cell_size)

    def _blockers(self, layers: _Side, result, cascade: int, vp: np.ndarray, lift: float,
                  notes: list[str]) -> None:
        volumes = result.cascade_geometry or [result.geometry_volume]
        volume = volumes[min(cascade, len(volumes) - 1)]
        if volume is None:
            notes.append("blockers: the geometry volume is off (Scene → Geometry volume)")
            return
        spec = (result.cascade_specs or [result.grid_spec])[cascade]
        _, _, forward = view_axes(result.camera.eye, result.camera.target)
        if layers.stale("blockers", volume, cascade, tuple(map(float, forward))):
            layers.splats.upload("blockers", Q.blocker_splats(
                volume, spec, result.settings.geometry_volume, forward))
        layers.splats.draw(layers.static.framebuffer, vp, "blockers", lift=lift)

    def _glyphs(self, layers: _Side, result, overlays: OverlayState, vp: np.ndarray,
                notes: list[str]) -> None:
        """The SH glyphs and an arrow along each lobe's axis (quantities.glyph_axes)."""
        o = overlays
        picked = (o.picked_cascade, o.picked_point)
        try:
            if layers.stale("glyphs", result, o.glyph_cells, o.slice_quantity, o.slice_step,
                            o.cascade, o.slice_axis, o.slice_index, o.glyph_scale,
                            o.glyph_stride, o.glyph_sizing, picked):
                glyphs = Q.glyphs(result, o)
                layers.glyphs.upload(glyphs)
                layers.lines.upload("glyph-axes", *Q.glyph_axes(glyphs))
        except ValueError as exc:
            layers.forget("glyphs")
            notes.append(f"glyphs: {exc}")
            return
        _, _, forward = view_axes(result.camera.eye, result.camera.target)
        layers.glyphs.draw(layers.output.framebuffer, vp, -forward)
        # each lobe's axis, depth-tested: the part inside its own lobe stays hidden
        layers.lines.draw(layers.output.framebuffer, vp, "glyph-axes")

    def _slice(self, layers: _Side, result, overlays: OverlayState, vp: np.ndarray,
               notes: list[str]) -> None:
        o = overlays
        try:
            shared = getattr(layers, "shared_top", None)
            if layers.stale("field", result, o.slice_quantity, o.slice_step, o.cascade,
                            o.direction_azimuth, o.direction_elevation, o.colour_map,
                            o.slice_scale, o.slice_log, shared):
                layers.field_cache = Q.slice_field(result, o, shared)
        except ValueError as exc:
            layers.forget("field")
            notes.append(f"slice: {exc}")
            return
        field = layers.field = layers.field_cache
        layer = Q.slice_layer(o, Q.layers_along(field.spec, o.slice_axis))
        if layers.stale("slice", field, o.slice_axis, layer):
            layers.slice.upload(Q.slice_values(field.values, o.slice_axis, layer))
        corner, edge_u, edge_v = Q.plane_corners(field.spec, o.slice_axis, layer)
        layers.slice.draw(layers.output.framebuffer, vp, corner, edge_u, edge_v, field.low,
                          field.high, field.colour_map, o.slice_opacity, o.slice_on_top,
                          field.log)

    def _wireframes(self, layers: _Side, specs: list, overlays: OverlayState, spec, layer: int,
                    vp: np.ndarray) -> None:
        segments, colours = [], []
        if overlays.lattice:
            lattice = Q.lattice_segments(spec, overlays.slice_axis, layer)
            segments += [lattice, Q.grid_box(spec)]
            colours += [np.tile(LATTICE_COLOUR, (len(lattice), 1)),
                        np.tile(CASCADE_COLOURS[0][:3] + (0.8,), (12, 1))]
        if overlays.cascade_boxes:
            for k, cascade_spec in enumerate(specs):
                segments.append(Q.grid_box(cascade_spec))
                colours.append(np.tile(CASCADE_COLOURS[k % len(CASCADE_COLOURS)], (12, 1)))
        if not segments:
            return
        if layers.stale("wire", overlays.lattice, overlays.cascade_boxes, tuple(specs),
                        overlays.slice_axis, layer, spec):
            layers.lines.upload("wire", np.concatenate(segments), np.concatenate(colours))
        layers.lines.draw(layers.output.framebuffer, vp, "wire")

    def _picked(self, layers: _Side, result, overlays: OverlayState, vp: np.ndarray,
                lift: float) -> None:
        """The picked cell's box and, for a picked surface point, a ring on the surface and
        its normal; drawn over everything so they stay visible."""
        o = overlays
        point = o.picked_point
        if point is None:
            return
        specs = result.cascade_specs or [result.grid_spec]
        segments = []
        cell = cell_at(result, o.picked_cascade, point)
        if cell is not None:
            segments.append(Q.cell_box(specs[o.picked_cascade], cell))
        marker = None
        pixel = pixel_of(result, point) if o.picked_kind == "pixel" else None
        if pixel is not None:
            normal = result.gbuffer_normal[pixel[1], pixel[0], :3]
            size = specs[0].cell_size
            segments.append(np.array([[point, np.add(point, normal * size)]]))
            marker = Q.Splats(np.array([point], np.float32), normal[None].astype(np.float32),
                              np.array([PICK_COLOUR[:3]], np.float32),
                              np.array([0.25 * size], np.float32))
        if segments:
            segments = np.concatenate(segments)
            if layers.stale("picked-lines", segments.tobytes()):
                layers.lines.upload("picked", segments, np.tile(PICK_COLOUR, (len(segments), 1)))
            layers.lines.draw(layers.output.framebuffer, vp, "picked", on_top=True)
        if marker is not None:
            if layers.stale("picked-marker", marker.packed().tobytes()):
                layers.splats.upload("picked", marker)
            layers.splats.draw(layers.output.framebuffer, vp, "picked", lift=lift)
