"""Compare panel: configuration B (its corrections; everything else follows A) and the
split/difference view options."""

from __future__ import annotations

import dataclasses

from imgui_bundle import imgui

from explorer.lpv.corrections import CORRECTIONS, PRESETS
from explorer.ui import widgets
from explorer.ui.state import VIEW_MODES, AppState


def gui_compare(state: AppState) -> None:
    widgets.dim_text_wrapped(
        "B shares scene, camera, light and LPV settings with A; only the corrections "
        "differ. Split: A left, B right. Difference: |A - B| (or A - B) in false "
        "colour.")
    for index, mode in enumerate(VIEW_MODES):
        if index:       # the row wraps where the panel is narrow (a radio is a checkbox wide)
            widgets.same_line_if_fits(mode.capitalize(), checkbox=True)
        if imgui.radio_button(mode.capitalize() + "##cmp", state.view_mode == mode):
            state.view_mode = mode
    if state.view_mode == "split":
        _, state.split_position = imgui.slider_float("Divider", state.split_position, 0.02,
                                                     0.98, "%.2f")
    if state.view_mode == "difference":
        from explorer.ui.panels.view import difference_controls

        difference_controls(state)
    _, state.expose_sides_separately = imgui.checkbox("Expose sides separately",
                                                      state.expose_sides_separately)
    widgets.help_marker("With the display's auto exposure each side keeps its own display "
                        "scale (otherwise B is shown at A's). Without it, each side's "
                        "exposure puts its brightest 1% near white (otherwise both use A's "
                        "exposure).")
    if state.expose_sides_separately and not state.settings.auto_exposure:
        ea, eb = state.runtime.frame.side_exposures
        imgui.text_disabled(f"exposure A {ea:.3g}   B {eb:.3g}")

    imgui.separator_text("Configuration B")
    corr = state.compare_settings.corrections
    for name in PRESETS:
        if widgets.button_active(name.capitalize() + "##B", corr == PRESETS[name]):
            state.apply_preset(name, compare=True)
        imgui.same_line()
    if imgui.button("Swap A/B"):
        a, b = state.settings.corrections, corr
        if state.update(corrections=b):
            state.compare_settings = state.compare_settings.with_changes(corrections=a)
    for entry in CORRECTIONS:
        changed, value = imgui.checkbox(entry.title + "##B", bool(getattr(corr, entry.name)))
        if changed:
            state.set_compare_corrections(dataclasses.replace(corr, **{entry.name: value}))
