"""The corrections registry: one entry per switch between a published and a corrected form.

Everything else about a switch comes from its entry here (docs/MODEL.md "Corrections"):

* the :class:`explorer.lpv.corrections.Corrections` dataclass (one ``bool`` field per
  entry, in registry order, ``True`` = corrected; the fields written out into
  ``explorer/lpv/correction_switches.py`` by ``python -m derivations.codegen``) and the
  presets;
* the shaders' uniform declarations, ``shaders/generated/corrections.glsl``
  (``python -m derivations.codegen``), one ``uniform bool u_<name>`` per entry;
* which passes must read the uniform (:attr:`Correction.stages`; the passes hand these to
  ``explorer.gl.program.set_uniforms``, which raises when a program lacks one);
* the Corrections panel (title, why, flux text) and the formulas it typesets: the
  derivations ``corrections.<name>.original`` and ``.corrected`` (``derivations/``), as
  LaTeX generated into ``explorer/derived_table.py``.

Plain data in the bottom layer, the derivations (it imports nothing of the project): the code
generator reads it without importing the LPV package, and the window reads it at start.
The stage names an entry gives are checked against the declared stage list by
:mod:`explorer.lpv.corrections`.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Correction:
    """One switch. ``False`` selects the published form, ``True`` the corrected one."""

    name: str
    """Field of :class:`Corrections`; the uniform is ``u_<name>``, the derivations
    ``corrections.<name>.original`` / ``.corrected``."""
    title: str
    why: str
    """Why the corrected form is right, in one or two sentences."""
    flux: str
    """What switching it changes in the flux. ``{derivation name:format}`` fields are
    filled with the derivation's value (``explorer.derived``)."""
    published: bool
    """True when the uncorrected form is what the published sources print: the "original"
    preset switches it off. False for implementation details the preset leaves corrected."""
    stages: tuple[str, ...]
    """Stages whose programs read the uniform (a subset of
    ``explorer.lpv.corrections.STAGES``)."""
    effects: tuple[tuple[str, str], ...]
    """(caption, item) of the derivations ``corrections.<name>.<item>`` the panel shows
    under the two formulas: what the switch changes, exactly."""
    forms: tuple[str, str]
    """(as published, corrected) in words and plain-text formulas: the row of the
    corrections table in docs/MODEL.md (generated from here by ``derivations.codegen``)."""

    @property
    def uniform(self) -> str:
        return f"u_{self.name}"

    @property
    def original(self) -> str:
        """Derivation name of the published form."""
        return f"corrections.{self.name}.original"

    @property
    def corrected(self) -> str:
        """Derivation name of the corrected form."""
        return f"corrections.{self.name}.corrected"

    def derivation(self, item: str) -> str:
        return f"corrections.{self.name}.{item}"

    def derivations(self) -> tuple[str, ...]:
        """Every derivation name the entry refers to."""
        return (self.original, self.corrected) + tuple(
            self.derivation(item) for _, item in self.effects)


_RATIO = "corrected ÷ published:"

CORRECTIONS: tuple[Correction, ...] = (
    Correction(
        "injection_pi", "Injection: intensity = flux / π",
        "A Lambertian emitter of flux Φ has peak intensity Φ/π, not Φ.",
        "off: every VPL injects π times its flux (×3.14 on all indirect light)",
        published=True, stages=("inject", "propagate"),
        effects=((_RATIO, "flux_factor"),),
        forms=("`I_p(ω) = Φ_p·clamp+⟨n_p, ω⟩`",
               "`I_p(ω) = Φ_p/π·clamp+⟨n_p, ω⟩`")),
    Correction(
        "propagation_4pi", "Propagation: no 1/(4π) per face",
        "Flux through a face is solid angle times intensity; the extra 1/(4π) averages "
        "twice.",
        "off: each step keeps 1/(4π) = 0.0796 of the flux",
        published=True, stages=("propagate",),
        effects=((_RATIO, "flux_factor"),),
        forms=("`Φ_f = Δω_f/(4π)·I(ω_c)`", "`Φ_f = Δω_f·I(ω_c)`")),
    Correction(
        "reprojection_pi", "Reprojection: face flux kept as is",
        "The face's flux becomes the new lobe's flux; dividing by π here undoes the "
        "injection's π.",
        "off alone: ×1/π per step; off together with injection: cancels",
        published=True, stages=("propagate",),
        effects=((_RATIO, "flux_factor"),),
        forms=("`Φ_lobe = Φ_f/π`", "`Φ_lobe = Φ_f`")),
    Correction(
        "exact_constants", "Exact solid angles",
        "The DX11 article prints rounded solid angles and π = 3.1415926.",
        "off: one step keeps ×{corrections.exact_constants.step_flux_original:.6f} "
        "instead of ×1",
        published=True, stages=("inject", "propagate"),
        effects=(("published, one step:", "step_flux_original"), (_RATIO, "flux_factor")),
        forms=("the decimals printed in the DX11 article (front 0.4006696846, side "
               "0.4234413544, π 3.1415926)", "exact values from the derivations")),
    Correction(
        "side_faces", "Side faces",
        "Each neighbour sends light through five faces of the target cell; the front face "
        "alone covers a fifth of the solid angle.",
        "off: one step keeps about ×{corrections.side_faces.step_flux_original:.3f} of the "
        "flux",
        published=False, stages=("propagate",),
        effects=(("front faces only, one step:", "step_flux_original"),
                 (_RATIO, "flux_factor")),
        forms=("front faces only", "front face + 4 side faces per neighbour")),
    Correction(
        "surfel_area_squared", "Occluder area grows with depth squared",
        "A texel of a perspective shadow map covers an area proportional to depth squared.",
        "off: far occluders block too little (geometry volume only)",
        published=False, stages=("geometry",),
        effects=((_RATIO, "flux_factor"),),
        forms=("surfel area `4·w/(W·H)` (linear in depth: the bug the annotations warn of)",
               "`4·w²/(W·H)`")),
    Correction(
        "ping_pong", "Ping-pong propagation",
        "Reading and writing the same texture races and re-propagates light that has "
        "already moved.",
        "off: light counted again each step (flux grows)",
        published=False, stages=("propagate",),
        effects=(("in place:", "accumulated_original"), ("ping-pong:", "accumulated_corrected"),
                 ("corrected ÷ published, flux-conserving step:", "flux_factor")),
        forms=("DX11 in-place read-modify-write of one texture (a data race)",
               "read grid t−1, write grid t")),
    Correction(
        "clamp_front_face", "Clamp the front face",
        "A two-coefficient SH lobe goes negative behind itself; clamping stops negative "
        "light from travelling.",
        "on: clamping adds a little flux (the audit's clamp gain)",
        published=False, stages=("propagate",),
        effects=(("clamp gain:", "clamp_gain"), ("L1 lobe behind itself:", "lobe_behind")),
        forms=("front-face term unclamped",
               "`clamp+` on the front-face intensity, as the DX11 shader does")),
    Correction(
        "model_face_weights", "Face weights of the model",
        "A face passes its solid angle times the intensity toward it, the same factor "
        "k_R·k_I·k_P = 1/π for every face; the DX11 shader divides front faces by 2π and "
        "side faces by 3π instead.",
        "off: one step keeps ×{corrections.model_face_weights.step_flux_original:.4f} of "
        "the flux",
        published=False, stages=("propagate",),
        effects=(("DX11 weights, one step:", "step_flux_original"), (_RATIO, "flux_factor")),
        forms=("DX11 shader: `Δω_front/(2π)` front, `Δω_side/(3π)` side",
               "`k_R·k_I·k_P·Δω_f` for every face")),
    Correction(
        "irradiance_gather", "Gather the irradiance",
        "A pixel needs the irradiance of the cell's light: its intensity weighted by the "
        "clamped cosine, per unit area of the cell; the DX11 shader reads the intensity "
        "toward −n instead, with no cosine lobe and no cell area.",
        "off: isotropic light reads ×h²/π of its irradiance (h the cell size), band 1 "
        "×3/(2π)",
        published=False, stages=("gather",),
        effects=(("band 0, corrected ÷ DX11:", "band0_factor"),
                 ("band 1, corrected ÷ DX11:", "band1_factor"),
                 ("isotropic light, corrected ÷ DX11:", "flux_factor")),
        forms=("DX11 shader: `E = max(⟨s, Y(−n)⟩, 0)`",
               "`E = max(⟨s, lobe(−n)⟩, 0)/h²`")),
)

BY_NAME: dict[str, Correction] = {entry.name: entry for entry in CORRECTIONS}


if len(BY_NAME) != len(CORRECTIONS):
    raise ValueError("two corrections share a name")
