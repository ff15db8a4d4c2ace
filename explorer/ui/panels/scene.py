"""Scene panel: scene or mesh file, camera, light, and every setting that declares a
widget in the settings schema, grouped by the spec's ``group``.

The generic controls come from the specs (explorer/ui/setting_widgets.py); the controls
with logic of their own stay here: the scene and mesh, the light's angles and flux, the
spot cone's two angles (one field, defaulting to the scene's cone), the geometry volume ↔
bounces coupling and the fixed resolution.
"""

from __future__ import annotations

from collections.abc import Callable

from imgui_bundle import imgui

from explorer.lpv.settings import Settings
from explorer.scene.builtin import BUILTIN_SCENES
from explorer.schema import SettingError, specs
from explorer.ui import camera, widgets
from explorer.ui.setting_widgets import draw_setting, label_of, tooltip_of
from explorer.ui.state import AppState

GROUPS = ("Light and shadows", "Light propagation volume", "Leak reduction and bounces",
          "Fog and glossy", "Cascades", "Display", "Output")
"""The panel's sections, top to bottom (each spec names the one it belongs in)."""
OWNERS = (Settings, AppState)
"""The classes whose declared fields the panel edits: configuration A and the view."""


def gui_scene(state: AppState) -> None:
    _scene_choice(state)
    _camera_and_light(state)
    for group in GROUPS:
        imgui.separator_text(group)
        for owner, name in controls(group):
            if not _SHOWN_WHEN.get(name, lambda s: True)(state):
                continue
            if name in _CUSTOM:
                _CUSTOM[name](state)
            else:
                _generic(state, owner, name)
        if group in _AFTER:
            _AFTER[group](state)


def controls(group: str) -> list[tuple[type, str]]:
    """(owner class, field) of every declared field in ``group``, in declaration order:
    those with a widget and those with a custom control."""
    return [(owner, name) for owner in OWNERS for name, spec in specs(owner).items()
            if spec.group == group and (spec.widget or name in _CUSTOM)]


def _generic(state: AppState, owner: type, name: str) -> None:
    spec = specs(owner)[name]
    target = state.settings if owner is Settings else state
    widgets.fit_next_item(label_of(spec, name))
    changed, value = draw_setting(name, spec, getattr(target, name))
    if not changed:
        return
    if owner is Settings:
        state.update(**{name: value})      # the schema refuses; the window says why
        return
    try:
        setattr(state, name, spec.check(name, value))
    except SettingError as exc:
        state.notify(f"not applied: {exc}", "error")


def _scene_choice(state: AppState) -> None:
    s = state.settings
    imgui.separator_text("Scene")
    current = s.scene if s.scene in BUILTIN_SCENES else (
        "(scene file)" if s.scene.lower().endswith(".toml") else "(mesh file)")
    widgets.fit_next_item("Scene")
    if imgui.begin_combo("Scene", current):
        for name in BUILTIN_SCENES:
            if imgui.selectable(name, name == s.scene)[0]:
                state.requests.open_scene = name
        imgui.end_combo()
    if current not in BUILTIN_SCENES:
        widgets.dim_text_wrapped(s.scene)
    imgui.set_next_item_width(-90)
    _, state.mesh_path = imgui.input_text_with_hint(
        "##mesh", "mesh or scene file (glb, obj, toml…)", state.mesh_path)
    imgui.same_line()
    if imgui.button("Open") and state.mesh_path.strip():
        state.requests.open_scene = state.mesh_path.strip()
    if state.runtime.services.file_dialog_available:
        imgui.same_line()
        if imgui.button("…"):
            state.requests.open_file_dialog = True
        _tooltip("browse for a mesh or scene file")
    widgets.dim_text_wrapped("or drop a mesh or a scene file (.toml) onto the window")


def _camera_and_light(state: AppState) -> None:
    s = state.settings
    imgui.separator_text("Camera and light")
    if imgui.button("Reset camera"):
        state.update(camera=None)
    imgui.same_line()
    if imgui.button("Reset light"):
        state.update(light=None, light_flux=None, light_kind=None)
    _light_angles(state)
    _light_placement(state)
    facts = state.runtime.scene_facts
    flux = s.light_flux if s.light_flux is not None else (facts.light_flux_default or 0.0)
    widgets.fit_next_item("Light flux [W]")
    changed, flux = imgui.input_float("Light flux [W]", flux, 0.0, 0.0, "%.3g")
    _tooltip(tooltip_of(specs(Settings)["light_flux"]))
    if changed and flux != 0.0:     # an emptied field reads 0: wait for a number
        state.update(light_flux=float(flux))


def _light_angles(state: AppState) -> None:
    light = state.settings.light or state.runtime.scene_facts.light_default
    if light is None:
        imgui.text_disabled("light direction: available once the scene is loaded")
        return
    position, target = camera.as_pair(light)
    azimuth, elevation, distance = camera.to_angles(position, target)
    widgets.fit_next_item("Light azimuth")
    changed_a, azimuth = imgui.slider_float("Light azimuth", azimuth, -180.0, 180.0, "%.1f°")
    widgets.fit_next_item("Light elevation")
    changed_e, elevation = imgui.slider_float("Light elevation", elevation, -89.0, 89.0,
                                              "%.1f°")
    if changed_a or changed_e:
        new_position = camera.from_angles(target, azimuth, elevation, distance)
        state.update(light=(new_position, target))


def _light_placement(state: AppState) -> None:
    """The primary light's kind and its position and target as numbers: the angles above
    orbit the target, these put the light anywhere (inside a closed room, say)."""
    from explorer.scene.lights import LIGHT_KINDS

    light = state.settings.light or state.runtime.scene_facts.light_default
    if light is None:
        return
    loaded = state.runtime.scene_facts.scene
    try:
        kind = state.settings.light_kind or loaded[1].with_lights(state.settings.lights).light.kind
    except Exception:  # noqa: BLE001 - the scene is not loaded yet, or lights it lacks
        kind = None
    if kind in LIGHT_KINDS:
        widgets.fit_next_item("Light kind")
        changed, index = imgui.combo("Light kind", LIGHT_KINDS.index(kind), list(LIGHT_KINDS))
        _tooltip(tooltip_of(specs(Settings)["light_kind"]))
        if changed and LIGHT_KINDS[index] != kind:
            state.update(light_kind=LIGHT_KINDS[index])
    position, target = ([float(v) for v in point] for point in camera.as_pair(light))
    widgets.fit_next_item("Light position [m]")
    changed_p, position = imgui.drag_float3("Light position [m]", position, 0.01, 0.0, 0.0,
                                            "%.3f")
    widgets.fit_next_item("Light target [m]")
    changed_t, target = imgui.drag_float3("Light target [m]", target, 0.01, 0.0, 0.0, "%.3f")
    if (changed_p or changed_t) and list(position) != list(target):
        state.update(light=(tuple(position), tuple(target)))


def _spot_cone_angles(state: AppState) -> None:
    """The cone's inner and outer half-angles as one two-handled slider (the pair is one
    field; unset, it shows the scene light's own cone)."""
    s, spec = state.settings, specs(Settings)["spot_cone_degrees"]
    cone = s.spot_cone_degrees or state.runtime.scene_facts.light_cone_default
    if cone is None:
        return
    widgets.fit_next_item(label_of(spec, "spot_cone_degrees"))
    changed, angles = imgui.slider_float2(label_of(spec, "spot_cone_degrees"), list(cone),
                                          spec.low, spec.high, "%.1f")
    _tooltip(tooltip_of(spec))
    if changed:
        inner, outer = sorted(float(a) for a in angles)
        state.update(spot_cone_degrees=(inner, max(outer, 0.5)))


def _geometry_volume_choice(state: AppState) -> None:
    s, spec = state.settings, specs(Settings)["geometry_volume"]
    widgets.fit_next_item(spec.label)
    changed, value = widgets.combo(spec.label, s.geometry_volume, spec.choices)
    _tooltip(tooltip_of(spec))
    if not changed:
        return
    if value == "off" and s.bounces > 1:
        # The second bounce is reflected by the geometry volume: switching it off also
        # goes back to one bounce, and the window says so.
        if state.update(geometry_volume="off", bounces=1):
            state.notify("geometry volume off: back to one bounce (the second bounce is "
                         "the light the volume reflects)", "warning")
        return
    state.update(geometry_volume=value)


def _bounces_choice(state: AppState) -> None:
    s, spec = state.settings, specs(Settings)["bounces"]
    choices = list(spec.choices)
    widgets.fit_next_item(spec.label)
    changed, index = imgui.combo(spec.label, choices.index(s.bounces),
                                 [str(b) for b in choices])
    _tooltip(tooltip_of(spec))
    if not changed or choices[index] == s.bounces:
        return
    bounces = choices[index]
    if bounces > 1 and s.geometry_volume == "off":
        if state.update(bounces=bounces, geometry_volume="one-sided"):
            state.notify("bounces = 2 needs blockers to reflect from: the geometry volume "
                         "was switched on (one-sided)", "warning")
        return
    state.update(bounces=bounces)


def _resolution(state: AppState) -> None:
    """A fixed render size, when the render does not follow the View panel's size."""
    if state.follow_view_size:
        return
    s = state.settings
    widgets.fit_next_item("Resolution")
    changed, size = imgui.input_int2("Resolution", [s.width, s.height])
    _tooltip(tooltip_of(specs(Settings)["width"]))
    if changed and min(size) >= 16:     # typing "512" passes through "5": wait for it
        state.update(width=int(size[0]), height=int(size[1]))


def _tooltip(text: str) -> None:
    if imgui.is_item_hovered():
        imgui.set_tooltip(text)


_CUSTOM: dict[str, Callable[[AppState], None]] = {
    "spot_cone_degrees": _spot_cone_angles,       # a pair; unset = the scene's own cone
    "geometry_volume": _geometry_volume_choice,   # switching it off drops the 2nd bounce
    "bounces": _bounces_choice,                   # a 2nd bounce switches the volume on
}
"""Declared fields whose control has logic of its own (drawn where the field is)."""
_AFTER: dict[str, Callable[[AppState], None]] = {"Output": _resolution}
_SHOWN_WHEN: dict[str, Callable[[AppState], bool]] = {
    "spot_cone": lambda state: state.runtime.scene_facts.light_is_spot,
    "spot_cone_degrees": lambda state: (state.runtime.scene_facts.light_is_spot
                                         and state.settings.spot_cone),
    "downsample_factor": lambda state: state.settings.downsample != "none",
    "cascade_extent": lambda state: state.settings.cascades > 1,
    "cascade_focus": lambda state: state.settings.cascades > 1,
    "cascade_iterations": lambda state: state.settings.cascades > 1,
    "render_scale": lambda state: state.follow_view_size,
    "camera_occluders": lambda state: state.settings.geometry_volume != "off",
    **{name: (lambda state: state.settings.fog) for name in (
        "fog_density", "fog_albedo", "fog_phase", "fog_steps")},
    "fog_g": lambda state: state.settings.fog and state.settings.fog_phase != "isotropic",
    **{name: (lambda state: state.settings.glossy) for name in (
        "glossy_roughness", "glossy_strength", "glossy_samples")},
}
"""Controls shown only where they mean something."""
