"""A cell, its neighbour's five faces, their projection on the unit sphere and the
30-face tiling.

Propagation sends light from a cell to each of its six neighbours through five faces of
the neighbour: the far ("front") face and four side faces (docs/MODEL.md "Propagation").
The left view shows the two cells and the five faces seen from the source cell's centre;
the right one their projections on the unit sphere, and with the tiling on all 30 faces of
the six neighbours, which cover the sphere exactly once. Hover a face (in the 3D view or
the table) to read its solid angle: the exact values come from explorer/lpv/constants.py
(derivations/solid_angles.py) and a quadrature of cos θ/r² over the face checks each one.
Cells have side 2 with the source centred at the origin, as in the derivation.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache, lru_cache

import numpy as np
from imgui_bundle import imgui, implot3d

from explorer.figure_params import DIRECTIONS
from explorer.figure_params import CellFacesParams as Params
from explorer.lpv import constants as K
from explorer.ui.figures import style

_AXIS_NAMES = "xyz"
_QUADRATURE_NODES = 24
_PATCH_STEPS = 10
_FRONT_COLOUR = imgui.ImVec4(0.33, 0.62, 0.98, 1.0)
_SIDE_COLOUR = imgui.ImVec4(0.35, 0.80, 0.72, 1.0)
# One hue per neighbour direction in the tiling (+x, −x, +y, −y, +z, −z).
_NEIGHBOUR_COLOURS = tuple(imgui.ImVec4(*rgb, 1.0) for rgb in (
    (0.95, 0.45, 0.40), (0.95, 0.70, 0.35), (0.45, 0.80, 0.45),
    (0.35, 0.75, 0.85), (0.45, 0.55, 0.98), (0.78, 0.50, 0.90)))


@dataclass
class State:
    highlighted: int          # index into neighbour_faces(), −1 for none

    @classmethod
    def from_params(cls, params: Params) -> State:
        return cls({"none": -1, "front": 0, "side": 1}[params.highlight])


# ----------------------------------------------------------------------------- geometry


@dataclass(frozen=True)
class Face:
    """An axis-aligned square face: the plane ``coordinate[axis] = plane``, spanning
    ``low[i]..high[i]`` along the two other axes (in increasing axis order)."""

    name: str
    axis: int
    plane: float
    low: tuple[float, float]
    high: tuple[float, float]
    is_front: bool

    @property
    def others(self) -> tuple[int, int]:
        return tuple(k for k in range(3) if k != self.axis)

    def point(self, u: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Points of the face at fractions ``u, v`` ∈ [0, 1] along its two spans."""
        u, v = np.broadcast_arrays(np.asarray(u, np.float64), np.asarray(v, np.float64))
        out = np.empty(u.shape + (3,))
        a, b = self.others
        out[..., self.axis] = self.plane
        out[..., a] = self.low[0] + u * (self.high[0] - self.low[0])
        out[..., b] = self.low[1] + v * (self.high[1] - self.low[1])
        return out

    def corners(self) -> np.ndarray:
        return self.point(np.array([0.0, 1.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0, 1.0]))


def _axis_sign(direction: str) -> tuple[int, float]:
    return _AXIS_NAMES.index(direction[1]), (1.0 if direction[0] == "+" else -1.0)


def neighbour_faces(direction: str) -> list[Face]:
    """The five faces of the neighbour along ``direction`` that light from the source
    cell's centre passes out through: front first, then the four sides."""
    axis, sign = _axis_sign(direction)
    others = [k for k in range(3) if k != axis]
    span = (min(sign, 3.0 * sign), max(sign, 3.0 * sign))   # the neighbour along its axis
    faces = [Face("front", axis, 3.0 * sign, (-1.0, -1.0), (1.0, 1.0), True)]
    for side_axis in others:
        for side_sign in (1.0, -1.0):
            spans = [span if k == axis else (-1.0, 1.0) for k in range(3) if k != side_axis]
            name = f"side {'+' if side_sign > 0 else '−'}{_AXIS_NAMES[side_axis]}"
            faces.append(Face(name, side_axis, side_sign, (spans[0][0], spans[1][0]),
                              (spans[0][1], spans[1][1]), False))
    return faces


@cache
def face_solid_angle_numeric(face: Face) -> float:
    """∫ cos θ / r² dA over the face seen from the origin (Gauss–Legendre; the integrand
    |plane| / r³ is smooth on the face, so 24² nodes reach double precision). Kept per
    face (thirty in all): the figure's table reads all of them every frame, 16 ms of
    quadrature a frame otherwise."""
    nodes, weights = np.polynomial.legendre.leggauss(_QUADRATURE_NODES)
    t = (nodes + 1.0) / 2.0
    u, v = np.meshgrid(t, t, indexing="ij")
    r = np.linalg.norm(face.point(u, v), axis=-1)
    area = (face.high[0] - face.low[0]) * (face.high[1] - face.low[1])
    w = np.outer(weights, weights) / 4.0 * area
    return float(np.sum(w * abs(face.plane) / r**3))


def face_solid_angle_exact(face: Face) -> float:
    """The derived constant for this kind of face (explorer/lpv/constants.py)."""
    return K.FRONT_FACE_SOLID_ANGLE if face.is_front else K.SIDE_FACE_SOLID_ANGLE


def readouts(params: Params, state: State, context=None) -> dict[str, float]:
    faces = neighbour_faces(params.direction)
    numeric = [face_solid_angle_numeric(face) for face in faces]
    every = [face_solid_angle_numeric(f) for d in DIRECTIONS for f in neighbour_faces(d)]
    values = {
        "front": K.FRONT_FACE_SOLID_ANGLE, "side": K.SIDE_FACE_SOLID_ANGLE,
        "front_numeric": numeric[0], "side_numeric": numeric[1],
        "five_faces": K.FRONT_FACE_SOLID_ANGLE + 4.0 * K.SIDE_FACE_SOLID_ANGLE,
        "five_faces_numeric": sum(numeric),
        "cube_face": K.CUBE_FACE_SOLID_ANGLE,
        "thirty_faces": 6.0 * (K.FRONT_FACE_SOLID_ANGLE + 4.0 * K.SIDE_FACE_SOLID_ANGLE),
        "thirty_faces_numeric": sum(every), "sphere": K.FOUR_PI,
        "published_side": K.PUBLISHED_SIDE_FACE_SOLID_ANGLE,
    }
    if 0 <= state.highlighted < len(faces):
        face = faces[state.highlighted]
        values["highlighted"] = face_solid_angle_exact(face)
        values["highlighted_numeric"] = numeric[state.highlighted]
    return values


# ----------------------------------------------------------------------------- drawing


def draw(params: Params, state: State, width: float, context) -> None:
    drawers = {"cells": lambda w: _cells(params, state, w),
               "sphere": lambda w: _sphere(params, state, w)}
    style.views(width, list(drawers.values()) if params.view == "both"
                else [drawers[params.view]])
    _table(params, state, width)


def _colour(face: Face, index: int, state: State) -> imgui.ImVec4:
    if index == state.highlighted:
        return style.HANDLE
    return _FRONT_COLOUR if face.is_front else _SIDE_COLOUR


def _begin_3d(title: str, width: float, centre: np.ndarray, half: float) -> bool:
    imgui.text_colored(style.MUTED, title)
    if not implot3d.begin_plot(f"##{title}", style.square(width),
                               implot3d.Flags_.no_menus | implot3d.Flags_.no_title):
        return False
    flags = implot3d.AxisFlags_.lock | implot3d.AxisFlags_.no_tick_labels
    implot3d.setup_axes("x", "z", "y", flags, flags, flags)
    c = style.to_implot3d(centre)
    implot3d.setup_axes_limits(c[0] - half, c[0] + half, c[1] - half, c[1] + half,
                               c[2] - half, c[2] + half, implot3d.Cond_.always)
    implot3d.setup_box_rotation(20.0, -35.0, False, implot3d.Cond_.once)
    implot3d.setup_legend(implot3d.Location_.north_west)
    return True


def _quad_spec(colour: imgui.ImVec4, alpha: float, line_alpha: float = 0.9) -> implot3d.Spec:
    spec = implot3d.Spec()
    spec.fill_color = colour
    spec.fill_alpha = alpha
    spec.line_color = style.with_alpha(colour, line_alpha)
    spec.line_weight = 1.5
    return spec


def _plot_quads(label: str, corners: np.ndarray, spec: implot3d.Spec) -> None:
    """Quads (k, 4, 3) in world coordinates."""
    p = style.to_implot3d(np.asarray(corners).reshape(-1, 3))
    implot3d.plot_quad(label, p[:, 0].copy(), p[:, 1].copy(), p[:, 2].copy(), spec)


def _cube_edges(centre: np.ndarray) -> np.ndarray:
    """(12, 2, 3) edges of the side-2 cube around ``centre``."""
    edges = []
    for axis in range(3):
        a, b = [k for k in range(3) if k != axis]
        for sa in (-1.0, 1.0):
            for sb in (-1.0, 1.0):
                p, q = np.zeros(3), np.zeros(3)
                p[axis], q[axis] = -1.0, 1.0
                p[a] = q[a] = sa
                p[b] = q[b] = sb
                edges.append((centre + p, centre + q))
    return np.array(edges)


def _plot_segments(label: str, segments: np.ndarray, colour: imgui.ImVec4, weight: float
                   ) -> None:
    spec = implot3d.Spec()
    spec.line_color = colour
    spec.line_weight = weight
    spec.flags = implot3d.LineFlags_.segments
    p = style.to_implot3d(np.asarray(segments).reshape(-1, 3))
    implot3d.plot_line(label, p[:, 0].copy(), p[:, 1].copy(), p[:, 2].copy(), spec)


def _cells(params: Params, state: State, width: float) -> None:
    faces = neighbour_faces(params.direction)
    axis, sign = _axis_sign(params.direction)
    neighbour = np.zeros(3)
    neighbour[axis] = 2.0 * sign
    if not _begin_3d("The source cell, its neighbour and the five faces (hover one)", width,
                     neighbour / 2.0, 2.3):
        return
    _plot_segments("source cell", _cube_edges(np.zeros(3)), style.TEXT, 1.5)
    _plot_segments("##neighbour", _cube_edges(neighbour), style.with_alpha(style.TEXT, 0.35),
                   1.0)
    for index, face in enumerate(faces):
        colour = _FRONT_COLOUR if face.is_front else _SIDE_COLOUR
        label = ("front face" if face.is_front else "side faces") if index < 2 else \
            f"##{face.name}"
        _plot_quads(label, face.corners()[None], _quad_spec(colour, 0.28))
    if 0 <= state.highlighted < len(faces):
        face = faces[state.highlighted]
        _plot_quads(face.name, face.corners()[None], _quad_spec(style.HANDLE, 0.55))
        # The pyramid of directions from the source centre through the highlighted face.
        corners = faces[state.highlighted].corners()
        rays = np.stack([np.zeros_like(corners), corners], 1)
        _plot_segments("##rays", rays, style.with_alpha(style.HANDLE, 0.6), 1.0)
    implot3d.plot_text("source", 0.0, 0.0, 0.0)
    _hover_face(faces, state)
    implot3d.end_plot()


def _hover_face(faces: list[Face], state: State) -> None:
    """Highlight the face under the mouse (the nearest along the view ray)."""
    pos, size = implot3d.get_plot_rect_pos(), implot3d.get_plot_rect_size()
    mouse = imgui.get_mouse_pos()
    if not (pos.x <= mouse.x <= pos.x + size.x and pos.y <= mouse.y <= pos.y + size.y) \
            or not imgui.is_window_hovered():
        return
    ray = implot3d.pixels_to_plot_ray(mouse)
    origin = style.from_implot3d(np.array([ray.origin.x, ray.origin.y, ray.origin.z]))
    direction = style.from_implot3d(np.array([ray.direction.x, ray.direction.y, ray.direction.z]))
    best, best_t = -1, np.inf
    for index, face in enumerate(faces):
        if abs(direction[face.axis]) < 1e-12:
            continue
        t = (face.plane - origin[face.axis]) / direction[face.axis]
        hit = origin + t * direction
        a, b = face.others
        inside = (face.low[0] <= hit[a] <= face.high[0]) and (face.low[1] <= hit[b] <=
                                                               face.high[1])
        if inside and t < best_t:
            best, best_t = index, t
    if best >= 0:
        state.highlighted = best


@lru_cache(maxsize=64)
def _patch(direction: str, index: int) -> tuple[np.ndarray, np.ndarray]:
    """The face's projection on the unit sphere: quads (k, 4, 3) and its outline (m, 3)."""
    face = neighbour_faces(direction)[index]
    t = np.linspace(0.0, 1.0, _PATCH_STEPS + 1)
    u, v = np.meshgrid(t, t, indexing="ij")
    points = face.point(u, v)
    points /= np.linalg.norm(points, axis=-1, keepdims=True)
    quads = np.stack([points[:-1, :-1], points[1:, :-1], points[1:, 1:], points[:-1, 1:]], 2)
    edge = np.concatenate([face.point(t, 0 * t), face.point(0 * t + 1, t),
                           face.point(t[::-1], 0 * t + 1), face.point(0 * t, t[::-1])])
    edge /= np.linalg.norm(edge, axis=-1, keepdims=True)
    return quads.reshape(-1, 4, 3), edge


def _sphere(params: Params, state: State, width: float) -> None:
    title = ("The 30 faces of the six neighbours on the unit sphere" if params.tiling
             else "The five faces projected on the unit sphere")
    if not _begin_3d(title, width, np.zeros(3), 1.05):
        return
    shown = DIRECTIONS if params.tiling else (params.direction,)
    for direction in shown:
        hue = _NEIGHBOUR_COLOURS[DIRECTIONS.index(direction)]
        if params.tiling:
            implot3d.plot_dummy("neighbour " + direction.replace("-", "−"),
                                _quad_spec(hue, 0.75))
        for index, face in enumerate(neighbour_faces(direction)):
            quads, edge = _patch(direction, index)
            mine = direction == params.direction
            if mine and index == state.highlighted:
                colour, alpha = style.HANDLE, 0.85
            elif params.tiling:
                colour, alpha = hue, (0.75 if face.is_front else 0.45)
            else:
                colour, alpha = _colour(face, index, state), 0.5
            spec = _quad_spec(colour, alpha, 0.0)
            spec.flags = implot3d.QuadFlags_.no_lines
            _plot_quads(f"##{direction}{index}", quads, spec)
            outline = style.to_implot3d(edge)
            line = implot3d.Spec()
            line.line_color = style.with_alpha(style.TEXT, 0.8 if mine else 0.35)
            line.line_weight = 1.5 if mine else 1.0
            implot3d.plot_line(f"##edge{direction}{index}", outline[:, 0].copy(),
                               outline[:, 1].copy(), outline[:, 2].copy(), line)
    implot3d.end_plot()


def _solid_angle_cells(exact: float, numeric: float) -> None:
    """The three number columns of a table row."""
    for column, text in enumerate((f"{exact:.6f} sr", f"{numeric:.6f} sr",
                                   style.percent(exact / K.FOUR_PI, 2)), start=1):
        imgui.table_set_column_index(column)
        imgui.text(text)


def _table(params: Params, state: State, width: float) -> None:
    r = readouts(params, state)
    faces = neighbour_faces(params.direction)
    flags = (imgui.TableFlags_.borders_inner_h | imgui.TableFlags_.sizing_stretch_same)
    if not imgui.begin_table("##faces", 4, flags, imgui.ImVec2(width, 0)):
        return
    neighbour = params.direction.replace("-", "−")
    for name in (f"face of the {neighbour} neighbour", "solid angle (derived)",
                 "quadrature ∫cos θ/r² dA", "share of the sphere"):
        imgui.table_setup_column(name)
    imgui.table_headers_row()
    for index, face in enumerate(faces):
        imgui.table_next_row()
        imgui.table_set_column_index(0)
        colour = _colour(face, index, state)
        selected = index == state.highlighted
        imgui.push_style_color(imgui.Col_.text, colour)
        clicked, _ = imgui.selectable(f"{face.name}##row{index}", selected,
                                      imgui.SelectableFlags_.span_all_columns)
        imgui.pop_style_color()
        if clicked or imgui.is_item_hovered():
            state.highlighted = index
        _solid_angle_cells(face_solid_angle_exact(face), face_solid_angle_numeric(face))
    for title, exact, numeric in (
            ("the five together", r["five_faces"], r["five_faces_numeric"]),
            ("all 30 faces", r["thirty_faces"], r["thirty_faces_numeric"])):
        imgui.table_next_row()
        imgui.table_set_column_index(0)
        imgui.text_colored(style.MUTED, title)
        _solid_angle_cells(exact, numeric)
    imgui.end_table()
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + width)
    imgui.text_colored(style.MUTED, f"The five faces of one neighbour cover what a face of "
                       f"the source cell covers seen from its centre ({r['cube_face']:.6f} sr), "
                       f"so the 30 faces cover the whole sphere, 4π = {r['sphere']:.6f} sr, "
                       f"exactly once. The DX11 article prints the side face as "
                       f"{r['published_side']:.10f} sr; the derivation gives "
                       f"{r['side']:.10f} sr.")
    imgui.pop_text_wrap_pos()
