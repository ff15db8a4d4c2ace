"""Lights & objects panel: which of the scene's lights shine (``Settings.lights``), the
object the view's gizmo moves and its transform (``Settings.object_transforms``), and the
play controls of the scene's animation paths and of its fly-through
(explorer/ui/animation.py, docs/MODEL.md "Several lights", "Moving objects and temporal
stability")."""

from __future__ import annotations

from imgui_bundle import imgui

from explorer.scene.animation import camera_at, path_names, pose_changes
from explorer.scene.objects import check_transform_values
from explorer.ui import widgets
from explorer.ui.animation import GIZMO_OPERATIONS, animation_of, scene_of
from explorer.ui.gizmo import object_transform
from explorer.ui.state import AppState


def gui_lights(state: AppState) -> None:
    scene = scene_of(state)
    if scene is None:
        imgui.text_disabled("the scene is loading")
        return
    _lights(state, scene)
    _objects(state, scene)
    _animation(state, scene)
    if scene.camera_path is not None:
        _fly_through(state, scene)


# --- lights ---------------------------------------------------------------------------------

def describe(light) -> str:
    """One line about a light: its kind, cone and flux."""
    if light.kind == "point":
        kind = "point light, 6 RSM faces"
    elif light.kind == "directional":
        kind = "directional (sun)"
    elif light.cone_degrees is None:
        kind = "spot, 90° frustum"
    else:
        kind = f"spot, cone {light.cone_degrees[0]:g}°/{light.cone_degrees[1]:g}°"
    return f"{kind}, {light.flux:.3g} W"


def shining(state: AppState, scene) -> tuple[str, ...]:
    """The names of the lights that shine now, primary first."""
    return state.settings.lights or scene.lights_on or scene.light_names


def set_lights(state: AppState, scene, names: list[str]) -> bool:
    """Let ``names`` shine (the first is the primary light). When the primary light
    changes, its placement and flux overrides go (they belonged to the other light) and
    the Scene panel's light controls start from the new primary's own."""
    if not names:
        state.notify("at least one light must shine", "warning")
        return False
    changes = {"lights": tuple(names)}
    primary = scene.with_lights(names).light
    if primary.name != shining(state, scene)[0]:
        changes.update(light=None, light_flux=None, spot_cone_degrees=None)
    if not state.update(**changes):
        return False
    rt = state.runtime
    rt.scene_facts.light_default = (tuple(primary.position), tuple(primary.target))
    rt.scene_facts.light_flux_default = primary.flux
    rt.scene_facts.light_cone_default = getattr(primary, "cone_degrees", None)
    rt.scene_facts.light_is_spot = primary.kind == "spot"
    return True


def _lights(state: AppState, scene) -> None:
    imgui.separator_text("Lights")
    on = shining(state, scene)
    for light in scene.rig:
        imgui.push_id(light.name)
        changed, lit = imgui.checkbox("##on", light.name in on)
        imgui.same_line()
        imgui.color_button("##colour", imgui.ImVec4(*light.colour, 1.0),
                           imgui.ColorEditFlags_.no_tooltip)
        imgui.same_line()
        imgui.text(light.name + (" (primary)" if on and light.name == on[0] else ""))
        imgui.same_line()
        widgets.dim_text_wrapped(describe(light))
        imgui.pop_id()
        if changed:
            names = [n for n in on if n != light.name] + ([light.name] if lit else [])
            set_lights(state, scene, names)
    if len(on) > 1 and imgui.begin_combo("Primary light", on[0]):
        for name in on:
            if imgui.selectable(name, name == on[0])[0] and name != on[0]:
                set_lights(state, scene, [name] + [n for n in on if n != name])
        imgui.end_combo()
    result = state.runtime.frame.result
    names = () if result is None else result.light_names
    if names:
        widgets.dim_text_wrapped(
            f"{len(names)} light(s), {len(result.vpl_sets)} RSM view(s) in "
            f"one grid; the light controls of the Scene panel move the primary light")


# --- objects --------------------------------------------------------------------------------

def _objects(state: AppState, scene) -> None:
    imgui.separator_text("Objects")
    if not scene.objects:
        imgui.text_disabled("this scene has no object that can move")
        return
    animation = animation_of(state)
    if imgui.radio_button("none", animation.selected is None):
        animation.selected = None
    for obj in scene.objects:
        imgui.same_line()
        if imgui.get_content_region_avail().x < imgui.calc_text_size(obj.name).x + 40:
            imgui.new_line()
        if imgui.radio_button(obj.name, animation.selected == obj.name):
            animation.selected = obj.name
    if animation.selected is None:
        widgets.dim_text_wrapped("select an object to move it with the gizmo in the view")
        return
    for operation in GIZMO_OPERATIONS:
        if imgui.radio_button(operation.capitalize(), animation.operation == operation):
            animation.operation = operation
        imgui.same_line()
    imgui.new_line()
    _transform_fields(state, animation.selected)
    if imgui.button("Reset object"):
        moved = dict(state.settings.object_transforms)
        moved.pop(animation.selected, None)
        state.update(object_transforms=moved)
    imgui.same_line()
    if imgui.button("Reset all objects"):
        state.update(object_transforms=())
    widgets.dim_text_wrapped("drag the gizmo's handles in the view: the RSM, the G-buffer and "
                             "every stage after them run again")


def _transform_fields(state: AppState, name: str) -> None:
    values = list(object_transform(state.settings, name).values())
    changed_t, values[0:3] = imgui.drag_float3("Move [m]", values[0:3], 0.005, 0.0, 0.0,
                                               "%.3f")
    changed_r, values[3:6] = imgui.drag_float3("Turn [°]", values[3:6], 0.5, 0.0, 0.0,
                                               "%.1f")
    changed_s, values[6:9] = imgui.drag_float3("Scale", values[6:9], 0.005, 0.01, 100.0,
                                               "%.3f")
    if changed_t or changed_r or changed_s:
        checked = check_transform_values(values)
        if checked is not None:
            moved = dict(state.settings.object_transforms)
            moved[name] = checked
            state.update(object_transforms=moved)


# --- animation ------------------------------------------------------------------------------

def _animation(state: AppState, scene) -> None:
    imgui.separator_text("Animation")
    names = path_names(scene)
    if not names:
        imgui.text_disabled("this scene has no animation path")
        return
    animation = animation_of(state)
    if imgui.button("Pause" if animation.playing else "Play"):
        animation.playing = not animation.playing
    imgui.same_line()
    imgui.set_next_item_width(-80)
    changed, seconds = imgui.slider_float("Time [s]", animation.seconds % _longest(scene),
                                          0.0, _longest(scene), "%.2f")
    if changed:                           # scrubbing puts the paths there, playing or not
        animation.seconds = seconds
        playing = tuple(n for n in names if animation.paths is None or n in animation.paths)
        if playing:
            state.update(**pose_changes(scene, seconds, playing,
                                        state.settings.object_transforms))
    _, animation.speed = imgui.slider_float("Speed", animation.speed, 0.1, 4.0, "%.2f×",
                                            imgui.SliderFlags_.logarithmic)
    for index, name in enumerate(names):
        if index:
            imgui.same_line()
        plays = animation.paths is None or name in animation.paths
        changed, plays = imgui.checkbox(name, plays)
        if changed:
            current = names if animation.paths is None else animation.paths
            animation.paths = tuple(n for n in names if (n in current and n != name)
                                    or (n == name and plays))
    widgets.dim_text_wrapped("the light path moves the primary light; an animated frame is "
                             "an ordinary one: only what moved runs again")


def _longest(scene) -> float:
    """The longest period of the scene's paths (the time slider's range)."""
    periods = [path.period for _, path in scene.object_paths]
    if scene.light_path is not None:
        periods.append(scene.light_path.period)
    return max(periods, default=1.0)


def _fly_through(state: AppState, scene) -> None:
    imgui.separator_text("Fly-through")
    animation = animation_of(state)
    if imgui.button("Pause##fly" if animation.flying else "Play##fly"):
        animation.flying = not animation.flying
    imgui.same_line()
    imgui.set_next_item_width(-80)
    changed, where = imgui.slider_float("Position", animation.fly_parameter, 0.0, 1.0,
                                        "%.3f")
    if changed:
        animation.fly_parameter = where
        state.update(camera=camera_at(scene, where))
    loops = animation.fly_speed * 60.0
    changed, loops = imgui.slider_float("Loops per minute", loops, 0.1, 10.0, "%.2f",
                                        imgui.SliderFlags_.logarithmic)
    if changed:
        animation.fly_speed = loops / 60.0
    widgets.dim_text_wrapped("the camera follows the scene's camera path; with cascades they "
                             "follow it too (lpv-explorer render --fly-through T renders one "
                             "position)")

