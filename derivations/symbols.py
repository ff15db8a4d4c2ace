r"""The left-hand side of every registry result that is not already a formula.

A result whose expression is an ``Eq`` typesets with its own left-hand side; every other
result (a number, a vector, an expression) is a value *of something*, and this table says
of what, in LaTeX. :func:`derivations.registry.latex` writes ``symbol = value``, so the
window, the lessons and the Corrections panel never show a bare right-hand side such as
``2\pi/3``. The tests check that every non-formula result has an entry here and that no
entry names a result that does not exist.
"""

from __future__ import annotations

_FRONT = r"\Delta\omega_{\mathrm{front}}"
_SIDE = r"\Delta\omega_{\mathrm{side}}"
_RATIO = r"\frac{\Phi_{\mathrm{corrected}}}{\Phi_{\mathrm{published}}}"
_STEP = r"\frac{\Phi_{t+1}}{\Phi_{t}}"


def _printed(what: str) -> str:
    """The symbol of a value as a source printed it (a compound symbol in brackets, so
    the mark applies to all of it)."""
    if any(part in what for part in (" ", "/", r"\cdot")):
        what = r"\left(" + what + r"\right)"
    return what + r"^{\mathrm{printed}}"


SYMBOL_LATEX: dict[str, str] = {
    "Delta_omega_f": r"\Delta\omega_{f}",
    "Delta_omega_front": _FRONT,
    "Delta_omega_side": _SIDE,
    "cos_theta": r"\cos\theta",
    "cos_theta_i": r"\cos\theta_{i}",
    "cos_theta_o": r"\cos\theta_{o}",
    "c_diff": r"c_{\mathrm{diff}}",
    "Phi_lobe": r"\Phi_{\mathrm{lobe}}",
    "Delta_omega_texel": r"\Delta\omega_{\mathrm{texel}}",
    "pi_formula": r"\pi_{\mathrm{formula}}",
    "p_{HG}": r"p_{\mathrm{HG}}",
}
"""How a sympy symbol whose name sympy would typeset badly is written (``Delta_omega_f``
would read ``\\Delta_{\\omega f}``, ``cos_theta_i`` ``cos_{\theta i}``): by its name."""

SYMBOLS: dict[str, str] = {
    # solid angles
    "solid_angles.front_face": _FRONT,
    "solid_angles.side_face": _SIDE,
    "solid_angles.front_face_spherical": _FRONT,
    "solid_angles.side_face_spherical": _SIDE,
    "solid_angles.cube_face": r"\Delta\omega_{\mathrm{cube\ face}}",
    "solid_angles.sphere": r"\int_{S^2} d\omega",
    "solid_angles.projected_hemisphere": r"\int_{H^2} \cos\theta \, d\omega",
    # spherical harmonics
    "sh.c0": "c_{0}",
    "sh.c1": "c_{1}",
    "sh.basis_l1": r"Y(x, y, z)",
    "sh.coslobe_c0": r"\mathrm{lobe}_{0}(+z)",
    "sh.coslobe_c1": r"\mathrm{lobe}_{2}(+z)",
    "sh.net_flux_c1": r"\mathrm{flux}_{2}(+z)",
    "sh.lobe": r"\mathrm{lobe}(n)",
    "sh.flux_factor": r"\Phi / f_{0}",
    "sh.clamped_cosine_energy": r"\int \max(\cos\theta, 0)^{2} \, d\omega",
    "sh.l1_energy_fraction": r"E_{L1} / E",
    "sh.l2_energy_fraction": r"E_{L2} / E",
    "sh.band0_energy_fraction": r"E_{0} / E",
    "sh.band1_energy_fraction": r"E_{1} / E",
    "sh.band2_energy_fraction": r"E_{2} / E",
    "sh.basis_l2": r"Y_{L2}(x, y, z)",
    "sh.l2_c0": "c_{0}",
    "sh.l2_c1": "c_{1}",
    "sh.l2_c2": "c_{2}",
    "sh.l2_c3": "c_{3}",
    "sh.l2_c4": "c_{4}",
    "sh.l2_coslobe_c0": r"\mathrm{lobe}_{0}(+z)",
    "sh.l2_coslobe_c1": r"\mathrm{lobe}_{2}(+z)",
    "sh.l2_coslobe_c2": r"\mathrm{lobe}_{6}(+z)",
    "sh.zonal_rotation_factors": r"(A_{0}, A_{1}, A_{2})",
    "sh.lobe_l2": r"\mathrm{lobe}_{L2}(n)",
    "sh.l2_lobe_c2": r"k_{xy}",
    "sh.l2_lobe_c3": r"k_{3z^{2}-1}",
    "sh.l2_lobe_c4": r"k_{x^{2}-y^{2}}",
    # reflective shadow maps
    "rsm.texel_flux_published_over_correct":
        r"\Phi_{o}^{\mathrm{published}} / \Phi_{o}",
    "rsm.pixel_solid_angle_approx": r"\Delta\omega_{\mathrm{texel}}",
    "rsm.pixel_solid_angle_exact": r"\Delta\omega_{ij}",
    "rsm.pixel_ratio_centre": r"\frac{\Delta\omega_{\mathrm{texel}}}{\Delta\omega_{ij}}"
                              r"\Big|_{\mathrm{centre}}",
    "rsm.pixel_ratio_corner": r"\frac{\Delta\omega_{\mathrm{texel}}}{\Delta\omega_{ij}}"
                              r"\Big|_{\mathrm{corner}}",
    "rsm.surfel_area": r"A_{\mathrm{texel}}",
    "rsm.cone_solid_angle": r"\int_{S^2} f \, d\omega",
    "rsm.cone_total_flux": r"\Phi_{\mathrm{cone}}",
    "rsm.cone_surfel_area": r"A_{\mathrm{texel}}^{\mathrm{cone}}",
    "rsm.point_light_room_flux": r"\Phi_{\mathrm{room}}",
    # corrections: corrected over published
    "corrections.injection_pi.flux_factor": _RATIO,
    "corrections.propagation_4pi.flux_factor": _RATIO,
    "corrections.reprojection_pi.flux_factor": _RATIO,
    "corrections.exact_constants.flux_factor": _RATIO,
    "corrections.model_face_weights.flux_factor": _RATIO,
    "corrections.irradiance_gather.band0_factor": r"\mathrm{lobe}_0 / Y_0",
    "corrections.irradiance_gather.band1_factor": r"\mathrm{lobe}_2 / Y_2",
    "corrections.irradiance_gather.flux_factor": r"E_{\mathrm{corrected}} / "
                                                 r"E_{\mathrm{DX11}}",
    "corrections.side_faces.flux_factor": r"\frac{\Phi_{\mathrm{5\ faces}}}"
                                          r"{\Phi_{\mathrm{front\ only}}}",
    "corrections.surfel_area_squared.flux_factor": r"A_{w^{2}} / A_{w}",
    "corrections.ping_pong.flux_factor": r"\frac{\Phi_{\mathrm{ping\ pong}}}"
                                         r"{\Phi_{\mathrm{in\ place}}}",
    # propagation
    "neighbours26.edge_face": r"\Delta\omega_{\mathrm{edge}}",
    "neighbours26.corner_face": r"\Delta\omega_{\mathrm{corner}}",
    "neighbours26.edge_eval_big": r"e_{\mathrm{edge},x}",
    "neighbours26.edge_eval_small": r"e_{\mathrm{edge},z}",
    "neighbours26.corner_eval_big": r"e_{\mathrm{corner},x}",
    "neighbours26.corner_eval_small": r"e_{\mathrm{corner},y}",
    "neighbours26.step_flux_factor": r"\Phi_{t}/\Phi_{t-1}\big|_{26}",
    "propagation.side_eval_direction": r"e_{\mathrm{side}}",
    "propagation.side_eval_small": r"e_{\mathrm{side},x}",
    "propagation.side_eval_big": r"e_{\mathrm{side},y}",
    "propagation.side_reprojection_direction": r"r_{\mathrm{side}}",
    "propagation.front_reprojection_direction": r"e_{\mathrm{front}} = r_{\mathrm{front}}",
    "propagation.l2_face_basis_sums": r"\Big(\sum_{f} Y_{k}(e_{f})\Big)",
    "propagation.step_flux_factor": _STEP,
    "propagation.step_flux_factor_original": _STEP + r"\Big|_{\mathrm{published}}",
    "propagation.step_flux_factor_corrected": _STEP + r"\Big|_{\mathrm{corrected}}",
    "propagation.step_flux_factor_dx11": _STEP + r"\Big|_{\mathrm{DX11}}",
    "propagation.front_weight_dx11": r"w_{\mathrm{front}}^{\mathrm{DX11}} / " + _FRONT,
    "propagation.side_weight_dx11": r"w_{\mathrm{side}}^{\mathrm{DX11}} / " + _SIDE,
    "propagation.front_share_dx11": r"\pi\, w_{\mathrm{front}}^{\mathrm{DX11}} / " + _FRONT,
    "propagation.side_share_dx11": r"\pi\, w_{\mathrm{side}}^{\mathrm{DX11}} / " + _SIDE,
    # occlusion
    "occlusion.one_sided": r"B(n)",
    "occlusion.double_sided_lobe": r"\mathrm{lobe}(n) + \mathrm{lobe}(-n)",
    "occlusion.double_sided_blocking": r"B_{\mathrm{double}} \, s^{2} / A",
    "occlusion.camera_surfel_area": r"A_{\mathrm{pixel}}",
    "occlusion.reprojection_depth_bound": r"\max |\Delta d|",
    "occlusion.statistical_visibility": r"V_{\mathrm{stat}}(\tau)",
    "occlusion.statistical_first_order": r"V_{\mathrm{stat}}(\tau) + O(\tau^{2})",
    # participating media and the glossy lobe
    "media.isotropic_phase": r"p_{\mathrm{iso}}",
    "media.isotropic_normalisation": r"\int_{S^2} p_{\mathrm{iso}} \, d\omega",
    "media.hg_normalisation": r"\int_{S^2} p_{\mathrm{HG}} \, d\omega",
    "media.hg_band_factors": r"(a_{0}, a_{1}, a_{2}, a_{3})_{\mathrm{HG}}",
    "media.hg_zonal_coefficients": r"\Big(\int_{S^2} p_{\mathrm{HG}} Y_{l0} \, d\omega\Big)",
    "media.isotropic_band_factors": r"(a_{0}, a_{1}, a_{2}, a_{3})_{\mathrm{iso}}",
    # errata: values as the sources printed them
    "errata.annotations.front_corner_dot_adjacent": _printed(r"c_{1} \cdot c_{2}"),
    "errata.annotations.front_corner_dot_diagonal": _printed(r"c_{3} \cdot c_{2}"),
    "errata.annotations.front_maple_delta": _printed(r"\delta"),
    "errata.annotations.front_maple_alpha": _printed(r"\alpha"),
    "errata.annotations.front_maple_closed_form": _printed(_FRONT),
    "errata.annotations.front_maple_decimal": _printed(_FRONT),
    "errata.annotations.side_corner_dot": _printed(r"c_{2} \cdot c_{4}"),
    "errata.annotations.side_maple_closed_form": _printed(_SIDE),
    "errata.annotations.side_maple_20_digits": _printed(_SIDE),
    "errata.annotations.side_maple_5_digits": _printed(_SIDE),
    "errata.annotations.front_integral_closed_form": _printed(_FRONT),
    "errata.annotations.front_integral_decimal": _printed(_FRONT),
    "errata.annotations.side_integral_closed_form": _printed(_SIDE),
    "errata.annotations.side_integral_decimal": _printed(_SIDE),
    "errata.annotations.coslobe_c0": _printed(r"s_{0}"),
    "errata.annotations.coslobe_c1": _printed(r"s_{2}"),
    "errata.annotations.side_direction_small": _printed(r"e_{\mathrm{side},x}"),
    "errata.annotations.side_direction_big": _printed(r"e_{\mathrm{side},y}"),
    "errata.dx11.rsm_vpls": _printed(r"N_{\mathrm{VPL}}"),
    "errata.dx11.sh_c0": _printed(r"\mathrm{SH\_C0}"),
    "errata.dx11.sh_c1": _printed(r"\mathrm{SH\_C1}"),
    "errata.dx11.coslobe_c0": _printed(r"\mathrm{SH\_cosLobe\_C0}"),
    "errata.dx11.coslobe_c1": _printed(r"\mathrm{SH\_cosLobe\_C1}"),
    "errata.dx11.pi": _printed(r"\pi"),
    "errata.dx11.front_solid_angle": _printed(_FRONT),
    "errata.dx11.side_solid_angle": _printed(_SIDE),
    "errata.dx11.front_weight": _printed(r"w_{\mathrm{front}}"),
    "errata.dx11.side_weight": _printed(r"w_{\mathrm{side}}"),
    "errata.dx11.side_eval_small": _printed(r"e_{\mathrm{side},x}"),
    "errata.dx11.side_eval_big": _printed(r"e_{\mathrm{side},y}"),
    "errata.dx11.surfel_weight": _printed(r"w_{\mathrm{surfel}}"),
    "errata.dx11.l1_accuracy": _printed(r"E_{L1} / E"),
    "errata.dx12.y00": _printed(r"Y_{0}^{0}"),
    "errata.dx12.y1": _printed(r"c_{1}"),
}
