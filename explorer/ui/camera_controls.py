"""Mouse and keyboard camera of the View panel (the math is explorer.ui.camera).

Orbit mode: left drag orbits, middle drag or shift + left drag pans, the wheel zooms.
Fly mode: left drag looks around, W/A/S/D move, Q/E go down/up, shift is faster, the wheel
moves forward. Either mode: F frames the scene, G frames the picked point.
Every move replaces ``Settings.camera``; the pipeline then re-renders the G-buffer and the
gather only (the light's passes do not depend on the camera). Moves are recorded in
``runtime.view.interaction``: while a drag lasts (and a moment after a wheel step or a fly
key) the window renders at a reduced size, and at full size once the camera rests.
"""

from __future__ import annotations

import time

import numpy as np
from imgui_bundle import imgui

from explorer.ui import camera, widgets
from explorer.ui.state import AppState

ORBIT_DEGREES_PER_PIXEL = 0.35
LOOK_DEGREES_PER_PIXEL = 0.2
ZOOM_PER_WHEEL_STEP = 0.9
FLY_SCENES_PER_SECOND = 0.35      # fly speed: this many scene diagonals per second
FLY_FAST = 4.0                    # with shift held
FLY_WHEEL_SCENES = 0.05           # one wheel step moves this many scene diagonals


def current_camera(state: AppState) -> tuple | None:
    value = state.settings.camera or state.runtime.scene_facts.camera_default
    return None if value is None else camera.as_pair(value)


def _frame_geometry(state: AppState) -> tuple | None:
    """(fov_y, aspect, bounds_min, bounds_max) of the last frame, or None before one."""
    result = state.runtime.frame.result
    if result is None or result.camera is None:
        return None
    height, width = result.image_size
    lo, hi = result.scene_bounds
    return result.camera.fov_y_degrees, width / height, lo, hi


def frame_scene(state: AppState) -> bool:
    current, geometry = current_camera(state), _frame_geometry(state)
    if current is None or geometry is None:
        return False
    fov, aspect, lo, hi = geometry
    return state.update(camera=camera.frame_box(*current, lo, hi, fov, aspect))


def picked_point(state: AppState):
    """World position of the picked surface point or cell centre, or None."""
    return state.overlays.picked_point


def frame_picked(state: AppState) -> bool:
    """Turn the camera to the picked point and move to a few cells from it."""
    current, point = current_camera(state), picked_point(state)
    if current is None or point is None:
        return False
    result = state.runtime.frame.result
    distance = min(float(np.linalg.norm(np.subtract(*current))),
                   12.0 * result.grid_spec.cell_size)
    return state.update(camera=camera.frame_point(*current, point, distance))


def toolbar(state: AppState, shown=("frame", "frame-picked", "fly")) -> None:
    """Frame buttons and the fly switch, on the View panel's toolbar line (those named in
    ``shown``); each wraps to the next line when the line is full."""
    if "frame" in shown:
        if imgui.button("Frame (F)"):
            frame_scene(state)
        if imgui.is_item_hovered():
            imgui.set_tooltip("look at the whole scene from the current direction")
    if "frame-picked" in shown:
        widgets.same_line_if_fits("Frame picked (G)")
        imgui.begin_disabled(state.overlays.picked_kind == "none")
        if imgui.button("Frame picked (G)"):
            frame_picked(state)
        imgui.end_disabled()
    if "fly" in shown:
        widgets.same_line_if_fits("Fly", checkbox=True)
        _, state.overlays.fly = imgui.checkbox("Fly", state.overlays.fly)
        if imgui.is_item_hovered():
            imgui.set_tooltip("fly mode: drag to look around, W/A/S/D to move, Q/E down/up, "
                              "shift faster")


def hint(state: AppState) -> str:
    if state.overlays.fly:
        return "drag: look   W/A/S/D/Q/E: fly   wheel: forward   F: frame   click: pick"
    return "drag: orbit   shift/middle drag: pan   wheel: zoom   F: frame   click: pick"


def handle_mouse(state: AppState, hovered: bool, active: bool, view_height: float) -> None:
    """Camera moves from the mouse and keys while the view image is hovered or dragged.
    ``view_height``: the image's height on screen (pan speed)."""
    interaction = state.runtime.view.interaction
    interaction.held = False
    current = current_camera(state)
    if current is None:
        return
    io = imgui.get_io()
    interaction.held = ((active and imgui.is_mouse_dragging(0))
                        or (hovered and imgui.is_mouse_dragging(2)))
    if hovered and not io.want_text_input:
        if imgui.is_key_pressed(imgui.Key.f, False):
            frame_scene(state)
            return
        if imgui.is_key_pressed(imgui.Key.g, False):
            frame_picked(state)
            return
    eye, target = current
    fly = state.overlays.fly
    new = None
    shift = io.key_shift
    if active and imgui.is_mouse_dragging(0):
        delta = imgui.get_mouse_drag_delta(0)
        imgui.reset_mouse_drag_delta(0)
        if fly:
            new = camera.fly_look(eye, target, -delta.x * LOOK_DEGREES_PER_PIXEL,
                                  -delta.y * LOOK_DEGREES_PER_PIXEL)
        elif shift:
            new = _pan(state, eye, target, delta, view_height)
        else:
            new = camera.orbit(eye, target, -delta.x * ORBIT_DEGREES_PER_PIXEL,
                               delta.y * ORBIT_DEGREES_PER_PIXEL)
    elif hovered and imgui.is_mouse_dragging(2):
        delta = imgui.get_mouse_drag_delta(2)
        imgui.reset_mouse_drag_delta(2)
        new = _pan(state, eye, target, delta, view_height)
    elif hovered and io.mouse_wheel != 0.0 and not io.key_ctrl:
        if fly:
            new = camera.fly_move(eye, target, io.mouse_wheel * FLY_WHEEL_SCENES
                                  * _scene_size(state), 0.0, 0.0)
        else:
            new = camera.dolly(eye, target, ZOOM_PER_WHEEL_STEP ** io.mouse_wheel)
    elif fly and hovered:
        new = _fly_keys(state, eye, target, io)
        if new is not None:
            state.runtime.request_redraw()      # held keys send no events: keep drawing
    if new is not None:
        interaction.moved_at = time.monotonic()
        state.update(camera=new)


def _pan(state: AppState, eye, target, delta, view_height: float):
    geometry = _frame_geometry(state)
    fov = geometry[0] if geometry else 45.0
    return camera.pan(eye, target, delta.x, delta.y, view_height, fov)


def _scene_size(state: AppState) -> float:
    geometry = _frame_geometry(state)
    if geometry is None:
        return 1.0
    return float(np.linalg.norm(np.subtract(geometry[3], geometry[2])))


def _fly_keys(state: AppState, eye, target, io):
    keys = {imgui.Key.w: (1, 0, 0), imgui.Key.s: (-1, 0, 0), imgui.Key.d: (0, 1, 0),
            imgui.Key.a: (0, -1, 0), imgui.Key.e: (0, 0, 1), imgui.Key.q: (0, 0, -1)}
    move = np.zeros(3)
    for key, direction in keys.items():
        if imgui.is_key_down(key):
            move += direction
    if not move.any():
        return None
    step = FLY_SCENES_PER_SECOND * _scene_size(state) * io.delta_time
    step *= FLY_FAST if io.key_shift else 1.0
    return camera.fly_move(eye, target, *(move * step))
