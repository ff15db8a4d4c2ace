"""The 3D view: the pipeline's final image, a split view of two configurations with a
draggable divider, or their difference in false colour with a scale bar. The camera (shared
by both sides) moves with the mouse and keys of explorer.ui.camera_controls; the overlays of
the "Show in scene" panel are drawn into the single and split views
(explorer.ui.overlays.in_view)."""

from __future__ import annotations

from imgui_bundle import imgui

from explorer.lpv.tonemap import display_encode
from explorer.ui import camera_controls, gizmo, images, legend, widgets
from explorer.ui.overlays import in_view
from explorer.ui.state import VIEW_BUFFERS, VIEW_MODES, AppState, default_screenshot_path
from explorer.ui.textures import tonemap

# Pipeline.final_texture holds the bottom row first (GL convention), so the view samples
# it upside down; textures the UI uploads from FrameResult arrays are top row first.
UV_TOP_LEFT, UV_BOTTOM_RIGHT = (0.0, 1.0), (1.0, 0.0)


def gui_view(state: AppState) -> None:
    _toolbar(state)
    rt = state.runtime
    avail = imgui.get_content_region_avail()
    scale = imgui.get_io().display_framebuffer_scale.x or 1.0
    # The difference view keeps room for its scale bar beside the image.
    bar = widgets.SCALE_BAR_WIDTH + 60.0 if state.view_mode == "difference" else 0.0
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
    over_gizmo = gizmo.hovered()        # the gizmo's handles take the click, not the camera
    imgui.begin_disabled(over_gizmo)
    imgui.invisible_button("##view", size)
    hovered, active = imgui.is_item_hovered(), imgui.is_item_active()
    imgui.end_disabled()
    draw = imgui.get_window_draw_list()
    end = imgui.ImVec2(origin.x + size.x, origin.y + size.y)
    rt.view_rect = (origin.x * scale, origin.y * scale, end.x * scale, end.y * scale)
    divider_grabbed = False
    split_x = None
    if state.view_mode == "split" and rt.compare_texture_id:
        divider_grabbed = _split(state, draw, origin, end, hovered)
        split_x = origin.x + (end.x - origin.x) * state.split_position
    elif state.view_mode == "difference" and rt.compare_result is not None:
        _difference(state, draw, origin, end)
    else:
        tex, flipped = side_texture(state, "A") or (rt.final_texture_id, True)
        draw.add_image(imgui.ImTextureRef(tex), origin, end, *_uv(0.0, 1.0, flipped))
        if state.comparing:
            _overlay(draw, origin, "configuration B is rendering…")
    if state.comparing and state.view_mode == "split":
        _label(draw, origin, end, state)
    if state.view_mode != "difference":     # overlays: colour bar, tooltip, picking
        in_view.over_image(state, draw, origin, end, hovered, split_x)
        divider_grabbed |= gizmo.draw(state, origin, end)   # the selected object's gizmo
    if not divider_grabbed:
        camera_controls.handle_mouse(state, hovered, active, end.y - origin.y)
    if hovered and not active:
        hint = camera_controls.hint(state) + ("   divider: drag" if state.view_mode == "split"
                                              else "")
        draw.add_text((origin.x + 8, end.y - imgui.get_text_line_height() - 6),
                      imgui.get_color_u32(imgui.ImVec4(1, 1, 1, 0.55)), hint)


def side_texture(state: AppState, side: str) -> tuple[int, bool] | None:
    """(GL texture name, stored bottom row first) of one side's chosen buffer with the
    enabled overlays drawn in it, or None. "final" is the pipeline's own texture; the other
    buffers are FrameResult arrays encoded like it (the frame's display scale and tone
    curve; albedo as it is) and uploaded to a texture the UI owns."""
    chosen = _buffer_texture(state, side)
    return None if chosen is None else in_view.shown_texture(state, side, *chosen)


def _buffer_texture(state: AppState, side: str) -> tuple[int, bool] | None:
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
    else:   # as the display pass shows the final image (docs/MODEL.md "Display")
        image = display_encode(result.settings.exposure * linear, result.display_scale,
                               result.settings.tone_map)
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
    camera_controls.toolbar(state)
    _same_line_if_fits("Exposure", field=120 + imgui.get_style().item_inner_spacing.x)
    imgui.set_next_item_width(120)
    changed, value = imgui.slider_float("Exposure", state.settings.exposure, 0.01, 64.0,
                                        "%.2f", imgui.SliderFlags_.logarithmic)
    if changed:
        state.update(exposure=value)
    if imgui.is_item_hovered():
        imgui.set_tooltip("multiplies the linear radiance; with the display's auto exposure "
                          "(Scene panel, Display) a compensation on top of it")
    if state.comparing:
        _same_line_if_fits("Expose sides separately", checkbox=True)
        _, state.expose_sides_separately = imgui.checkbox("Expose sides separately",
                                                          state.expose_sides_separately)
    _same_line_if_fits("Indirect only", checkbox=True)
    changed, value = imgui.checkbox("Indirect only", state.settings.indirect_only)
    if changed:
        state.update(indirect_only=value)
    _same_line_if_fits("Screenshot (F12)")
    if imgui.button("Screenshot (F12)"):
        state.requests.screenshot = default_screenshot_path()


def _same_line_if_fits(label: str, checkbox: bool = False, field: float = 0.0) -> None:
    """Continue the toolbar on this line if the next widget fits, else wrap. ``field``:
    the width of a slider or input in front of the label."""
    style = imgui.get_style()
    width = imgui.calc_text_size(label).x + style.frame_padding.x * 2 + field
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
    # B is A with the compare corrections and overrides (App.settings_for): name what
    # differs.
    a, b = legend.side_labels(state.settings, state.settings.with_changes(
        corrections=state.compare_settings.corrections, **dict(state.compare_overrides)))
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
    bar = widgets.SCALE_BAR_WIDTH + 60.0
    image_end = imgui.ImVec2(end.x - bar, end.y)
    draw.add_image(imgui.ImTextureRef(tex), origin, image_end)
    widgets.scale_bar(draw, imgui.ImVec2(image_end.x + 8, origin.y), end.y - origin.y, top)
    _overlay(draw, origin, f"|A − B| luminance of {state.view_buffer}"
             + (" (auto scale)" if state.difference_scale <= 0 else ""))
