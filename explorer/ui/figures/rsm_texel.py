"""An RSM texel on a surface you tilt: the footprint grows, the irradiance falls, the flux
stays.

The light arrives straight down through one texel of its shadow map (a square of area A0
across the beam, carrying the flux Φ0 = E0·A0). On a surface tilted by θ the texel's four
corner rays meet the surface in a footprint of area A0/cos θ, and the surface receives
the irradiance E0·cos θ; their product, the flux the texel stands for, is Φ0 at every
tilt. That is why a reflective shadow map stores flux per texel (docs/MODEL.md
"Reflective shadow map"), and why a VPL's flux needs no cos θ of its own. The footprint
is computed by intersecting the corner rays with the tilted plane; the plot beside it
repeats that for every θ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from imgui_bundle import imgui, implot

from explorer.figure_params import MAX_TILT
from explorer.figure_params import RsmTexelParams as Params
from explorer.ui.figures import plotting, style

TEXEL = 0.5                  # texel edge in the side view (world units)
_LIGHT_HEIGHT = 1.5
_CURVE_SAMPLES = 171
_FOOTPRINT = imgui.ImVec4(0.33, 0.62, 0.98, 1.0)
_IRRADIANCE = imgui.ImVec4(1.0, 0.68, 0.26, 1.0)
_CURVES = (("footprint", "footprint A/A0 = 1/cos θ", _FOOTPRINT),
           ("irradiance", "irradiance E/E0 = cos θ", _IRRADIANCE),
           ("flux", "flux E·A/Φ0", style.EXACT))


@dataclass
class State:
    theta_deg: float
    handles: dict = field(default_factory=dict, compare=False)
    """Handle name ("tilt") -> its screen position (pixels) as last drawn."""

    @classmethod
    def from_params(cls, params: Params) -> State:
        return cls(params.theta_deg)


# ----------------------------------------------------------------------------- the numbers


def surface_normal(theta_deg: np.ndarray | float) -> np.ndarray:
    """Unit normal (..., 3) of the surface tilted by θ about z from facing +y."""
    t = np.radians(np.asarray(theta_deg, np.float64))
    return np.stack([np.sin(t), np.cos(t), np.zeros_like(t)], -1)


def footprint(theta_deg: np.ndarray | float, texel: float = 1.0) -> np.ndarray:
    """Corners (..., 4, 3) where the four corner rays of a texel (edge ``texel``, centred
    on the y axis, light travelling along −y) meet the plane through the origin with the
    tilted normal: y = −(n_x·x + n_z·z)/n_y."""
    n = surface_normal(theta_deg)[..., None, :]
    half = texel / 2.0
    xz = np.array([[-half, -half], [half, -half], [half, half], [-half, half]])
    x, z = xz[:, 0], xz[:, 1]
    y = -(n[..., 0] * x + n[..., 2] * z) / n[..., 1]
    return np.stack(np.broadcast_arrays(x, y, z), -1)


def quad_area(corners: np.ndarray) -> np.ndarray:
    """Area of planar quads (..., 4, 3) with corners in order: half the norm of the sum of
    the cross products of consecutive corners (the vector area)."""
    c = np.asarray(corners, np.float64)
    vector_area = 0.5 * np.sum(np.cross(c, np.roll(c, -1, axis=-2)), axis=-2)
    return np.linalg.norm(vector_area, axis=-1)


def texel_terms(theta_deg: np.ndarray | float) -> dict[str, np.ndarray]:
    """Footprint area A/A0, irradiance E/E0 = ⟨n, −l⟩ and flux E·A/Φ0 at each tilt."""
    texel = 1.0
    area = quad_area(footprint(theta_deg, texel)) / texel**2
    light = np.array([0.0, -1.0, 0.0])
    irradiance = np.maximum(-surface_normal(theta_deg) @ light, 0.0)
    return {"footprint": area, "irradiance": irradiance, "flux": area * irradiance}


def readouts(params: Params, state: State, context=None) -> dict[str, float]:
    terms = texel_terms(state.theta_deg)
    return {"theta_deg": state.theta_deg, **{k: float(v) for k, v in terms.items()}}


# ----------------------------------------------------------------------------- drawing


def draw(params: Params, state: State, width: float, context) -> None:
    drawers = [lambda w: _side_view(state, w)] + ([lambda w: _plot(state, w)] if params.plot
                                                  else [])
    style.views(width, drawers, 260.0)
    _numbers(state, width)


def _side_view(state: State, width: float) -> None:
    imgui.text_colored(style.MUTED, "Side view: drag the yellow handle to tilt the surface")
    flags = (implot.Flags_.equal | implot.Flags_.no_inputs | implot.Flags_.no_menus
             | implot.Flags_.no_title | implot.Flags_.no_legend)
    if not implot.begin_plot("##side view", style.square(width), flags):
        return
    hidden = implot.AxisFlags_.no_decorations
    implot.setup_axes("", "", hidden, hidden)
    implot.setup_axes_limits(-1.5, 1.5, -1.2, 1.8, implot.Cond_.once)   # square: 3 × 3
    theta = state.theta_deg
    corners = footprint(theta, TEXEL)
    half = TEXEL / 2.0
    # The light's parallel rays, the texel at the top, and the rays through its corners.
    for x in np.linspace(-1.1, 1.1, 12):
        implot.plot_line("##ray", np.array([x, x]), np.array([_LIGHT_HEIGHT + 0.2, -1.0]),
                         style.line_spec(style.with_alpha(style.NOTE, 0.12), 1.0))
    implot.plot_line("##texel", np.array([-half, half]),
                     np.array([_LIGHT_HEIGHT, _LIGHT_HEIGHT]), style.line_spec(style.NOTE, 4.0))
    implot.plot_text("RSM texel, A0", 0.0, _LIGHT_HEIGHT, imgui.ImVec2(0.0, -14.0))
    for x, y in ((corners[0, 0], corners[0, 1]), (corners[1, 0], corners[1, 1])):
        implot.plot_line("##corner ray", np.array([x, x]), np.array([_LIGHT_HEIGHT, y]),
                         style.line_spec(style.with_alpha(style.NOTE, 0.8), 1.5))
    style.fill_polygon_in_plot(np.array([-half, half, half, -half]),
                               np.array([_LIGHT_HEIGHT, _LIGHT_HEIGHT, corners[1, 1],
                                         corners[0, 1]]), style.NOTE, 0.10)
    # The surface, the footprint on it and its normal.
    tangent = np.array([math.cos(math.radians(theta)), -math.sin(math.radians(theta))])
    ends = np.outer([-1.0, 1.0], tangent)
    implot.plot_line("##surface", ends[:, 0].copy(), ends[:, 1].copy(),
                     style.line_spec(style.TEXT, 2.0))
    implot.plot_line("##footprint", corners[:2, 0].copy(), corners[:2, 1].copy(),
                     style.line_spec(_FOOTPRINT, 5.0))
    normal = surface_normal(theta)[:2] * 0.7
    implot.plot_line("##normal", np.array([0.0, normal[0]]), np.array([0.0, normal[1]]),
                     style.line_spec(style.TEXT, 1.5))
    implot.plot_text("n", float(normal[0]), float(normal[1]), imgui.ImVec2(8.0, -8.0))
    arc = np.radians(np.linspace(0.0, theta, 24))
    implot.plot_line("##theta", 0.35 * np.sin(arc), 0.35 * np.cos(arc),
                     style.line_spec(style.HANDLE, 1.5))
    implot.plot_line("##toward the light", np.array([0.0, 0.0]), np.array([0.0, 0.45]),
                     style.line_spec(style.with_alpha(style.HANDLE, 0.6), 1.0))
    # Between the vertical and the normal, above the arc, whatever the tilt.
    middle = math.radians(theta / 2.0)
    implot.plot_text(f"θ = {theta:.0f}°", 0.6 * math.sin(middle), 0.6 * math.cos(middle),
                     imgui.ImVec2(30.0, 0.0))
    # Below the surface, far enough along −n (in pixels) that the text clears the line.
    label = "footprint A0/cos θ"
    sin_t, cos_t = math.sin(math.radians(theta)), math.cos(math.radians(theta))
    away = 24.0 + 0.5 * imgui.calc_text_size(label).x * sin_t
    implot.plot_text(label, float(corners[:2, 0].mean()), float(corners[:2, 1].mean()),
                     imgui.ImVec2(-sin_t * away, cos_t * away))
    handle = ends[1]
    state.handles = {"tilt": implot.plot_to_pixels(float(handle[0]), float(handle[1]))}
    changed, x, y, *_ = implot.drag_point(0, float(handle[0]), float(handle[1]),
                                          style.HANDLE, 7.0)
    if changed and x > 0:
        state.theta_deg = float(np.clip(math.degrees(math.atan2(-y, x)), 0.0, MAX_TILT))
    implot.end_plot()


def _plot(state: State, width: float) -> None:
    imgui.text_colored(style.MUTED, "Against the tilt θ (relative to facing the light)")
    thetas = np.linspace(0.0, MAX_TILT, _CURVE_SAMPLES)
    terms = texel_terms(thetas)
    everything = np.concatenate(list(terms.values()))
    scale = plotting.choose_scale(everything)
    if not implot.begin_plot("##tilt", style.square(width), implot.Flags_.no_menus
                             | implot.Flags_.no_box_select | implot.Flags_.no_title):
        return
    implot.setup_axes("θ [degrees]", "", 0, 0)
    implot.setup_axis_limits(implot.ImAxis_.x1, 0.0, 90.0, implot.Cond_.always)
    plotting.setup_value_axis(implot.ImAxis_.y1, everything, scale)
    implot.setup_legend(implot.Location_.north_west)
    now = texel_terms(state.theta_deg)
    for key, label, colour in _CURVES:
        implot.plot_line(label, thetas, terms[key], style.line_spec(colour, 2.0))
        implot.plot_scatter(f"##{key} now", np.array([state.theta_deg]),
                            np.array([float(now[key])]),
                            style.line_spec(colour, 1.0, implot.Marker_.circle))
    implot.plot_inf_lines("##now", np.array([state.theta_deg]),
                          style.line_spec(style.HANDLE, 1.5))
    implot.end_plot()


def _numbers(state: State, width: float) -> None:
    r = readouts(None, state)
    rows = [["footprint A", f"{r['footprint']:.3f} A0"],
            ["irradiance E", f"{r['irradiance']:.3f} E0"],
            ["flux E·A", f"{r['flux']:.3f} Φ0"]]
    style.readout_table("##texel numbers", ["", f"θ = {r['theta_deg']:.1f}°"], rows,
                        min(width, 360.0), [None, style.HANDLE])
