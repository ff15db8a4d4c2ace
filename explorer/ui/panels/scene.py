"""Scene panel: scene or mesh file, camera, light direction, and the LPV's sizes and modes."""

from __future__ import annotations

from imgui_bundle import imgui

from explorer.lpv.settings import (
    BOUNCES,
    CASCADE_ITERATIONS,
    DOWNSAMPLE_MODES,
    GEOMETRY_VOLUME_MODES,
    GRID_FORMATS,
    INJECTION_MODES,
    MAX_CASCADES,
    MAX_SHADOW_KERNEL,
    SH_ORDERS,
)
from explorer.scene.lights import MAX_CONE_DEGREES
from explorer.ui import camera, widgets
from explorer.ui.state import AppState

BUILTIN_SCENES = ("cornell", "single-source", "room", "atrium")
GRID_SIZES = (8, 16, 24, 32, 48, 64)
RSM_SIZES = (64, 128, 256, 512, 1024)


def gui_scene(state: AppState) -> None:
    s = state.settings
    imgui.separator_text("Scene")
    scene_names = list(BUILTIN_SCENES)
    current = s.scene if s.scene in scene_names else "(mesh file)"
    if imgui.begin_combo("Scene", current):
        for name in scene_names:
            if imgui.selectable(name, name == s.scene)[0]:
                state.requests.open_scene = name
        imgui.end_combo()
    if current == "(mesh file)":
        widgets.dim_text_wrapped(s.scene)
    imgui.set_next_item_width(-90)
    _, state.mesh_path = imgui.input_text_with_hint("##mesh", "path to a mesh (obj, ply, glb…)",
                                                    state.mesh_path)
    imgui.same_line()
    if imgui.button("Open") and state.mesh_path.strip():
        state.requests.open_scene = state.mesh_path.strip()
    if state.runtime.file_dialog_available:
        imgui.same_line()
        if imgui.button("…"):
            state.requests.open_file_dialog = True
        if imgui.is_item_hovered():
            imgui.set_tooltip("browse for a mesh file")
    widgets.dim_text_wrapped("or drop a mesh file onto the window")

    imgui.separator_text("Camera and light")
    if imgui.button("Reset camera"):
        state.update(camera=None)
    imgui.same_line()
    if imgui.button("Reset light"):
        state.update(light=None, light_flux=None)
    _light_angles(state)
    flux = s.light_flux if s.light_flux is not None else (state.runtime.light_flux_default
                                                          or 0.0)
    changed, flux = imgui.input_float("Light flux [W]", flux, 0.0, 0.0, "%.3g")
    if changed and flux > 0:
        state.update(light_flux=float(flux))
    _spot_cone(state)
    changed, value = imgui.slider_int("Shadow PCF [texels]", s.shadow_kernel, 1,
                                      MAX_SHADOW_KERNEL)
    if changed:
        state.update(shadow_kernel=value)
    _tooltip("width of the box over which the direct light's shadow test is averaged: "
             "shadow edges become ramps this many shadow-map texels wide; 1 = hard")

    imgui.separator_text("Light propagation volume")
    _choice_int(state, "Grid size (cells³)", "grid_size", GRID_SIZES)
    changed, value = imgui.slider_int("Iterations", s.iterations, 0, 64)
    if changed:
        state.update(iterations=value)
    _choice_int(state, "RSM size (texels²)", "rsm_size", RSM_SIZES)
    _choice(state, "Downsample", "downsample", DOWNSAMPLE_MODES)
    if s.downsample != "none":
        changed, value = imgui.slider_int("Downsample factor", s.downsample_factor, 2, 8)
        if changed:
            state.update(downsample_factor=value)
    _choice(state, "Injection", "injection_mode", INJECTION_MODES)
    _geometry_volume_choice(state)
    _choice(state, "Grid format", "grid_format", GRID_FORMATS)
    _choice_int(state, "SH order", "sh_order", SH_ORDERS)
    _tooltip("1 = L1 (4 coefficients per colour), 2 = L2 (9). L2 keeps 127/128 of the "
             "clamped cosine's energy (L1: 7/8); its measured error: docs/ERRORS.md")

    imgui.separator_text("Leak reduction and bounces")
    changed, value = imgui.slider_float("VPL offset [cells]",
                                        s.injection_offset_cells, 0.0, 1.0, "%.2f")
    if changed:
        state.update(injection_offset_cells=round(float(value), 3))
    _tooltip("VPLs move this far along their normal before injection (default 0.5): a wall "
             "then stops lighting itself; room, 8 iterations: rel. L2 1.51 -> 0.555")
    changed, value = imgui.checkbox("Gather damping", s.gather_damping)
    if changed:
        state.update(gather_damping=value)
    _tooltip("scales E by clamp(E(p + h/2 n) / E(p - h/2 n), 0, 1): removes light that "
             "arrives from behind a surface; a small effect (docs/ERRORS.md)")
    _bounces_choice(state)

    imgui.separator_text("Cascades")
    changed, value = imgui.slider_int("Cascades", s.cascades, 1, MAX_CASCADES)
    if changed:
        state.update(cascades=value)
    _tooltip("nested grids around the camera's target, each with twice the cell size of "
             "the last, blended in the final gather")
    if s.cascades > 1:
        _choice(state, "Cascade iterations", "cascade_iterations", CASCADE_ITERATIONS)
        changed, value = imgui.slider_float("Cascade focus", s.cascade_focus, 0.0, 1.0,
                                            "%.2f")
        if changed:
            state.update(cascade_focus=float(value))
        _tooltip("0 = centred on the eye, 1 = on the camera's target")
        extent = s.cascade_extent or 0.0
        changed, value = imgui.input_float("Finest extent [m]", extent, 0.0, 0.0, "%.3g")
        _tooltip("edge of the finest cascade in world units; 0 = automatic (the coarsest "
                 "cascade then has the single grid's cells)")
        if changed and value >= 0.0:
            state.update(cascade_extent=float(value) or None)

    imgui.separator_text("Output")
    _, state.follow_view_size = imgui.checkbox("Render at view size", state.follow_view_size)
    if state.follow_view_size:
        changed, value = imgui.slider_float("Render scale", state.render_scale, 0.25, 2.0,
                                            "%.2f")
        if changed:
            state.render_scale = value
    else:
        changed, size = imgui.input_int2("Resolution", [s.width, s.height])
        if changed and min(size) >= 16:
            state.update(width=int(size[0]), height=int(size[1]))
    changed, value = imgui.checkbox("Check passes for NaN/Inf", s.debug_nan)
    if changed:
        state.update(debug_nan=value)


def _light_angles(state: AppState) -> None:
    light = state.settings.light or state.runtime.light_default
    if light is None:
        imgui.text_disabled("light direction: available once the scene is loaded")
        return
    position, target = camera.as_pair(light)
    azimuth, elevation, distance = camera.to_angles(position, target)
    changed_a, azimuth = imgui.slider_float("Light azimuth", azimuth, -180.0, 180.0, "%.1f°")
    changed_e, elevation = imgui.slider_float("Light elevation", elevation, -89.0, 89.0,
                                              "%.1f°")
    if changed_a or changed_e:
        new_position = camera.from_angles(target, azimuth, elevation, distance)
        state.update(light=(new_position, target))


def _spot_cone(state: AppState) -> None:
    """The spot's cone: on/off, and its inner and outer half-angles."""
    s = state.settings
    default = state.runtime.light_cone_default
    if not state.runtime.light_is_spot:
        return
    changed, value = imgui.checkbox("Spot cone", s.spot_cone)
    if changed:
        state.update(spot_cone=value)
    _tooltip("on: the spot fades smoothly from its inner to its outer angle, in the RSM and "
             "the direct light alike (docs/MODEL.md 'Spot cone'); off: the 90° square "
             "frustum with uniform intensity")
    cone = s.spot_cone_degrees or default
    if not s.spot_cone or cone is None:
        return
    changed, angles = imgui.slider_float2("Cone inner/outer [°]", list(cone), 0.0,
                                          MAX_CONE_DEGREES, "%.1f")
    if changed:
        inner, outer = sorted(float(a) for a in angles)
        state.update(spot_cone_degrees=(inner, max(outer, 0.5)))


def _geometry_volume_choice(state: AppState) -> None:
    s = state.settings
    changed, value = widgets.combo("Geometry volume", s.geometry_volume, GEOMETRY_VOLUME_MODES)
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
    s = state.settings
    changed, index = imgui.combo("Bounces", BOUNCES.index(s.bounces), [str(b) for b in BOUNCES])
    _tooltip("2: the geometry volume reflects part of the light it blocks (needs a geometry "
             "volume; also carries third and later bounces)")
    if not changed or BOUNCES[index] == s.bounces:
        return
    bounces = BOUNCES[index]
    if bounces > 1 and s.geometry_volume == "off":
        if state.update(bounces=bounces, geometry_volume="one-sided"):
            state.notify("bounces = 2 needs blockers to reflect from: the geometry volume "
                         "was switched on (one-sided)", "warning")
        return
    state.update(bounces=bounces)


def _tooltip(text: str) -> None:
    if imgui.is_item_hovered():
        imgui.set_tooltip(text)


def _choice(state: AppState, label: str, field: str, choices) -> None:
    changed, value = widgets.combo(label, getattr(state.settings, field), choices)
    if changed:
        state.update(**{field: value})


def _choice_int(state: AppState, label: str, field: str, choices) -> None:
    current = getattr(state.settings, field)
    options = sorted(set(choices) | {current})
    changed, index = imgui.combo(label, options.index(current), [str(v) for v in options])
    if changed:
        state.update(**{field: options[index]})
