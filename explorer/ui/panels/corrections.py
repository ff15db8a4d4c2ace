"""Corrections panel: one switch per entry of the corrections registry
(``derivations/correction_registry.py``), its published and corrected formulas side by side (the
derivations ``corrections.<name>.original`` / ``.corrected``, typeset from the LaTeX
generated into ``explorer/derived_table.py``), why it matters and what it changes."""

from __future__ import annotations

from imgui_bundle import imgui

from explorer import derived
from explorer.lpv.corrections import CORRECTIONS, PRESETS
from explorer.ui import widgets
from explorer.ui.state import AppState


def gui_corrections(state: AppState) -> None:
    corr = state.settings.corrections
    imgui.text("Preset")
    imgui.same_line()
    if widgets.button_active("Original (as published)", corr == PRESETS["original"]):
        state.apply_preset("original")
    imgui.same_line()
    if widgets.button_active("Corrected", corr == PRESETS["corrected"]):
        state.apply_preset("corrected")
    imgui.separator()
    formulas = state.runtime.services.formulas
    for entry in CORRECTIONS:
        value = bool(getattr(corr, entry.name))
        imgui.push_id(entry.name)
        changed, new_value = imgui.checkbox(entry.title, value)
        if changed:
            state.set_corrections(**{entry.name: new_value})
        widgets.dim_text_wrapped(entry.why)
        if imgui.begin_table("forms", 2, imgui.TableFlags_.sizing_stretch_same):
            for variant, name, active in (("original", entry.original, not new_value),
                                          ("corrected", entry.corrected, new_value)):
                imgui.table_next_column()
                result = derived.get(name)
                widgets.caption(variant + ("  (active)" if active else ""), active)
                widgets.formula(formulas, result.latex, active, tooltip=result.tooltip)
            imgui.end_table()
        widgets.flux_text(derived.fill(entry.flux))
        for caption, item in entry.effects:
            _effect(formulas, caption, derived.get(entry.derivation(item)))
        imgui.pop_id()
        imgui.separator()


def _effect(formulas, caption: str, result: derived.Derived) -> None:
    """One consequence of a switch: optional caption, the typeset result, ≈ its value."""
    if caption:
        widgets.caption(caption)
        imgui.same_line()
    widgets.formula(formulas, result.latex, True, tooltip=result.tooltip, scale=0.8)
    if result.value is not None and _needs_decimals(result.value):
        decimals = f"≈ {result.value:.7g}"
        widgets.same_line_if_fits(decimals)    # wraps in a narrow column (1280 px window)
        imgui.text_disabled(decimals)


def _needs_decimals(value: float) -> bool:
    """True unless the value is short enough to read off its formula (1, −1/4, 12)."""
    return len(f"{abs(value):.7g}".replace(".", "").strip("0")) > 3
