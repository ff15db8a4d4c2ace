"""Picked panel: every value the pipeline holds for the picked pixel (world position,
normal, direct and indirect radiance, the indirect light recomputed from the grid, and on
request the one-bounce reference radiance with the ratio LPV / reference) and for its
cell (SH coefficients, flux, flux in flight per step, and the cell's own audit records read
back from the GPU: what it received, sent out of the grid, gained by the clamp and lost to
occlusion). The values are read from the current FrameResult each frame, so they follow
the frame when a switch changes it. Click in the view to pick."""

from __future__ import annotations

import numpy as np
from imgui_bundle import imgui, implot

from explorer.ui import camera_controls, widgets
from explorer.ui.overlays.describe import cell_audit_rows, cell_rows, pixel_rows
from explorer.ui.overlays.in_view import pick_with_references
from explorer.ui.overlays.picking import CellAuditInfo, cell_at, cell_audit, pick_cell, pixel_of
from explorer.ui.overlays.pixel_reference import pixel_references
from explorer.ui.state import AppState


def gui_picked(state: AppState) -> None:
    o, rt = state.overlays, state.runtime
    if o.picked_kind == "none":
        widgets.dim_text_wrapped("Click a pixel of the view (or a cell of the slice plane) "
                                 "to read its values here; hovering shows them in a tooltip.")
        return
    result = rt.frame.result if o.picked_side == "A" else rt.frame.compare_result
    if result is None or result.gbuffer_position is None:
        imgui.text_disabled(f"no frame of side {o.picked_side}")
        return
    if imgui.button("Frame it (G)"):
        camera_controls.frame_picked(state)
    imgui.same_line()
    if imgui.button("Glyphs around it"):
        o.glyphs, o.glyph_cells = True, "picked"
    imgui.same_line()
    if imgui.button("Clear"):
        o.picked_kind = "none"
        return
    point = o.picked_point
    imgui.text_disabled(f"side {o.picked_side} · {o.picked_kind} at "
                        + ", ".join(f"{v:.4g}" for v in point))
    if o.picked_kind == "pixel":
        pixel = pixel_of(result, point)
        if pixel is None:
            imgui.text_disabled("the picked point is hidden or outside the view in this frame")
        else:
            _table("pixel", pixel_rows(pick_with_references(state, result, pixel,
                                                            o.picked_side), 6))
            _reference_button(state, result, pixel)
    _cell_picker(state, result)
    index = cell_at(result, o.picked_cascade, point)
    cell = None if index is None else pick_cell(result, o.picked_cascade, *index)
    if cell is None:
        imgui.text_disabled(f"the point lies outside cascade {o.picked_cascade}")
        return
    _table("cell", cell_rows(cell, 6))
    if cell.in_flight is not None and len(cell.in_flight) > 1:
        _in_flight_plot(cell.in_flight)
    else:
        imgui.text_disabled("flux per step: record the steps (Inspect → propagation, or the "
                            "slice's light in flight)")
    # the cell's audit records: the picked side's frames measure them
    state.runtime.want_audit("full", side=o.picked_side)
    _cell_audit(result, cell)


def _reference_button(state: AppState, result, pixel) -> None:
    """Compute the reference radiance at the picked pixel (both modes), in the
    background; the table above and the tooltip show it once done."""
    service = pixel_references(state)
    if len(service.values(result, pixel)) == 2:
        return
    if service.computing(result, pixel):
        imgui.text_disabled(f"reference radiance at this pixel: {service.progress()}")
    elif imgui.button("Reference radiance at this pixel"):
        service.request(result, pixel)
    if imgui.is_item_hovered():
        imgui.set_tooltip("the one-bounce reference (explorer/truth): every VPL of this frame "
                          "gathered at this pixel alone, with shadow rays (visible) and "
                          "without (unoccluded); cached per settings and pixel")
    if service.problem:
        imgui.text_colored(widgets.ERROR, service.problem)


def _cell_audit(result, cell) -> None:
    """The cell's own audit records [W], read from the GPU for this cell only."""
    imgui.separator_text("Audit of this cell [W]")
    info = cell_audit(result, cell.cascade, cell.index)
    if not isinstance(info, CellAuditInfo):
        imgui.text_disabled(info)
        return
    _table("cell-audit", cell_audit_rows(info, 6))
    widgets.dim_text_wrapped(
        "received: flux the steps delivered into the cell; sent out of the grid: what it "
        "sent through the grid's border; clamp gain and occluded: on the faces it gathered "
        "through (and, at the border, those it sent out). Summed over all cells they are "
        "the Energy audit plot's bars.")


def _cell_picker(state: AppState, result) -> None:
    """Step through the cells: the cascade and i, j, k of the picked cell (picking its
    centre)."""
    o = state.overlays
    specs = result.cascade_specs or [result.grid_spec]
    if len(specs) > 1:
        _, o.picked_cascade = imgui.slider_int("Cascade##picked", o.picked_cascade, 0,
                                               len(specs) - 1)
    spec = specs[min(o.picked_cascade, len(specs) - 1)]
    index = cell_at(result, o.picked_cascade, o.picked_point)
    if index is None:
        return
    changed, ijk = imgui.input_int3("Cell i, j, k", list(index))
    if changed:
        new = np.clip(ijk, 0, np.asarray(spec.cells) - 1)
        o.pick("cell", o.picked_side, o.picked_cascade, spec.cell_centre(new))


def _table(name: str, rows: list[tuple[str, str]]) -> None:
    flags = imgui.TableFlags_.row_bg | imgui.TableFlags_.borders_inner_v
    if not imgui.begin_table(f"##{name}", 2, flags):
        return
    imgui.table_setup_column("what", imgui.TableColumnFlags_.width_fixed)
    imgui.table_setup_column("value")
    for label, value in rows:
        imgui.table_next_row()
        imgui.table_next_column()
        imgui.text_disabled(label)
        imgui.table_next_column()
        imgui.text_wrapped(value)
    imgui.end_table()


def _in_flight_plot(in_flight: np.ndarray) -> None:
    if not implot.begin_plot("Flux of grid_t in this cell [W]", (-1, 180)):
        return
    implot.setup_axes("step t", "W")
    steps = np.arange(len(in_flight), dtype=np.float64)
    for channel, name in enumerate(("r", "g", "b")):
        implot.plot_line(name, steps, np.ascontiguousarray(in_flight[:, channel], np.float64))
    implot.end_plot()
