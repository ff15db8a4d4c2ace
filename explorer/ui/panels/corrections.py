"""Corrections panel: one switch per formula, the published and the corrected form side by
side, why it matters and what it does to the flux."""

from __future__ import annotations

from dataclasses import dataclass

from imgui_bundle import imgui

from explorer.lpv import constants as C
from explorer.lpv.settings import Corrections
from explorer.ui import widgets
from explorer.ui.state import AppState


@dataclass(frozen=True)
class CorrectionInfo:
    title: str
    why: str
    flux: str
    original: str    # LaTeX used until the derivations registry provides the formula
    corrected: str


def _per_step(front: float, side: float, faces: int = 4) -> float:
    """Flux one corrected propagation step keeps with the given solid angles
    (docs/MODEL.md "Flux per step": 6·(Δω_front + 4·Δω_side)/(4π))."""
    return 6.0 * (front + faces * side) / C.FOUR_PI


_PUBLISHED_STEP = _per_step(C.PUBLISHED_FRONT_FACE_SOLID_ANGLE, C.PUBLISHED_SIDE_FACE_SOLID_ANGLE)
_FRONT_ONLY_STEP = _per_step(C.FRONT_FACE_SOLID_ANGLE, 0.0, faces=0)

INFO: dict[str, CorrectionInfo] = {
    "injection_pi": CorrectionInfo(
        "Injection: intensity = flux / π",
        "A Lambertian emitter of flux Φ has peak intensity Φ/π, not Φ.",
        "off: every VPL injects π times its flux (×3.14 on all indirect light)",
        r"I_p(\omega) = \Phi_p \langle n_p, \omega \rangle_+",
        r"I_p(\omega) = \frac{\Phi_p}{\pi} \langle n_p, \omega \rangle_+"),
    "propagation_4pi": CorrectionInfo(
        "Propagation: no 1/(4π) per face",
        "Flux through a face is solid angle times intensity; the extra 1/(4π) "
        "averages twice.",
        "off: each step keeps 1/(4π) = 0.0796 of the flux",
        r"\Phi_f = \frac{\Delta\omega_f}{4\pi} I(\omega_c)",
        r"\Phi_f = \Delta\omega_f \, I(\omega_c)"),
    "reprojection_pi": CorrectionInfo(
        "Reprojection: face flux kept as is",
        "The face's flux becomes the new lobe's flux; dividing by π here undoes "
        "the injection's π.",
        "off alone: ×1/π per step; off together with injection: cancels",
        r"\Phi_l = \frac{\Phi_f}{\pi}",
        r"\Phi_l = \Phi_f"),
    "exact_constants": CorrectionInfo(
        "Exact solid angles",
        "The DX11 article prints rounded solid angles and π = 3.1415926.",
        f"off: one step keeps ×{_PUBLISHED_STEP:.6f} instead of ×1",
        r"\Delta\omega_{front} = 0.4006696846,\ \Delta\omega_{side} = 0.4234413544",
        r"\Delta\omega_{front} = 4\arctan\frac{\sqrt{11}}{33},\ "
        r"\Delta\omega_{side} = 2\arctan\frac{3\sqrt{11}}{11} - \frac{\pi}{3}"),
    "side_faces": CorrectionInfo(
        "Side faces",
        "Each neighbour sends light through five faces of the target cell; the front "
        "face alone covers a fifth of the solid angle.",
        f"off: one step keeps about ×{_FRONT_ONLY_STEP:.3f} of the flux",
        r"\Phi = \Phi_{front}",
        r"\Phi = \Phi_{front} + \sum_{4\ sides} \Phi_{side}"),
    "surfel_area_squared": CorrectionInfo(
        "Occluder area grows with depth squared",
        "A texel of a perspective shadow map covers an area proportional to depth "
        "squared.",
        "off: far occluders block too little (geometry volume only)",
        r"A_s = \frac{4 w}{W H}",
        r"A_s = \frac{4 w^2}{W H}"),
    "ping_pong": CorrectionInfo(
        "Ping-pong propagation",
        "Reading and writing the same texture races and re-propagates light that has "
        "already moved.",
        "off: light counted again each step (flux grows)",
        r"acc_t = acc_{t-1} + P(acc_{t-1})",
        r"grid_t = P(grid_{t-1}),\ acc_N = \sum_t grid_t"),
    "clamp_front_face": CorrectionInfo(
        "Clamp the front face",
        "A two-coefficient SH lobe goes negative behind itself; clamping stops "
        "negative light from travelling.",
        "on: clamping adds a little flux (the audit's clamp gain)",
        r"I_f = I(\omega_c)",
        r"I_f = \max(I(\omega_c), 0)"),
}


def formula_latex(key: str, variant: str) -> tuple[str, str]:
    """(LaTeX, tooltip) of ``corrections.<key>.<variant>``: from the derivations registry
    when it holds the formula (the tooltip then gives its name and statement), else the
    panel's own transcription of docs/MODEL.md."""
    found = registry_entry(f"corrections.{key}.{variant}")
    if found is not None:
        return found
    return getattr(INFO[key], variant), "transcribed from docs/MODEL.md"


def registry_entry(name: str) -> tuple[str, str] | None:
    """(LaTeX, "name: statement") of a registry result, or None if it has none."""
    try:
        from derivations import registry

        entry = registry.get(name)
        return str(registry.latex(name)), f"{name}: {entry.statement}"
    except Exception:  # noqa: BLE001 - registry absent or this result not registered
        return None


def gui_corrections(state: AppState) -> None:
    corr = state.settings.corrections
    imgui.text("Preset")
    imgui.same_line()
    if widgets.button_active("Original (as published)", corr == _preset("original")):
        state.apply_preset("original")
    imgui.same_line()
    if widgets.button_active("Corrected", corr == _preset("corrected")):
        state.apply_preset("corrected")
    imgui.separator()
    formulas = state.runtime.formulas
    for key in Corrections.names():
        info = INFO[key]
        value = bool(getattr(corr, key))
        imgui.push_id(key)
        changed, new_value = imgui.checkbox(info.title, value)
        if changed:
            state.set_corrections(**{key: new_value})
        widgets.dim_text_wrapped(info.why)
        if imgui.begin_table("forms", 2, imgui.TableFlags_.sizing_stretch_same):
            for variant, active in (("original", not new_value), ("corrected", new_value)):
                imgui.table_next_column()
                latex, source = formula_latex(key, variant)
                widgets.caption(variant + ("  (active)" if active else ""), active)
                widgets.formula(formulas, latex, active, tooltip=source)
            imgui.end_table()
        widgets.flux_text(info.flux)
        factor = registry_entry(f"corrections.{key}.flux_factor")
        if factor is not None:
            widgets.caption("corrected ÷ published:")
            imgui.same_line()
            widgets.formula(formulas, factor[0], True, tooltip=factor[1], scale=0.8)
        imgui.pop_id()
        imgui.separator()


def _preset(name: str) -> Corrections:
    from explorer.lpv.settings import PRESETS

    return PRESETS[name]
