r"""The three published formulas the annotations correct, each as a flux identity.

Notation (annotations §1): ``clamp⁺(x) = max(x, 0)``, ``Φ`` flux, ``I = dΦ/dω``.
For each correction ``<key>`` (a field of ``Corrections``) the registry holds
``corrections.<key>.original`` and ``.corrected`` (the formula as an ``Eq``),
``.flux_factor`` (corrected ÷ original of the quantity it changes) and the flux
identities that decide between them.

Injection (``injection_pi``, annotations §4.1). A VPL emits ``Φ_p``; the published
intensity ``I_p(ω) = Φ_p·clamp⁺⟨n_p, ω⟩`` emits

.. math:: \int_{S^2} \Phi_p \max(0, \cos\theta)\,d\omega = \pi\,\Phi_p \ne \Phi_p,

so the corrected intensity divides by π and emits exactly ``Φ_p``.

Propagation (``propagation_4pi``, §6.2). The flux through a face of solid angle
``Δω_f`` of an intensity that is constant (``I(ω_c)``) over the face is
:math:`\int_{\Delta\omega_f} I\,d\omega = \Delta\omega_f\,I(\omega_c)`; the published
``Δω_f/(4π)·I(ω_c)`` is ``1/(4π)`` of it.

Reprojection (``reprojection_pi``, §6.3). A face that receives ``Φ_f`` re-emits it as a
cosine lobe whose flux is ``Φ_lobe``; with the corrected intensity
``(1/π)·Φ_lobe·clamp⁺⟨n_l, ω⟩`` that lobe carries exactly ``Φ_lobe``, so ``Φ_lobe = Φ_f``
conserves the flux and the published ``Φ_lobe = Φ_f/π`` keeps only ``1/π`` of it.
Together with the injection correction the net factor ``k_R·k_I = 1/π`` is unchanged
(docs/MODEL.md, "Propagation").

Examples
--------
>>> from derivations.corrections import emitted_flux, Phi_p
>>> emitted_flux(Phi_p)          # published intensity
pi*Phi_p
>>> emitted_flux(Phi_p / sp.pi)  # corrected intensity
Phi_p

References
----------
A. Kirsch, "Light Propagation Volumes — Corrections" (2010); "Annotations" §4.1, §6.2, §6.3.
A. Kaplanyan, C. Dachsbacher, "Cascaded Light Propagation Volumes for Real-Time Indirect
Illumination", I3D 2010.
"""

from __future__ import annotations

import sympy as sp

from derivations.registry import Result, result

MODULE = "corrections"
KEYS = ("injection_pi", "propagation_4pi", "reprojection_pi")

theta, phi = sp.symbols("theta phi", real=True)
Phi_p, Phi_f, Phi_l, I_p, I_c = sp.symbols("Phi_p Phi_f Phi_lobe I_p I_c", positive=True)
delta_omega = sp.Symbol(r"Delta_omega_f", positive=True)
clamped_cos = sp.Max(0, sp.cos(theta))
"""``clamp⁺⟨n, ω⟩`` with θ the angle between n and ω."""


def emitted_flux(scale: sp.Expr) -> sp.Expr:
    """``∫_{S²} scale·clamp⁺(cos θ) dω`` (θ from the lobe axis): only ``θ < π/2`` counts."""
    return sp.integrate(scale * sp.cos(theta) * sp.sin(theta), (theta, 0, sp.pi / 2),
                        (phi, 0, 2 * sp.pi))


def face_flux(intensity: sp.Expr, solid_angle: sp.Expr) -> sp.Expr:
    """Exact flux of a constant intensity through a face: ``∫_{Δω} I dω = I·Δω``."""
    omega = sp.Symbol("omega")
    return sp.integrate(intensity, (omega, 0, solid_angle))


def formulas() -> dict[str, tuple[sp.Eq, sp.Eq]]:
    """``key -> (original, corrected)`` formulas, as the annotations write them."""
    return {
        "injection_pi": (sp.Eq(I_p, Phi_p * clamped_cos),
                         sp.Eq(I_p, Phi_p / sp.pi * clamped_cos)),
        "propagation_4pi": (sp.Eq(Phi_f, delta_omega / (4 * sp.pi) * I_c),
                            sp.Eq(Phi_f, delta_omega * I_c)),
        "reprojection_pi": (sp.Eq(Phi_l, Phi_f / sp.pi), sp.Eq(Phi_l, Phi_f)),
    }


def flux_factors() -> dict[str, sp.Expr]:
    """Corrected ÷ original of the quantity each formula defines (I_p, Φ_f, Φ_lobe)."""
    return {key: sp.simplify(corrected.rhs / original.rhs)
            for key, (original, corrected) in formulas().items()}


def flux_identities() -> dict[str, dict[str, sp.Expr]]:
    """For each key: the flux each version delivers, and the flux it should deliver."""
    eqs = formulas()
    injection_o, injection_c = (e.rhs / clamped_cos for e in eqs["injection_pi"])
    # Reprojected lobe: intensity Φ_lobe/π·clamp⁺ (corrected injection normalisation).
    reproject_o, reproject_c = (e.rhs for e in eqs["reprojection_pi"])
    return {
        "injection_pi": {"emitted_original": emitted_flux(injection_o),
                         "emitted_corrected": emitted_flux(injection_c),
                         "should_be": Phi_p},
        "propagation_4pi": {"through_face_original": eqs["propagation_4pi"][0].rhs,
                            "through_face_corrected": eqs["propagation_4pi"][1].rhs,
                            "should_be": face_flux(I_c, delta_omega)},
        "reprojection_pi": {"reprojected_original": emitted_flux(reproject_o / sp.pi),
                            "reprojected_corrected": emitted_flux(reproject_c / sp.pi),
                            "should_be": Phi_f},
    }


_STATEMENTS = {
    "injection_pi": ("VPL intensity as published (Crytek): emits π·Φ_p.",
                     "VPL intensity normalised by 1/π: emits exactly Φ_p.",
                     "Corrected ÷ published VPL intensity: 1/π."),
    "propagation_4pi": ("Flux onto a face as published: Δω_f/(4π)·I(ω_c).",
                        "Flux onto a face: Δω_f·I(ω_c) = ∫_face I dω for constant I.",
                        "Corrected ÷ published face flux: 4π."),
    "reprojection_pi": ("Reprojected flux as published: Φ_lobe = Φ_f/π (loses 1 − 1/π).",
                        "Reprojected flux: Φ_lobe = Φ_f (the lobe re-emits all of it).",
                        "Corrected ÷ published reprojected flux: π."),
}


def results() -> list[Result]:
    """The three published formulas (the five implementation switches follow them in the
    registry: ``derivations/implementation_switches.py``, which builds on this module)."""
    out: list[Result] = []
    eqs, factors, identities = formulas(), flux_factors(), flux_identities()
    glsl = {"injection_pi": "INV_PI"}
    for key in KEYS:
        original, corrected = eqs[key]
        s_orig, s_corr, s_factor = _STATEMENTS[key]
        out += [
            result(MODULE, f"{key}.original", original, s_orig),
            result(MODULE, f"{key}.corrected", corrected, s_corr),
            result(MODULE, f"{key}.flux_factor", factors[key], s_factor,
                   glsl_name=glsl.get(key)),
        ]
    inj, prop, rep = (identities[k] for k in KEYS)
    out += [
        result(MODULE, "injection_pi.emitted_original",
               sp.Eq(sp.Symbol("Phi_emitted"), inj["emitted_original"]),
               "∫ Φ_p·max(0, ⟨n_p, ω⟩) dω = π·Φ_p: the published VPL emits π times its flux."),
        result(MODULE, "injection_pi.emitted_corrected",
               sp.Eq(sp.Symbol("Phi_emitted"), inj["emitted_corrected"]),
               "∫ Φ_p/π·max(0, ⟨n_p, ω⟩) dω = Φ_p: the corrected VPL emits its flux."),
        result(MODULE, "propagation_4pi.exact_face_flux",
               sp.Eq(Phi_f, prop["should_be"]),
               "Flux of a constant intensity through a face: ∫_face I dω = Δω_f·I."),
        result(MODULE, "reprojection_pi.reprojected_original",
               sp.Eq(sp.Symbol("Phi_reprojected"), rep["reprojected_original"]),
               "The published reprojection re-emits Φ_f/π of the face's flux Φ_f."),
        result(MODULE, "reprojection_pi.reprojected_corrected",
               sp.Eq(sp.Symbol("Phi_reprojected"), rep["reprojected_corrected"]),
               "The corrected reprojection re-emits all of the face's flux Φ_f."),
    ]
    return out
