"""Inspect panel: the RSM buffers, any z slice of the grid (one SH coefficient or the
intensity toward a chosen direction), the geometry volume, and the propagation at any
iteration with a scrubber and play/pause. Images come from FrameResult arrays and are
uploaded to textures the UI owns."""

from __future__ import annotations

import numpy as np
from imgui_bundle import imgui, implot3d

from explorer.ui import glyphs, images, widgets
from explorer.ui.overlays import quantities as Q
from explorer.ui.state import GRID_COMPONENTS, INSPECT_SOURCES, AppState
from explorer.ui.widgets import scale_bar

SOURCE_LABELS = {
    "rsm-position": "RSM: world position",
    "rsm-normal": "RSM: normal",
    "rsm-flux": "RSM: reflected flux",
    "grid-slice": "LPV: accumulated grid",
    "propagation": "LPV: light in flight, step t",
    "geometry-volume": "Geometry volume (slice)",
    "vpls": "VPLs as 3D points",
    "cascade-weights": "Cascade weights per pixel",
}


def gui_inspect(state: AppState) -> None:
    ins = state.inspect
    labels = [SOURCE_LABELS[s] for s in INSPECT_SOURCES]
    index = INSPECT_SOURCES.index(ins.source) if ins.source in INSPECT_SOURCES else 0
    widgets.fit_next_item("Show")
    changed, index = imgui.combo("Show", index, labels)
    if changed:
        ins.source = INSPECT_SOURCES[index]
    result = state.runtime.frame.result
    if result is None:
        imgui.text_disabled("no frame yet")
        return
    if ins.source == "vpls":
        _vpl_plot(state, result)
        return
    make, problem = _image_for(state, result)
    if make is None:
        widgets.dim_text_wrapped(problem)
        return
    version = (ins.source, id(result), ins.slice_z, ins.component, ins.direction_azimuth,
               ins.direction_elevation, ins.iteration, ins.signed_scale, ins.cascade)
    rt = state.runtime
    if rt.services.inspect_cache is None or rt.services.inspect_cache[0] != version:
        # Only a new frame or a changed control recomputes and uploads the picture.
        image, top, caption = make()
        tex = rt.services.textures.upload("inspect", image, version=version)
        rt.services.inspect_cache = (version, tex, top, caption, image.shape[:2])
    _, tex, top, caption, (height_px, width_px) = rt.services.inspect_cache
    signed = ins.component != "intensity" and ins.source in ("grid-slice", "propagation")
    widgets.dim_text_wrapped(caption)
    avail = imgui.get_content_region_avail()
    bar = 80.0 if top is not None else 0.0
    side = max(min(avail.x - bar, avail.y - 8), 32.0)
    fit = side / max(width_px, height_px)
    size = imgui.ImVec2(width_px * fit, height_px * fit)
    pos = imgui.get_cursor_screen_pos()
    imgui.image(imgui.ImTextureRef(tex), size)
    if top is not None:
        scale_bar(imgui.get_window_draw_list(), imgui.ImVec2(pos.x + size.x + 8, pos.y),
                  size.y, top, signed)
    grid = _shown_grid(state, result)
    if grid is not None:
        _, ins.glyphs = imgui.checkbox("SH glyphs (intensity in the slice plane)", ins.glyphs)
        if ins.glyphs:
            _draw_glyphs(grid, ins.slice_z, pos, size)


def _shown_grid(state: AppState, result):
    ins = state.inspect
    if ins.source == "grid-slice":
        return result.accumulated
    if ins.source == "propagation" and result.steps:
        return result.steps[min(ins.iteration, len(result.steps) - 1)]
    return None


_GLYPH_MAX_CELLS = 48


def _draw_glyphs(grid: np.ndarray, z: int, pos, size) -> None:
    """Per cell, a polar curve of the radiant intensity (mean of the channels) toward the
    directions of the slice plane: where light in that cell is heading."""
    n = grid.shape[1]
    if n > _GLYPH_MAX_CELLS:
        imgui.text_disabled(f"glyphs are drawn for grids up to {_GLYPH_MAX_CELLS}³")
        return
    z = int(np.clip(z if z >= 0 else n // 2, 0, n - 1))
    glyphs.draw_lobe_glyphs(imgui.get_window_draw_list(), grid, z, pos, size,
                            imgui.get_color_u32(imgui.ImVec4(0.55, 0.85, 1.0, 0.9)))


def _grid_controls(state: AppState, resolution: int, components: bool = True) -> None:
    ins = state.inspect
    z = ins.slice_z if 0 <= ins.slice_z < resolution else resolution // 2
    widgets.fit_next_item("Slice z")
    _, ins.slice_z = imgui.slider_int("Slice z", z, 0, resolution - 1)
    if not components:
        return
    widgets.fit_next_item("Show##component")
    changed, ins.component = widgets.combo("Show##component", ins.component, GRID_COMPONENTS)
    if ins.component == "intensity":
        widgets.fit_next_item("Direction azimuth")
        _, ins.direction_azimuth = imgui.slider_float("Direction azimuth",
                                                      ins.direction_azimuth, -180, 180,
                                                      "%.0f°")
        widgets.fit_next_item("Direction elevation")
        _, ins.direction_elevation = imgui.slider_float("Direction elevation",
                                                        ins.direction_elevation, -90, 90,
                                                        "%.0f°")


def _image_for(state: AppState, result):
    """Draw the source's controls; return (a function computing (image, scale top or None,
    caption), None), or (None, why there is nothing to show)."""
    ins = state.inspect
    if ins.source == "cascade-weights":
        return _cascade_weights(state, result)
    if ins.source.startswith("rsm-"):
        buffer = getattr(result, ins.source.replace("-", "_"))
        h, w = buffer.shape[:2]
        return (lambda: (images.rsm_image(buffer, ins.source), None, f"{w}×{h} texels")), None
    if ins.source == "geometry-volume":
        volume = _cascade_pick(state, result, result.cascade_geometry, result.geometry_volume)
        if volume is None:
            return None, "the geometry volume is off (Scene → Geometry volume)"
        _grid_controls(state, volume.shape[2], components=False)

        def make_volume():
            image, top = images.volume_slice(volume, ins.slice_z)
            return image, top, f"band-0 blocking, {volume.shape[0]}³ cells on grid corners"

        return make_volume, None
    if ins.source == "grid-slice":
        grid = _cascade_pick(state, result, result.cascade_accumulated, result.accumulated)
        cascades = len(result.cascade_accumulated or [result.accumulated])
        what = Q.grid_words(cascade=ins.cascade, cascades=cascades)
    else:
        steps = result.steps
        if not steps:
            return None, "steps are being recorded; next frame"
        last = len(steps) - 1
        _playback(state, last)
        grid, what = steps[min(ins.iteration, last)], Q.grid_words(step=min(ins.iteration,
                                                                              last))
    _grid_controls(state, grid.shape[3])

    def make_slice():
        direction = images.direction_from_angles(ins.direction_azimuth,
                                                 ins.direction_elevation)
        image, top = images.grid_slice(grid, ins.slice_z, ins.component, direction,
                                       ins.signed_scale)
        flux = images.flux_of_grid(grid)
        return image, top, f"{what}: flux {flux:.4g} W (sum of channels)"

    return make_slice, None


def _cascade_weights(state: AppState, result):
    """The final gather's blend weights per pixel (docs/MODEL.md "Cascades"), from the
    pipeline's own view: it needs the G-buffer, which the FrameResult does not carry."""
    from explorer.lpv.views import CASCADE_COLOURS

    view = state.runtime.frame.frame_view
    if view is None:
        return None, "no frame yet"
    count = len(result.cascade_specs or [result.grid_spec])
    for k in range(count):
        name = f"cascade {k}" + (" (finest)" if k == 0 and count > 1 else "")
        if k:       # the legend wraps in the narrow tool column (1280 px window)
            widgets.same_line_if_fits(name, field=12.0 + imgui.get_style().item_spacing.x)
        imgui.color_button(f"##cascade{k}", imgui.ImVec4(*map(float, CASCADE_COLOURS[k]), 1.0),
                           0, (12, 12))
        imgui.same_line()
        imgui.text(name)

    def make():
        image = view("cascade-weights")
        return image, None, (f"which cascade the final gather reads at each pixel, of "
                             f"{count}; mixed colours: it blends two cascades there; "
                             "black: background")

    return make, None


def _cascade_pick(state: AppState, result, per_cascade: list, finest):
    """With several cascades, a slider picks the cascade shown (0 = the finest)."""
    ins = state.inspect
    if len(per_cascade) < 2:
        ins.cascade = 0
        return finest
    ins.cascade = min(ins.cascade, len(per_cascade) - 1)
    widgets.fit_next_item("Cascade")
    _, ins.cascade = imgui.slider_int("Cascade", ins.cascade, 0, len(per_cascade) - 1)
    spec = result.cascade_specs[ins.cascade]
    size = f"cell {spec.cell_size:.3g} m"
    widgets.same_line_if_fits(size)
    imgui.text_disabled(size)
    return per_cascade[ins.cascade]


def _playback(state: AppState, last: int) -> None:
    ins, rt = state.inspect, state.runtime
    ins.playing, ins.iteration, rt.view.play_clock = widgets.playback(
        ins.playing, ins.iteration, last, rt.view.play_clock, ins.play_rate)


def _vpl_plot(state: AppState, result) -> None:
    """The VPLs the grid received, as points coloured by their flux (drag to rotate)."""
    rt = state.runtime
    if rt.services.vpl_cache is None or rt.services.vpl_cache[0] != id(result):
        vpls = result.vpls
        rt.services.vpl_cache = (id(result), images.vpl_groups(vpls.positions, vpls.flux),
                        len(vpls.positions))
    _, groups, count = rt.services.vpl_cache
    shown = sum(len(points) for _, points in groups)
    imgui.text_disabled(f"{count} VPLs injected, {shown} lit ones shown; drag to rotate")
    if not implot3d.begin_plot("##vpls", (-1, -1)):
        return
    implot3d.setup_axes("x", "y", "z")
    for rgb, points in groups:
        spec = implot3d.Spec()
        spec.marker = implot3d.Marker_.circle
        spec.marker_size = 2.0
        colour = imgui.ImVec4(rgb[0], rgb[1], rgb[2], 1.0)
        spec.marker_line_color = colour
        spec.fill_color = colour
        spec.line_color = colour
        # world y is up; implot3d's z axis is up
        implot3d.plot_scatter(f"##{rgb}", np.ascontiguousarray(points[:, 0]),
                              np.ascontiguousarray(points[:, 2]),
                              np.ascontiguousarray(points[:, 1]), spec)
    implot3d.end_plot()
