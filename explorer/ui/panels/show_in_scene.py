"""Show in scene panel: which quantities the main view draws in the 3D scene (slice plane,
SH glyphs, VPLs, wireframes, blockers) and their controls. Changing any of them redraws
the overlays only; no LPV pass runs (except once, to record the propagation steps, when
the slice first shows the light in flight)."""

from __future__ import annotations

from imgui_bundle import imgui

from explorer.ui import widgets
from explorer.ui.overlays import quantities as Q
from explorer.ui.reader_controls import OVERLAY_SWITCHES, overlay_sections, reader_step
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
    "flux": "accumulated flux per cell",
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
    # the reader's mode: the sections of the overlays the step (or the reader) turned on
    sections = overlay_sections(reader_step(state),
                                {name: bool(getattr(o, name)) for name in OVERLAY_SWITCHES})
    if "slice" in sections:
        _toggle(o, "slice", "Slice plane",
                "a plane through one layer of cells, coloured by the quantity below; hover "
                "it to read a cell, click to pick it; ctrl + wheel or [ ] over the view "
                "moves it")
    if o.slice or (o.glyphs and o.glyph_cells == "slice"):     # glyphs on the slice too
        _slice_controls(state, result, specs)
    if "glyphs" in sections:
        imgui.separator()
        if _toggle(o, "glyphs", "SH glyphs",
                   "each cell's intensity lobe |f(ω)| as a 3D polar surface: orange where "
                   "f > 0, blue where f < 0 (SH ringing)"):
            _glyph_controls(state, result)
    if "vpls" in sections:
        imgui.separator()
        if _toggle(o, "vpls", "VPLs",
                   "each VPL a disc along its surfel's normal, coloured by its flux; a "
                   "thinner subset draws larger discs so the lit area stays covered"):
            _vpl_controls(state, result)
    if sections & {"lattice", "cascade_boxes", "blockers"}:
        imgui.separator()
    if "lattice" in sections:
        _toggle(o, "lattice", "Cell lattice (on the slice plane) and grid box")
    if "cascade_boxes" in sections:
        _toggle(o, "cascade_boxes", "Cascade extents")
    if "blockers" in sections:
        _toggle(o, "blockers", "Blockers (geometry volume)",
                "the geometry volume's occluders on the grid corners: a disc of the "
                "surfels' area facing their mean normal")
    if sections != frozenset(OVERLAY_SWITCHES):
        widgets.dim_text_wrapped("The overlays this step draws; All panels (Lesson panel) "
                                 "shows every other.")
    _notes(state)


def _toggle(overlays, name: str, label: str, help_text: str | None = None) -> bool:
    """A checkbox for the overlay switch ``name``; returns whether it is on."""
    _, value = imgui.checkbox(label, getattr(overlays, name))
    setattr(overlays, name, value)
    if help_text:
        _help(help_text)
    return value


def _help(text: str) -> None:
    """The "(?)" of a control, on its line when it fits there (else under it)."""
    widgets.same_line_if_fits("(?)")
    imgui.text_disabled("(?)")
    if imgui.is_item_hovered():
        imgui.set_tooltip(text)


def _slice_controls(state: AppState, result, specs) -> None:
    o = state.overlays
    if len(specs) > 1:
        o.cascade = min(o.cascade, len(specs) - 1)
        widgets.fit_next_item("Cascade")
        _, o.cascade = imgui.slider_int("Cascade", o.cascade, 0, len(specs) - 1)
    for axis in SLICE_AXES:
        if imgui.radio_button(axis, o.slice_axis == axis):
            o.slice_axis = axis
        imgui.same_line()
    imgui.text("axis")
    n = Q.layers_along(specs[min(o.cascade, len(specs) - 1)], o.slice_axis)
    widgets.fit_next_item("Layer")
    changed, layer = imgui.slider_int("Layer", Q.slice_layer(o, n), 0, n - 1)
    if changed:
        o.slice_index = layer
    coefficients = result.accumulated.shape[-1]
    choices = [q for q in SLICE_QUANTITIES
               if not (q.startswith("sh") and int(q[2:]) >= coefficients)]
    labels = [QUANTITY_LABELS.get(q, f"SH coefficient {q[2:]}") for q in choices]
    index = choices.index(o.slice_quantity) if o.slice_quantity in choices else 0
    widgets.fit_next_item("Quantity")
    _, index = imgui.combo("Quantity", index, labels)
    o.slice_quantity = choices[index]
    if o.slice_quantity == "intensity":
        widgets.fit_next_item("Azimuth")
        _, o.direction_azimuth = imgui.slider_float("Azimuth", o.direction_azimuth, -180, 180,
                                                    "%.0f°")
        widgets.fit_next_item("Elevation")
        _, o.direction_elevation = imgui.slider_float("Elevation", o.direction_elevation,
                                                      -90, 90, "%.0f°")
    if o.slice_quantity == "in-flight":
        steps = len(result.steps) - 1 if result.steps else state.settings.iterations
        widgets.fit_next_item("Step t")
        _, o.slice_step = imgui.slider_int("Step t", min(o.slice_step, steps), 0, steps)
    widgets.fit_next_item("Colour map")
    _, o.colour_map = widgets.combo("Colour map", o.colour_map, COLOUR_MAPS)
    if Q.resolved_colour_map(o) == "heat":
        _, o.slice_log = imgui.checkbox(f"Log scale ({Q.LOG_DECADES:.0f} decades)",
                                        o.slice_log)
        _help("colours follow log10 of the value over the decades below the "
                            "top of the bar; cells below the bar are drawn faint")
    widgets.fit_next_item("Scale top (0 = auto)")
    _, o.slice_scale = imgui.input_float("Scale top (0 = auto)", o.slice_scale, 0.0, 0.0,
                                         "%.4g")
    o.slice_scale = max(o.slice_scale, 0.0)
    widgets.fit_next_item("Opacity")
    _, o.slice_opacity = imgui.slider_float("Opacity", o.slice_opacity, 0.05, 1.0, "%.2f")
    _, o.slice_on_top = imgui.checkbox("Over the geometry", o.slice_on_top)


def _glyph_controls(state: AppState, result) -> None:
    o = state.overlays
    widgets.fit_next_item("Cells")
    _, o.glyph_cells = widgets.combo("Cells", o.glyph_cells, GLYPH_CELLS)
    if o.glyph_cells == "picked" and o.picked_point is None:
        imgui.text_disabled("pick a cell or a pixel in the view")
    widgets.fit_next_item("Glyph size")
    _, o.glyph_scale = imgui.slider_float("Glyph size", o.glyph_scale, 0.1, 4.0, "%.2f",
                                          imgui.SliderFlags_.logarithmic)
    if o.glyph_cells == "slice":
        n = max(result.grid_spec.cells)
        automatic = Q.auto_glyph_stride(n)
        widgets.fit_next_item("Every k-th cell")
        _, o.glyph_stride = imgui.slider_int("Every k-th cell", o.glyph_stride, 0, 8,
                                             f"k = %d (0: auto = {automatic})")
    widgets.fit_next_item("Size follows (?)")     # its help on the line
    _, o.glyph_sizing = widgets.combo("Size follows", o.glyph_sizing, GLYPH_SIZINGS)
    _help("a glyph's size against its peak intensity: linear, square root "
                        "(dim cells stay visible) or equal (shape only)")


def _vpl_controls(state: AppState, result) -> None:
    o = state.overlays
    count = result.vpls.count
    widgets.fit_next_item("Density")
    _, o.vpl_density = imgui.slider_float("Density", o.vpl_density, 0.001, 1.0, "%.3f",
                                          imgui.SliderFlags_.logarithmic)
    imgui.text_disabled(f"{int(round(o.vpl_density * count))} of {count} VPLs drawn")
    widgets.fit_next_item("Disc size")
    _, o.vpl_size = imgui.slider_float("Disc size", o.vpl_size, 0.1, 2.0, "%.2f")


def _notes(state: AppState) -> None:
    compositor = state.runtime.services.compositor
    if compositor is None:
        return
    for name, log in compositor.programs.errors.items():   # a failed hot reload
        imgui.push_text_wrap_pos(0.0)
        imgui.text_colored(widgets.ERROR, f"{name}: {(log.strip().splitlines() or [''])[0]}")
        imgui.pop_text_wrap_pos()
    sides = ("A", "B") if state.view_mode == "split" else ("A",)
    for side in sides:
        for note in compositor.notes.get(side, []):
            imgui.push_text_wrap_pos(0.0)       # a long note wraps in the tool column
            imgui.text_colored(widgets.WARN, f"{side}: {note}")
            imgui.pop_text_wrap_pos()
