"""A lesson step's marks (explorer/lessons/marks.py) drawn over the 3D view: a label in a
box, an arrow from it to the mark's world point, a dot there. Drawn with the View panel's
draw list, so window screenshots and ``lessons --export`` show them too.

:func:`placements` is the geometry (pure numpy, tested without a window): where each mark
lands on the image and where its label goes, off the surface along the mark's normal as
the camera sees it (up the screen when the mark has no normal)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LABEL_DISTANCE = 64.0
"""Screen units from a mark's point to its label's nearest corner."""


@dataclass(frozen=True)
class Placement:
    label: str
    point: tuple[float, float]
    """The mark's point on screen."""
    anchor: tuple[float, float]
    """Where the arrow starts: the label box's side facing the point."""
    box: tuple[float, float, float, float]
    """The label box (x0, y0, x1, y1) on screen."""
    visible: bool
    """False when a surface hides the point (it is drawn faded)."""


def _clip(result, world: np.ndarray) -> np.ndarray:
    from explorer.ui.overlays.picking import view_projection

    return np.append(world, 1.0) @ view_projection(result).T


VISIBLE_SLACK = 0.05
"""Metres a surface may lie in front of a mark before it hides it (a mark sits a little
off the surface it labels)."""


def _visible(result, at: np.ndarray, x: int, y: int) -> bool:
    """Whether the surface seen at pixel (x, y) leaves ``at`` in view: no surface there,
    or one no nearer to the camera than the mark (less :data:`VISIBLE_SLACK`)."""
    position = result.gbuffer_position[y, x]
    if position[3] < 0.5:
        return True
    eye = np.asarray(result.camera.eye, np.float64)
    return bool(np.linalg.norm(position[:3] - eye) >= np.linalg.norm(at - eye) - VISIBLE_SLACK)


def placements(result, marks, origin: tuple[float, float], end: tuple[float, float],
               text_size) -> list[Placement]:
    """Where ``marks`` go over the image of ``result`` drawn from ``origin`` to ``end``
    (screen units); ``text_size(label) -> (w, h)``. Marks behind the camera or off the
    image are left out."""
    from explorer.ui.overlays.picking import project

    height, width = result.image_size
    sx = (end[0] - origin[0]) / width
    sy = (end[1] - origin[1]) / height
    out = []
    for mark in marks:
        if not mark.label:
            continue            # a mark that only measures
        at = np.asarray(mark.at, np.float64)
        if _clip(result, at)[3] <= 0.0:
            continue
        px, py = project(result, at)
        if not (0.0 <= px < width and 0.0 <= py < height):
            continue
        point = np.array([origin[0] + px * sx, origin[1] + py * sy])
        direction = np.array([0.0, -1.0])
        if mark.normal is not None:
            ahead = at + 0.3 * np.asarray(mark.normal, np.float64)
            if _clip(result, ahead)[3] > 0.0:
                qx, qy = project(result, ahead)
                d = np.array([(qx - px) * sx, (qy - py) * sy])
                if np.linalg.norm(d) > 1e-3:
                    direction = d / np.linalg.norm(d)
        # lean the label upwards so that it rarely covers what it points at
        direction = direction + np.array([0.0, -0.6])
        direction /= np.linalg.norm(direction)
        w, h = text_size(mark.label)
        w, h = w + 10.0, h + 6.0
        centre = point + direction * (LABEL_DISTANCE + 0.5 * max(w * abs(direction[0]),
                                                                 h * abs(direction[1])))
        x0 = float(np.clip(centre[0] - w / 2, origin[0] + 2, max(end[0] - w - 2, origin[0])))
        y0 = float(np.clip(centre[1] - h / 2, origin[1] + 2, max(end[1] - h - 2, origin[1])))
        box = (x0, y0, x0 + w, y0 + h)
        anchor = (float(np.clip(point[0], box[0], box[2])),
                  float(np.clip(point[1], box[1], box[3])))
        visible = _visible(result, at, int(px), int(py))
        out.append(Placement(mark.label, (float(point[0]), float(point[1])), anchor, box,
                             visible))
    return out


def draw(draw_list, placed: list[Placement]) -> None:
    """The marks on ``draw_list`` (imgui): a dark label box, a light arrow, a dot."""
    from imgui_bundle import imgui

    for item in placed:
        alpha = 1.0 if item.visible else 0.55
        ink = imgui.get_color_u32(imgui.ImVec4(1.0, 0.92, 0.45, alpha))
        backdrop = imgui.get_color_u32(imgui.ImVec4(0.0, 0.0, 0.0, 0.7 * alpha))
        x0, y0, x1, y1 = item.box
        tip = np.array(item.point)
        start = np.array(item.anchor)
        shaft = tip - start
        length = float(np.linalg.norm(shaft))
        if length > 8.0:
            unit = shaft / length
            side = np.array([-unit[1], unit[0]])
            base = tip - unit * 9.0
            draw_list.add_line(tuple(start), tuple(base), ink, 2.0)
            draw_list.add_triangle_filled(tuple(tip), tuple(base + side * 4.5),
                                          tuple(base - side * 4.5), ink)
        draw_list.add_circle(tuple(tip), 4.0, ink, 12, 1.5)
        draw_list.add_rect_filled((x0, y0), (x1, y1), backdrop, 3.0)
        draw_list.add_rect((x0, y0), (x1, y1), ink, 3.0)
        draw_list.add_text((x0 + 5.0, y0 + 3.0), ink, item.label)
