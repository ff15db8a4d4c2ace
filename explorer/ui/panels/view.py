"""The 3D view: the pipeline's final image, a split view of two configurations with a
draggable divider, or their difference in false colour with a scale bar. Mouse: drag to
orbit, wheel to zoom (the camera is shared by both sides)."""

from __future__ import annotations

import numpy as np
from imgui_bundle import imgui

from explorer.lpv.tonemap import TONE_MAPS, display_encode
from explorer.ui import camera, images, widgets
from explorer.ui.state import VIEW_BUFFERS, VIEW_MODES, AppState
from explorer.ui.textures import diverging, heat, tonemap

ORBIT_DEGREES_PER_PIXEL = 0.35
ZOOM_PER_WHEEL_STEP = 0.9
_SCALE_BAR_WIDTH = 18.0
# Pipeline.final_texture holds the bottom row first (GL convention), so the view samples
# it upside down; textures the UI uploads from FrameResult arrays are top row first.
UV_TOP_LEFT, UV_BOTTOM_RIGHT = (0.0, 1.0), (1.0, 0.0)


def gui_view(state: AppState) -> None:
    _toolbar(state)
    rt = state.runtime
    avail = imgui.get_content_region_avail()
    scale = imgui.get_io().display_framebuffer_scale.x or 1.0
    # The difference view keeps room for its scale bar beside the image.
    bar = _SCALE_BAR_WIDTH + 60.0 if state.view_mode == "difference" else 0.0
    rt.view_size = (max(int((avail.x - bar) * scale), 0), max(int(avail.y * scale), 0))
    if avail.x < 8 or avail.y < 8:
        return
    if not rt.final_texture_id:
        _centred_message(state, avail)
        return
    width, height = state.settings.width, state.settings.height
    fit = min((avail.x - bar) / width, avail.y / height)
    size = imgui.ImVec2(width * fit + bar, height * fit)
    origin = imgui.get_cursor_screen_pos()
    origin = imgui.ImVec2(origin.x + (avail.x - size.x) * 0.5, origin.y)
    imgui.set_cursor_screen_pos(origin)
    imgui.invisible_button("##view", size)
    hovered, active = imgui.is_item_hovered(), imgui.is_item_active()
    draw = imgui.get_window_draw_list()
    end = imgui.ImVec2(origin.x + size.x, origin.y + size.y)
    rt.view_rect = (origin.x * scale, origin.y * scale, end.x * scale, end.y * scale)
    divider_grabbed = False
    if state.view_mode == "split" and rt.compare_texture_id:
        divider_grabbed = _split(state, draw, origin, end, hovered)
    elif state.view_mode == "difference" and rt.compare_result is not None:
        _difference(state, draw, origin, end)
    else:
        tex, flipped = side_texture(state, "A") or (rt.final_texture_id, True)
        draw.add_image(imgui.ImTextureRef(tex), origin, end, *_uv(0.0, 1.0, flipped))
        if state.comparing:
            _overlay(draw, origin, "configuration B is rendering…")
    if state.comparing and state.view_mode == "split":
        _label(draw, origin, end, state)
    if not divider_grabbed:
        _mouse_camera(state, hovered, active)
    if hovered and not active:
        hint = "drag: orbit   wheel: zoom" + ("   divider: drag" if state.view_mode == "split"
                                              else "")
        draw.add_text((origin.x + 8, end.y - imgui.get_text_line_height() - 6),
                      imgui.get_color_u32(imgui.ImVec4(1, 1, 1, 0.55)), hint)


def side_texture(state: AppState, side: str) -> tuple[int, bool] | None:
    """(GL texture name, stored bottom row first) of one side's chosen buffer, or None.
    "final" is the pipeline's own texture; the other buffers are FrameResult arrays
    encoded like it (the frame's display scale and tone curve; albedo as it is) and
    uploaded to a texture the UI owns."""
    rt = state.runtime
    if state.view_buffer == "final":
        tex = rt.final_texture_id if side == "A" else rt.compare_texture_id
        return (tex, True) if tex else None
    result = rt.result if side == "A" else rt.compare_result
    if result is None:
        return None
    version = (state.view_buffer, id(result))
    linear = linear_image(result, state.view_buffer)
    if state.view_buffer == "albedo":
        image = tonemap(linear, 1.0)
    else:
        image = display_encode(result.settings.exposure * linear,
                               getattr(result, "display_scale", 1.0),
                               getattr(result.settings, "tone_map", "linear-clip"))
    tex = rt.textures.upload(f"view-{side}", image, version=version, nearest=False)
    return tex, False


def linear_image(result, buffer: str):
    """The linear (H, W, 3) image of ``buffer`` (VIEW_BUFFERS) from a FrameResult."""
    return result.final_image if buffer == "final" else getattr(result, buffer)


def _uv(u0: float, u1: float, flipped: bool):
    """Texture coordinates of the columns u0..u1, top row at the top."""
    return ((u0, 1.0), (u1, 0.0)) if flipped else ((u0, 0.0), (u1, 1.0))


def _toolbar(state: AppState) -> None:
    for mode in VIEW_MODES:
        if imgui.radio_button(mode.capitalize(), state.view_mode == mode):
            state.view_mode = mode
        imgui.same_line()
    imgui.set_next_item_width(90)
    _, state.view_buffer = widgets.combo("##buffer", state.view_buffer, VIEW_BUFFERS)
    if imgui.is_item_hovered():
        imgui.set_tooltip("what the view shows: final = exposure·(direct + indirect)")
    imgui.same_line()
    imgui.set_next_item_width(120)
    changed, value = imgui.slider_float("Exposure", state.settings.exposure, 0.01, 64.0,
                                        "%.2f", imgui.SliderFlags_.logarithmic)
    if changed:
        state.update(exposure=value)
    if state.comparing:
        _same_line_if_fits("Auto-exposure per side", checkbox=True)
        _, state.auto_exposure = imgui.checkbox("Auto-exposure per side", state.auto_exposure)
    _same_line_if_fits("Auto exposure", checkbox=True)
    changed, value = imgui.checkbox("Auto exposure", state.settings.auto_exposure)
    if changed:
        state.update(auto_exposure=value)
    if imgui.is_item_hovered():
        imgui.set_tooltip("expose the image's log-average luminance at middle grey (0.18); "
                          "the Exposure slider then compensates on top")
    imgui.same_line()
    imgui.set_next_item_width(100)
    changed, value = widgets.combo("##tonemap", state.settings.tone_map, TONE_MAPS)
    if changed:
        state.update(tone_map=value)
    if imgui.is_item_hovered():
        imgui.set_tooltip("tone curve: filmic rolls highlights off (ACES fit), linear-clip "
                          "clips everything above 1 to white")
    _same_line_if_fits("Indirect only", checkbox=True)
    changed, value = imgui.checkbox("Indirect only", state.settings.indirect_only)
    if changed:
        state.update(indirect_only=value)
    _same_line_if_fits("Screenshot (F12)")
    if imgui.button("Screenshot (F12)"):
        from explorer.ui.app import default_screenshot_path

        state.requests.screenshot = default_screenshot_path()


def _same_line_if_fits(label: str, checkbox: bool = False) -> None:
    """Continue the toolbar on this line if the next widget fits, else wrap."""
    style = imgui.get_style()
    width = imgui.calc_text_size(label).x + style.frame_padding.x * 2
    if checkbox:
        width += imgui.get_frame_height() + style.item_inner_spacing.x
    imgui.same_line()
    if imgui.get_content_region_avail().x < width:
        imgui.new_line()


def _centred_message(state: AppState, avail) -> None:
    rt = state.runtime
    text = rt.gl_problem or rt.pipeline_error or "rendering…"
    colour = widgets.ERROR if (rt.gl_problem or rt.pipeline_error) else widgets.DIM
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + avail.x - 16)
    imgui.dummy((0, avail.y * 0.4))
    imgui.text_colored(colour, text)
    imgui.pop_text_wrap_pos()


def _split(state: AppState, draw, origin, end, hovered: bool) -> bool:
    """Draw A left and B right of the divider; returns True while the divider is dragged."""
    rt = state.runtime
    width = end.x - origin.x
    x = origin.x + width * state.split_position
    frac = state.split_position
    tex_a, flip_a = side_texture(state, "A") or (rt.final_texture_id, True)
    tex_b, flip_b = side_texture(state, "B") or (rt.compare_texture_id, True)
    draw.add_image(imgui.ImTextureRef(tex_a), origin, (x, end.y), *_uv(0.0, frac, flip_a))
    draw.add_image(imgui.ImTextureRef(tex_b), (x, origin.y), end, *_uv(frac, 1.0, flip_b))
    mouse = imgui.get_mouse_pos()
    near = hovered and abs(mouse.x - x) < 6.0
    grabbing = rt.split_dragging
    if near and imgui.is_mouse_clicked(0):
        grabbing = True
    if not imgui.is_mouse_down(0):
        grabbing = False
    rt.split_dragging = grabbing
    if grabbing:
        state.split_position = min(max((mouse.x - origin.x) / max(width, 1.0), 0.02), 0.98)
    if near or grabbing:
        imgui.set_mouse_cursor(imgui.MouseCursor_.resize_ew)
    colour = imgui.get_color_u32(imgui.ImVec4(1, 1, 1, 0.9 if (near or grabbing) else 0.6))
    draw.add_line((x, origin.y), (x, end.y), colour,
                  2.0 * (imgui.get_style().font_scale_dpi or 1.0))
    mid = (origin.y + end.y) * 0.5
    draw.add_circle_filled((x, mid), 7.0, imgui.get_color_u32(imgui.ImVec4(0.1, 0.1, 0.12, 0.9)))
    draw.add_circle((x, mid), 7.0, colour, 0, 2.0)
    draw.add_text((x - 16, mid - 7), colour, "<")
    draw.add_text((x + 10, mid - 7), colour, ">")
    return grabbing


def _label(draw, origin, end, state: AppState) -> None:
    a = "A: " + _preset_name(state.settings.corrections)
    b = "B: " + _preset_name(state.compare_settings.corrections)
    pad = 6.0
    _overlay(draw, origin, a)
    width = imgui.calc_text_size(b).x
    _overlay(draw, imgui.ImVec2(end.x - width - 2 * pad - 4, origin.y), b)


def _overlay(draw, pos, text: str) -> None:
    pad = 6.0
    size = imgui.calc_text_size(text)
    p0 = imgui.ImVec2(pos.x + 4, pos.y + 4)
    p1 = imgui.ImVec2(p0.x + size.x + 2 * pad, p0.y + size.y + 2 * pad)
    draw.add_rect_filled(p0, p1, imgui.get_color_u32(imgui.ImVec4(0, 0, 0, 0.6)), 4.0)
    draw.add_text((p0.x + pad, p0.y + pad), imgui.get_color_u32(imgui.ImVec4(1, 1, 1, 1)),
                  text)


def _preset_name(corrections) -> str:
    from explorer.lpv.settings import PRESETS

    for name, value in PRESETS.items():
        if value == corrections:
            return name
    return "custom"


def _difference(state: AppState, draw, origin, end) -> None:
    rt = state.runtime
    a, b = rt.result, rt.compare_result
    image_a, image_b = linear_image(a, state.view_buffer), linear_image(b, state.view_buffer)
    if image_a.shape != image_b.shape:
        _overlay(draw, origin, "the two sides differ in size; waiting for B")
        return
    version = ("difference", id(a), id(b), state.difference_scale, state.view_buffer)
    if rt.difference_cache is None or rt.difference_cache[0] != version:
        image, top = images.difference(image_a, image_b, state.difference_scale)
        tex = rt.textures.upload("difference", image, version=version)
        rt.difference_cache = (version, tex, top)
    _, tex, top = rt.difference_cache
    bar = _SCALE_BAR_WIDTH + 60.0
    image_end = imgui.ImVec2(end.x - bar, end.y)
    draw.add_image(imgui.ImTextureRef(tex), origin, image_end)
    scale_bar(draw, imgui.ImVec2(image_end.x + 8, origin.y), end.y - origin.y, top)
    _overlay(draw, origin, f"|A − B| luminance of {state.view_buffer}"
             + (" (auto scale)" if state.difference_scale <= 0 else ""))


def scale_bar(draw, pos, height: float, top: float, signed: bool = False) -> None:
    """A vertical colour-scale bar with ticks: heat from 0 (bottom) to ``top``, or with
    ``signed`` the diverging map from −top (bottom) to +top."""
    steps = 32
    low = -top if signed else 0.0

    def colour(frac: float):
        if signed:
            return diverging(np.array(2.0 * frac - 1.0), 1.0)
        return heat(frac)

    for i in range(steps):
        t0, t1 = i / steps, (i + 1) / steps
        c0, c1 = _u32(colour(1.0 - t0)), _u32(colour(1.0 - t1))
        y0, y1 = pos.y + t0 * height, pos.y + t1 * height
        draw.add_rect_filled_multi_color((pos.x, y0), (pos.x + _SCALE_BAR_WIDTH, y1),
                                         c0, c0, c1, c1)
    white = imgui.get_color_u32(imgui.ImVec4(1, 1, 1, 0.9))
    for frac in (0.0, 0.25, 0.5, 0.75, 1.0):
        y = pos.y + (1.0 - frac) * height
        draw.add_line((pos.x + _SCALE_BAR_WIDTH, y), (pos.x + _SCALE_BAR_WIDTH + 4, y), white)
        label = f"{low + (top - low) * frac:.2g}"
        draw.add_text((pos.x + _SCALE_BAR_WIDTH + 6, min(y, pos.y + height - 14) - 6), white,
                      label)


def _u32(rgb) -> int:
    return imgui.get_color_u32(imgui.ImVec4(float(rgb[0]), float(rgb[1]), float(rgb[2]), 1.0))


def _mouse_camera(state: AppState, hovered: bool, active: bool) -> None:
    current = state.settings.camera or state.runtime.camera_default
    if current is None:
        return
    eye, target = camera.as_pair(current)
    io = imgui.get_io()
    new = None
    if active and imgui.is_mouse_dragging(0):
        delta = imgui.get_mouse_drag_delta(0)
        imgui.reset_mouse_drag_delta(0)
        new = camera.orbit(eye, target, -delta.x * ORBIT_DEGREES_PER_PIXEL,
                           delta.y * ORBIT_DEGREES_PER_PIXEL)
    elif hovered and io.mouse_wheel != 0.0:
        new = camera.dolly(eye, target, ZOOM_PER_WHEEL_STEP ** io.mouse_wheel)
    if new is not None:
        state.update(camera=new)
