"""Show in scene panel: which quantities the main view draws in the 3D scene (slice plane,
SH glyphs, VPLs, wireframes, blockers) and their controls. Changing any of them redraws
the overlays only; no LPV pass runs (except once, to record the propagation steps, when
the slice first shows the light in flight)."""

from __future__ import annotations

from imgui_bundle import imgui

from explorer.ui import widgets
from explorer.ui.overlays import quantities as Q
from explorer.ui.state import (
    COLOUR_MAPS,
    GLYPH_CELLS,
    GLYPH_SIZINGS,
    SLICE_AXES,
    SLICE_QUANTITIES,
    AppState,
)

QUANTITY_LABELS = {
    "intensity": "intensity toward a direction",
    "flux": "flux per cell (acc_N)",
    "in-flight": "light in flight at step t",
}


def gui_show_in_scene(state: AppState) -> None:
    o, rt = state.overlays, state.runtime
    result = rt.frame.result
    if result is None:
        imgui.text_disabled("no frame yet")
        return
    if result.gbuffer_position is None:
        imgui.text_disabled("this frame holds no G-buffer to draw in")
        return
    specs = result.cascade_specs or [result.grid_spec]
    _toggle(o, "slice", "Slice plane",
            "a plane through one layer of cells, coloured by the quantity below; hover it "
            "to read a cell, click to pick it; ctrl + wheel or [ ] over the view moves it")
    if o.slice or (o.glyphs and o.glyph_cells == "slice"):     # glyphs on the slice too
        _slice_controls(state, result, specs)
    imgui.separator()
    if _toggle(o, "glyphs", "SH glyphs",
               "each cell's intensity lobe |f(ω)| as a 3D polar surface: orange where "
               "f > 0, blue where f < 0 (SH ringing)"):
        _glyph_controls(state, result)
    imgui.separator()
    if _toggle(o, "vpls", "VPLs",
               "each VPL a disc along its surfel's normal, coloured by its flux; a thinner "
               "subset draws larger discs so the lit area stays covered"):
        _vpl_controls(state, result)
    imgui.separator()
    _toggle(o, "lattice", "Cell lattice (on the slice plane) and grid box")
    _toggle(o, "cascade_boxes", "Cascade extents")
    _toggle(o, "blockers", "Blockers (geometry volume)",
            "the geometry volume's occluders on the grid corners: a disc of the surfels' "
            "area facing their mean normal")
    _notes(state)


def _toggle(overlays, name: str, label: str, help_text: str | None = None) -> bool:
    """A checkbox for the overlay switch ``name``; returns whether it is on."""
    _, value = imgui.checkbox(label, getattr(overlays, name))
    setattr(overlays, name, value)
    if help_text:
        widgets.help_marker(help_text)
    return value


def _slice_controls(state: AppState, result, specs) -> None:
    o = state.overlays
    if len(specs) > 1:
        o.cascade = min(o.cascade, len(specs) - 1)
        _, o.cascade = imgui.slider_int("Cascade", o.cascade, 0, len(specs) - 1)
    for axis in SLICE_AXES:
        if imgui.radio_button(axis, o.slice_axis == axis):
            o.slice_axis = axis
        imgui.same_line()
    imgui.text("axis")
    n = Q.layers_along(specs[min(o.cascade, len(specs) - 1)], o.slice_axis)
    changed, layer = imgui.slider_int("Layer", Q.slice_layer(o, n), 0, n - 1)
    if changed:
        o.slice_index = layer
    coefficients = result.accumulated.shape[-1]
    choices = [q for q in SLICE_QUANTITIES
               if not (q.startswith("sh") and int(q[2:]) >= coefficients)]
    labels = [QUANTITY_LABELS.get(q, f"SH coefficient {q[2:]}") for q in choices]
    index = choices.index(o.slice_quantity) if o.slice_quantity in choices else 0
    _, index = imgui.combo("Quantity", index, labels)
    o.slice_quantity = choices[index]
    if o.slice_quantity == "intensity":
        _, o.direction_azimuth = imgui.slider_float("Azimuth", o.direction_azimuth, -180, 180,
                                                    "%.0f°")
        _, o.direction_elevation = imgui.slider_float("Elevation", o.direction_elevation,
                                                      -90, 90, "%.0f°")
    if o.slice_quantity == "in-flight":
        steps = len(result.steps) - 1 if result.steps else state.settings.iterations
        _, o.slice_step = imgui.slider_int("Step t", min(o.slice_step, steps), 0, steps)
    _, o.colour_map = widgets.combo("Colour map", o.colour_map, COLOUR_MAPS)
    if Q.resolved_colour_map(o) == "heat":
        _, o.slice_log = imgui.checkbox(f"Log scale ({Q.LOG_DECADES:.0f} decades)",
                                        o.slice_log)
        widgets.help_marker("colours follow log10 of the value over the decades below the "
                            "top of the bar; cells below the bar are drawn faint")
    _, o.slice_scale = imgui.input_float("Scale top (0 = auto)", o.slice_scale, 0.0, 0.0,
                                         "%.4g")
    o.slice_scale = max(o.slice_scale, 0.0)
    _, o.slice_opacity = imgui.slider_float("Opacity", o.slice_opacity, 0.05, 1.0, "%.2f")
    _, o.slice_on_top = imgui.checkbox("Over the geometry", o.slice_on_top)


def _glyph_controls(state: AppState, result) -> None:
    o = state.overlays
    _, o.glyph_cells = widgets.combo("Cells", o.glyph_cells, GLYPH_CELLS)
    if o.glyph_cells == "picked" and o.picked_point is None:
        imgui.text_disabled("pick a cell or a pixel in the view")
    _, o.glyph_scale = imgui.slider_float("Glyph size", o.glyph_scale, 0.1, 4.0, "%.2f",
                                          imgui.SliderFlags_.logarithmic)
    if o.glyph_cells == "slice":
        n = max(result.grid_spec.cells)
        automatic = Q.auto_glyph_stride(n)
        _, o.glyph_stride = imgui.slider_int("Every k-th cell", o.glyph_stride, 0, 8,
                                             f"k = %d (0: auto = {automatic})")
    _, o.glyph_sizing = widgets.combo("Size follows", o.glyph_sizing, GLYPH_SIZINGS)
    widgets.help_marker("a glyph's size against its peak intensity: linear, square root "
                        "(dim cells stay visible) or equal (shape only)")


def _vpl_controls(state: AppState, result) -> None:
    o = state.overlays
    count = result.vpls.count
    _, o.vpl_density = imgui.slider_float("Density", o.vpl_density, 0.001, 1.0, "%.3f",
                                          imgui.SliderFlags_.logarithmic)
    imgui.text_disabled(f"{int(round(o.vpl_density * count))} of {count} VPLs drawn")
    _, o.vpl_size = imgui.slider_float("Disc size", o.vpl_size, 0.1, 2.0, "%.2f")


def _notes(state: AppState) -> None:
    compositor = state.runtime.services.compositor
    if compositor is None:
        return
    for name, log in compositor.programs.errors.items():   # a failed hot reload
        imgui.text_colored(widgets.ERROR, f"{name}: {(log.strip().splitlines() or [''])[0]}")
    sides = ("A", "B") if state.view_mode == "split" else ("A",)
    for side in sides:
        for note in compositor.notes.get(side, []):
            imgui.text_colored(widgets.WARN, f"{side}: {note}")
