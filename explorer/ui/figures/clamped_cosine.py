"""The clamped cosine around a normal you drag, against its L1 and L2 projections.

A polar slice (the x–y plane: x right, y up) and a 3D view show clamp⁺⟨n, ω⟩, its L1
(4-coefficient) and L2 (9-coefficient) SH projections, and where a projection goes
negative (its tail behind the surface, shaded red). The projection is computed numerically
each time the normal moves (docs/MODEL.md "Notation and storage"), and the table under the
plots reads the energy each order keeps (L1 7/8, L2 127/128, the same for every normal),
the value toward the normal and the most negative value, the share of the lobe's flux in
the negative tail, and all three functions toward a probe direction you drag.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from imgui_bundle import imgui, implot, implot3d

from explorer.figure_params import ClampedCosineParams as Params
from explorer.lpv.twin.light_grid import sh_basis
from explorer.ui.figures import style

_MU_NODES = 64          # Gauss–Legendre nodes on each of μ ∈ [−1, 0] and [0, 1]
_PHI_NODES = 96
_CURVE_SAMPLES = 721    # 0.5° steps around the slice, the normal's direction included
_MESH_ELEVATIONS, _MESH_AZIMUTHS = 19, 37
_SLICE_RADIUS = 1.25


@dataclass
class State:
    normal_deg: float
    probe_deg: float
    handles: dict = field(default_factory=dict, compare=False)
    """Handle name ("n", "ω") -> its screen position (pixels) as last drawn: where a
    reader (or a click test) grabs it."""

    @classmethod
    def from_params(cls, params: Params) -> State:
        return cls(params.normal_deg, params.probe_deg)


# ----------------------------------------------------------------------------- the numbers


def slice_direction(degrees: float) -> np.ndarray:
    """Unit vector in the slice plane, ``degrees`` from +y toward +x."""
    a = math.radians(degrees)
    return np.array([math.sin(a), math.cos(a), 0.0])


def sphere_quadrature(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Directions (P, 3) and weights (P,) over the sphere, in the normal's frame:
    Gauss–Legendre in μ = ⟨n, ω⟩ on [−1, 0] and [0, 1] separately (so the lobe's kink at
    μ = 0 falls between the two rules and polynomial integrands are exact), uniform in φ."""
    n = np.asarray(normal, np.float64) / np.linalg.norm(normal)
    helper = np.array([0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    nodes, weights = np.polynomial.legendre.leggauss(_MU_NODES)
    mu = np.concatenate([(nodes - 1.0) / 2.0, (nodes + 1.0) / 2.0])
    w_mu = np.concatenate([weights, weights]) / 2.0
    phi = np.arange(_PHI_NODES) * (2.0 * np.pi / _PHI_NODES)
    mu_g, phi_g = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(np.maximum(1.0 - mu_g**2, 0.0))
    dirs = (mu_g[..., None] * n + (s * np.cos(phi_g))[..., None] * t1
            + (s * np.sin(phi_g))[..., None] * t2)
    w = np.repeat(w_mu[:, None], _PHI_NODES, axis=1) * (2.0 * np.pi / _PHI_NODES)
    return dirs.reshape(-1, 3), w.reshape(-1)


@dataclass(frozen=True)
class Projection:
    """The clamped cosine around ``normal`` projected on SH bands 0–2, numerically."""

    normal: np.ndarray
    coefficients: np.ndarray        # (9,) in reference.sh_basis's order
    lobe_energy: float              # ∫ clamp⁺(cos)² dω (2π/3)
    lobe_flux: float                # ∫ clamp⁺(cos) dω (π)
    band_energy: np.ndarray         # (3,) Σ s_k² of bands 0, 1, 2 (Parseval)
    negative_flux: dict[int, float]  # order -> ∫ min(projection, 0) dω; 0: the lobe's own

    def energy_kept(self, order: int) -> float:
        """Share of the lobe's energy the projection up to band ``order`` keeps."""
        return float(self.band_energy[:order + 1].sum() / self.lobe_energy)

    def energy_of_lobe(self) -> float:
        """The lobe's own energy as a share of itself (the exact column of the table)."""
        return self.lobe_energy / self.lobe_energy

    def evaluate(self, directions: np.ndarray, order: int) -> np.ndarray:
        """The projection up to band ``order`` toward unit ``directions`` (..., 3)."""
        count = (order + 1) ** 2
        return sh_basis(directions, 2)[..., :count] @ self.coefficients[:count]


def lobe(directions: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """clamp⁺⟨n, ω⟩."""
    return np.maximum(np.asarray(directions, np.float64) @ np.asarray(normal, np.float64), 0.0)


@lru_cache(maxsize=64)
def _projection(nx: float, ny: float, nz: float) -> Projection:
    normal = np.array([nx, ny, nz])
    dirs, w = sphere_quadrature(normal)
    f = lobe(dirs, normal)
    basis = sh_basis(dirs, 2)                      # (P, 9)
    coefficients = basis.T @ (w * f)               # s_k = ∫ f Y_k dω
    bands = np.array([coefficients[0] ** 2, np.sum(coefficients[1:4] ** 2),
                      np.sum(coefficients[4:9] ** 2)])
    negative = {0: float(w @ np.minimum(f, 0.0))}      # order 0: the exact lobe itself
    for order in (1, 2):
        count = (order + 1) ** 2
        negative[order] = float(w @ np.minimum(basis[:, :count] @ coefficients[:count], 0.0))
    return Projection(normal, coefficients, float(w @ f**2), float(w @ f), bands, negative)


def project_clamped_cosine(normal: np.ndarray) -> Projection:
    """The numerical SH projection (bands 0–2) of the clamped cosine around ``normal``."""
    n = np.asarray(normal, np.float64)
    n = n / np.linalg.norm(n)
    return _projection(*(round(float(v), 12) for v in n))


def slice_curves(projection: Projection) -> dict[str, np.ndarray]:
    """Angles (from +y, radians) around the slice starting at the normal, and the three
    functions along them."""
    start = math.atan2(projection.normal[0], projection.normal[1])
    angles = start + np.linspace(0.0, 2.0 * np.pi, _CURVE_SAMPLES)
    dirs = np.stack([np.sin(angles), np.cos(angles), np.zeros_like(angles)], -1)
    return {"angles": angles, "dirs": dirs, "exact": lobe(dirs, projection.normal),
            "l1": projection.evaluate(dirs, 1), "l2": projection.evaluate(dirs, 2)}


def readouts(params: Params, state: State, context=None) -> dict[str, float]:
    """Every number the figure shows, computed from the current normal and probe."""
    projection = project_clamped_cosine(slice_direction(state.normal_deg))
    curves = slice_curves(projection)
    probe = slice_direction(state.probe_deg)
    values = {"normal_deg": state.normal_deg, "probe_deg": state.probe_deg,
              "probe_angle_deg": math.degrees(math.acos(np.clip(
                  probe @ projection.normal, -1.0, 1.0))),
              "lobe_energy": projection.lobe_energy, "lobe_flux": projection.lobe_flux}
    for band in range(3):
        values[f"band{band}_energy"] = float(projection.band_energy[band]
                                             / projection.lobe_energy)
    for order, key in ((0, "exact"), (1, "l1"), (2, "l2")):
        along = curves[key]
        # The first sample within rounding of the minimum (the exact lobe is 0 from 90°).
        lowest = int(np.argmax(along <= along.min() + 1e-12))
        values[f"{key}_energy"] = (projection.energy_kept(order) if order
                                   else projection.energy_of_lobe())
        values[f"{key}_at_normal"] = float(along[0])
        values[f"{key}_min"] = float(along[lowest])
        values[f"{key}_min_angle_deg"] = abs(math.degrees(
            (curves["angles"][lowest] - curves["angles"][0] + np.pi) % (2 * np.pi) - np.pi))
        values[f"{key}_negative_flux"] = projection.negative_flux[order] / projection.lobe_flux
        values[f"{key}_probe"] = float(lobe(probe, projection.normal) if not order
                                       else projection.evaluate(probe, order))
    return values


# ----------------------------------------------------------------------------- drawing


def draw(params: Params, state: State, width: float, context) -> None:
    orders = (1, 2) if params.orders == "both" else (int(params.orders[1]),)
    drawers = {"polar": lambda w: _polar(state, orders, w),
               "3d": lambda w: _three_d(state, orders, w)}
    style.views(width, list(drawers.values()) if params.view == "both"
                else [drawers[params.view]])
    _table(params, state, orders, width)


def _polar(state: State, orders: tuple[int, ...], width: float) -> None:
    projection = project_clamped_cosine(slice_direction(state.normal_deg))
    curves = slice_curves(projection)
    # Equal aspect keeps circles round (implot widens one axis, so the limits are set
    # once, not always); no_inputs keeps the reader from panning the handles away (the
    # drag points still move).
    flags = (implot.Flags_.equal | implot.Flags_.no_inputs | implot.Flags_.no_menus
             | implot.Flags_.no_title)
    imgui.text_colored(style.MUTED, "Slice z = 0 (x right, y up): drag n and ω")
    if not implot.begin_plot("##slice", style.square(width), flags):
        return
    ticks = implot.AxisFlags_.no_tick_labels
    implot.setup_axes("", "", ticks, ticks)
    implot.setup_axes_limits(-_SLICE_RADIUS, _SLICE_RADIUS, -_SLICE_RADIUS, _SLICE_RADIUS,
                             implot.Cond_.once)
    implot.setup_legend(implot.Location_.north_west, implot.LegendFlags_.no_buttons)
    circle = np.linspace(0.0, 2.0 * np.pi, 129)
    implot.plot_line("##unit circle", np.sin(circle), np.cos(circle),
                     style.line_spec(style.with_alpha(style.MUTED, 0.35), 1.0))
    dirs = curves["dirs"]
    for order in orders:
        values = curves[f"l{order}"]
        negative = np.maximum(-values, 0.0)
        if negative.max() > 0.0:
            # Drawn as |value| toward its direction, filled red: the tail behind the surface.
            xs, ys = negative * dirs[:, 0], negative * dirs[:, 1]
            style.fill_polygon_in_plot(xs, ys, style.NEGATIVE, 0.35)
            implot.plot_line(f"L{order} < 0 (drawn as |value|)" if order == orders[0]
                             else f"##L{order} negative", xs, ys,
                             style.line_spec(style.NEGATIVE, 1.5))
        positive = np.maximum(values, 0.0)
        colour = style.L1 if order == 1 else style.L2
        implot.plot_line(f"L{order} ({(order + 1) ** 2} coefficients)",
                         positive * dirs[:, 0], positive * dirs[:, 1],
                         style.line_spec(colour, 2.0))
    exact = curves["exact"]
    implot.plot_line("max(cos, 0) (exact)", exact * dirs[:, 0], exact * dirs[:, 1],
                     style.line_spec(style.EXACT, 2.0))
    _handles(state)
    implot.end_plot()


def _handles(state: State) -> None:
    """The normal (yellow, drag its tip) and the probe direction (dashed, drag its dot)."""
    n = slice_direction(state.normal_deg)
    p = slice_direction(state.probe_deg) * 1.1
    implot.plot_line("##normal", np.array([0.0, n[0]]), np.array([0.0, n[1]]),
                     style.line_spec(style.HANDLE, 2.5))
    implot.plot_line("##probe", np.array([0.0, p[0]]), np.array([0.0, p[1]]),
                     style.line_spec(style.with_alpha(style.TEXT, 0.5), 1.0))
    implot.plot_text("n", float(n[0]), float(n[1]), imgui.ImVec2(12.0 * n[0], -12.0 * n[1]))
    implot.plot_text("ω", float(p[0]), float(p[1]), imgui.ImVec2(12.0 * p[0], -12.0 * p[1]))
    state.handles = {"n": implot.plot_to_pixels(float(n[0]), float(n[1])),
                     "ω": implot.plot_to_pixels(float(p[0]), float(p[1]))}
    changed, x, y, *_ = implot.drag_point(0, float(n[0]), float(n[1]), style.HANDLE, 7.0)
    if changed and (x or y):
        state.normal_deg = math.degrees(math.atan2(x, y))
    changed, x, y, *_ = implot.drag_point(1, float(p[0]), float(p[1]), style.TEXT, 5.0)
    if changed and (x or y):
        state.probe_deg = math.degrees(math.atan2(x, y))


@lru_cache(maxsize=32)
def _lobe_mesh(nx: float, ny: float, nz: float, order: int, sign: int):
    """An implot3d Mesh of the surface r(ω)·ω with r = max(sign·value, 0); order 0 is the
    exact lobe. None when the surface is empty."""
    normal = np.array([nx, ny, nz])
    el = np.linspace(0.0, np.pi, _MESH_ELEVATIONS)
    az = np.linspace(0.0, 2.0 * np.pi, _MESH_AZIMUTHS)
    el_g, az_g = np.meshgrid(el, az, indexing="ij")
    dirs = np.stack([np.sin(el_g) * np.cos(az_g), np.cos(el_g), np.sin(el_g) * np.sin(az_g)],
                    -1)
    if order == 0:
        values = lobe(dirs, normal)
    else:
        values = project_clamped_cosine(normal).evaluate(dirs, order)
    radius = np.maximum(sign * values, 0.0)
    if radius.max() <= 0.0:
        return None
    vertices = style.to_implot3d(radius[..., None] * dirs).reshape(-1, 3)
    points = [implot3d.Point(float(x), float(y), float(z)) for x, y, z in vertices]
    idx = []
    for i in range(_MESH_ELEVATIONS - 1):
        for j in range(_MESH_AZIMUTHS - 1):
            a = i * _MESH_AZIMUTHS + j
            b, c, d = a + 1, a + _MESH_AZIMUTHS, a + _MESH_AZIMUTHS + 1
            idx += [a, c, b, b, c, d]
    return implot3d.Mesh(points, idx)


def _three_d(state: State, orders: tuple[int, ...], width: float) -> None:
    n = slice_direction(state.normal_deg)
    key = tuple(round(float(v), 6) for v in n)
    imgui.text_colored(style.MUTED, f"L{orders[0]} in 3D: drag to turn")
    if not implot3d.begin_plot("##3d", style.square(width),
                               implot3d.Flags_.no_menus | implot3d.Flags_.no_title):
        return
    lock = implot3d.AxisFlags_.lock | implot3d.AxisFlags_.no_tick_labels
    implot3d.setup_axes("x", "z", "y", lock, lock, lock)
    implot3d.setup_axes_limits(-1.0, 1.0, -1.0, 1.0, -1.0, 1.0, implot3d.Cond_.always)
    implot3d.setup_box_rotation(15.0, -20.0, False, implot3d.Cond_.once)
    implot3d.setup_box_scale(1.2, 1.2, 1.2)
    implot3d.setup_legend(implot3d.Location_.north_west)
    _slice_plane()
    # One order in 3D (the first asked for): two nested lobes would hide each other.
    order = orders[0]
    colour = style.L1 if order == 1 else style.L2
    for sign, tint, label in ((1, colour, f"L{order}"), (-1, style.NEGATIVE, f"L{order} < 0")):
        mesh = _lobe_mesh(*key, order, sign)
        if mesh is None:
            continue
        spec = implot3d.Spec()
        spec.fill_color = tint
        spec.fill_alpha = 0.7 if sign < 0 else 0.35
        spec.line_color = style.with_alpha(tint, 0.3)
        spec.flags = implot3d.MeshFlags_.no_markers
        implot3d.plot_mesh(label, mesh, spec)
    exact = _lobe_mesh(*key, 0, 1)
    spec = implot3d.Spec()
    spec.line_color = style.with_alpha(style.EXACT, 0.35)
    spec.fill_color = style.EXACT          # the legend's swatch (the mesh is not filled)
    spec.flags = implot3d.MeshFlags_.no_fill | implot3d.MeshFlags_.no_markers
    implot3d.plot_mesh("max(cos, 0)", exact, spec)
    tip = style.to_implot3d(n)
    spec = implot3d.Spec()
    spec.line_color = style.HANDLE
    spec.line_weight = 3.0
    implot3d.plot_line("##n", np.array([0.0, tip[0]]), np.array([0.0, tip[1]]),
                       np.array([0.0, tip[2]]), spec)
    implot3d.plot_text("n", *(float(v) * 1.15 for v in tip))
    implot3d.end_plot()


def _slice_plane() -> None:
    """The polar slice's plane (world z = 0), faint, so the two views connect."""
    corners = style.to_implot3d(np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0],
                                 [-1.0, 1.0, 0.0]]))
    spec = implot3d.Spec()
    spec.fill_color = style.TEXT
    spec.fill_alpha = 0.05
    spec.line_color = style.with_alpha(style.TEXT, 0.25)
    implot3d.plot_quad("##slice plane", corners[:, 0].copy(), corners[:, 1].copy(),
                       corners[:, 2].copy(), spec)


def _table(params: Params, state: State, orders: tuple[int, ...], width: float) -> None:
    r = readouts(params, state)
    columns = [("exact", style.EXACT)] + [(f"l{o}", style.L1 if o == 1 else style.L2)
                                          for o in orders]
    header = ["", "max(cos, 0)"] + [f"L{o} ({(o + 1) ** 2} coeff.)" for o in orders]

    def row(title: str, fmt) -> list[str]:
        return [title] + [fmt(key) for key, _ in columns]

    rows = [
        row("energy kept", lambda k: style.percent(r[f"{k}_energy"], 2)),
        row("toward n", lambda k: style.num(r[f"{k}_at_normal"], ".4f")),
        row("lowest", lambda k: f"{style.num(r[f'{k}_min'])} at "
            f"{r[f'{k}_min_angle_deg']:.0f}° from n"),
        row("flux in the tail", lambda k: style.percent(r[f"{k}_negative_flux"], 1)
            + " of the lobe's"),
        row(f"toward ω ({r['probe_angle_deg']:.0f}° from n)",
            lambda k: style.num(r[f"{k}_probe"])),
    ]
    style.readout_table("##cosine numbers", header, rows, width,
                        [None] + [colour for _, colour in columns])
    bands = " + ".join(f"band {b}: {style.percent(r[f'band{b}_energy'], 1)}"
                       for b in range(3))
    rest = 1.0 - sum(r[f"band{b}_energy"] for b in range(3))
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + width)
    imgui.text_colored(style.MUTED, f"Energy of the lobe by band: {bands}; bands 3 and up "
                       f"hold {style.percent(rest, 2)}. Turning n changes none of these.")
    imgui.pop_text_wrap_pos()
