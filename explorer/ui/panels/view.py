"""The 3D view: one configuration's picture, a split view of two configurations with a
draggable divider, or their difference in false colour with a scale bar. The images come
from the view composer (explorer/ui/view_composer.py, one pass of ``shaders/view.glsl``
over the sides' pictures), so exposure, buffer, indirect only, the divider and the
difference's scale and colour map run no pipeline stage. Side by side and small multiples
(:data:`GRID_MODES`) draw each side's whole picture in a cell of a grid, every cell
rendered at the cell's size and shown at A's exposure; while a side is still
converging its progress ("propagating 5/8") shows in the corner. The camera (shared by
both sides) moves with the mouse and keys of explorer.ui.camera_controls; the overlays of
the "Show in scene" panel are drawn into the single and split views
(explorer.ui.overlays.in_view)."""

from __future__ import annotations

from imgui_bundle import imgui

from explorer.lessons.compare_views import exposure_note, grid_shape, white_share
from explorer.ui import camera_controls, gizmo, legend, widgets
from explorer.ui.overlays import in_view
from explorer.ui.state import VIEW_BUFFERS, VIEW_MODES, AppState, default_screenshot_path
from explorer.ui.view_composer import DIFFERENCE_MAPS
from explorer.ui.weak_version import WeakVersion

GRID_MODES = ("side-by-side", "small-multiples")
"""View modes that show whole pictures in a grid of cells, one side each."""
GRID_GAP = 4.0
"""Screen units between two cells of the grid."""
MIN_CELL_ASPECT = 1.0
"""Narrowest a grid cell's picture gets (width / height): the camera's field of view is
vertical, so a narrower picture would crop the scene's sides away."""
_WHITE_CACHE: dict[str, tuple[WeakVersion, float]] = {}
"""Side -> ((its finished result, exposure, display scale, tone map, indirect only), share
shown white): measured once per result and display (the result held weakly: a freed
one's id names no entry, and the cache keeps no frame alive)."""


def gui_view(state: AppState) -> None:
    _toolbar(state)
    rt = state.runtime
    avail = imgui.get_content_region_avail()
    scale = imgui.get_io().display_framebuffer_scale.x or 1.0
    # The difference view keeps room for its scale bar beside the image.
    bar = widgets.SCALE_BAR_WIDTH + 60.0 if state.view_mode == "difference" else 0.0
    cells = grid_sides(state)
    # side by side is one row whatever the panel's shape (lessons say "left" and "right")
    cols, rows = (len(cells), 1) if state.view_mode == "side-by-side" else \
        grid_shape(len(cells), avail.x, avail.y) if cells else (1, 1)
    # each cell of a grid renders at the cell's size (the aspect kept, the work shared)
    cell_w, cell_h = (avail.x - bar - GRID_GAP * (cols - 1)) / cols, \
        (avail.y - GRID_GAP * (rows - 1)) / rows
    if cells:      # a cell's picture no narrower than square: the camera's view stays whole
        cell_h = min(cell_h, cell_w / MIN_CELL_ASPECT)
    rt.view.view_size = (max(int(cell_w * scale), 0), max(int(cell_h * scale), 0))
    if avail.x < 8 or avail.y < 8:
        return
    pictures = rt.frame.pictures
    if "A" not in pictures or rt.services.composer is None:
        _centred_message(state, avail)
        return
    width, height = state.settings.width, state.settings.height
    fit = min(cell_w / width, cell_h / height)
    size = imgui.ImVec2((width * fit + GRID_GAP) * cols - GRID_GAP + bar,
                        (height * fit + GRID_GAP) * rows - GRID_GAP)
    origin = imgui.get_cursor_screen_pos()
    origin = imgui.ImVec2(origin.x + (avail.x - size.x) * 0.5,
                          origin.y + ((avail.y - size.y) * 0.5 if cells else 0.0))
    imgui.set_cursor_screen_pos(origin)
    over_gizmo = gizmo.hovered()        # the gizmo's handles take the click, not the camera
    imgui.begin_disabled(over_gizmo)
    imgui.invisible_button("##view", size)
    hovered, active = imgui.is_item_hovered(), imgui.is_item_active()
    imgui.end_disabled()
    draw = imgui.get_window_draw_list()
    end = imgui.ImVec2(origin.x + size.x, origin.y + size.y)
    rt.view.view_rect = (origin.x * scale, origin.y * scale, end.x * scale, end.y * scale)
    divider_grabbed = False
    split_x = None
    if state.view_mode == "split" and "B" in pictures:
        divider_grabbed = _split(state, draw, origin, end, hovered)
        split_x = origin.x + (end.x - origin.x) * state.split_position
    elif state.view_mode == "difference" and "B" in pictures:
        _difference(state, draw, origin, end)
    elif cells:
        _grid(state, draw, origin, cells, cols, imgui.ImVec2(width * fit, height * fit))
    else:
        tex, flipped = side_texture(state, "A")
        draw.add_image(imgui.ImTextureRef(tex), origin, end, *_uv(0.0, 1.0, flipped))
        if state.comparing:
            _overlay(draw, origin, "configuration B is rendering…")
    if state.comparing and state.view_mode == "split":
        _label(draw, origin, end, state)
    _progress(state, draw, origin, end)
    if state.view_mode != "difference" and not cells:   # overlays: bar, tooltip, picking
        in_view.over_image(state, draw, origin, end, hovered, split_x)
        divider_grabbed |= gizmo.draw(state, origin, end)   # the selected object's gizmo
    if not divider_grabbed:
        camera_controls.handle_mouse(state, hovered, active, end.y - origin.y)
    else:               # the divider or the gizmo has the mouse: only a gizmo drag moves
        rt.view.interaction.held = gizmo.using()
    if hovered and not active:
        hint = camera_controls.hint(state) + ("   divider: drag" if state.view_mode == "split"
                                              else "")
        draw.add_text((origin.x + 8, end.y - imgui.get_text_line_height() - 6),
                      imgui.get_color_u32(imgui.ImVec4(1, 1, 1, 0.55)), hint)


def side_texture(state: AppState, side: str) -> tuple[int, bool]:
    """(GL texture name, stored bottom row first) of one side's chosen buffer as the
    display shows it (the view composer's image of the side's picture), with the enabled
    overlays drawn in it."""
    rt = state.runtime
    picture = rt.frame.pictures[side]
    display = rt.frame.displays.get(side) or _display(state, side)
    tex = rt.services.composer.side_image(side, picture, display, state.view_buffer)
    return in_view.shown_texture(state, side, tex, True,
                                 (picture.stamp, display, state.view_buffer))


def _display(state: AppState, side: str):
    from explorer.ui.picture import SideDisplay

    s = state.settings
    return SideDisplay(s.exposure, 1.0, s.tone_map, s.indirect_only)


def _uv(u0: float, u1: float, flipped: bool):
    """Texture coordinates of the columns u0..u1, top row at the top."""
    return ((u0, 1.0), (u1, 0.0)) if flipped else ((u0, 0.0), (u1, 1.0))


def _toolbar(state: AppState) -> None:
    """The view's controls; in the reader's mode only those the step on screen uses
    (explorer/ui/reader_controls.py)."""
    from explorer.ui.reader_controls import reader_step, view_controls

    shown = view_controls(reader_step(state))
    if "modes" in shown:
        for index, mode in enumerate(VIEW_MODES):
            if index:
                widgets.same_line_if_fits(mode.capitalize(), checkbox=True)
            if imgui.radio_button(mode.capitalize(), state.view_mode == mode):
                state.view_mode = mode
            imgui.same_line()
    if "buffer" in shown:
        imgui.set_next_item_width(90)
        _, state.view_buffer = widgets.combo("##buffer", state.view_buffer, VIEW_BUFFERS)
        if imgui.is_item_hovered():
            imgui.set_tooltip("what the view shows: final = exposure·(direct + indirect)")
        imgui.same_line()
    camera_controls.toolbar(state, shown)
    widgets.same_line_if_fits("Exposure", field=120 + imgui.get_style().item_inner_spacing.x)
    imgui.set_next_item_width(120)
    changed, value = imgui.slider_float("Exposure", state.settings.exposure, 0.01, 64.0,
                                        "%.2f", imgui.SliderFlags_.logarithmic)
    if changed:
        state.update(exposure=value)
    if imgui.is_item_hovered():
        imgui.set_tooltip("multiplies the linear radiance; with the display's auto exposure "
                          "(Scene panel, Display) a compensation on top of it")
    if state.comparing:
        widgets.same_line_if_fits("Expose sides separately", checkbox=True)
        _, state.expose_sides_separately = imgui.checkbox("Expose sides separately",
                                                          state.expose_sides_separately)
    if "indirect-only" in shown:
        widgets.same_line_if_fits("Indirect only", checkbox=True)
        changed, value = imgui.checkbox("Indirect only", state.settings.indirect_only)
        if changed:
            state.update(indirect_only=value)
    if "screenshot" in shown:
        widgets.same_line_if_fits("Screenshot (F12)")
        if imgui.button("Screenshot (F12)"):
            state.requests.screenshot = default_screenshot_path()


def _centred_message(state: AppState, avail) -> None:
    rt = state.runtime
    progress = rt.frame.progress.get("A")
    text = rt.services.gl_problem or rt.frame.pipeline_error or (
        f"rendering… {progress}" if progress else "rendering…")
    colour = widgets.ERROR if (rt.services.gl_problem or rt.frame.pipeline_error) else widgets.DIM
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + avail.x - 16)
    imgui.dummy((0, avail.y * 0.4))
    imgui.text_colored(colour, text)
    imgui.pop_text_wrap_pos()


def _progress(state: AppState, draw, origin, end) -> None:
    """Each side still converging says where it is, in the view's bottom right corner
    ("A: propagating 5/8"), and a side showing a progressive preview says so with the
    size it was gathered at ("preview 240×135 · propagating 5/8")."""
    rt = state.runtime
    labels = {side: text for side in ("A", "B")
              if (side == "A" or state.comparing)
              and (text := progress_label(rt.frame.progress.get(side),
                                          rt.frame.pictures.get(side)))}
    if not labels:
        return
    text = "   ".join(f"{side}: {label}" if state.comparing else label
                       for side, label in labels.items())
    width = imgui.calc_text_size(text).x
    line = imgui.get_text_line_height()
    _overlay(draw, imgui.ImVec2(end.x - width - 20, end.y - line - 2 * 6 - 8), text)


def progress_label(progress: str | None, picture) -> str:
    """What the view's corner says of one side: its job's progress, after "preview WxH"
    while the picture shown is a progressive preview (a coarse, reduced picture of the
    light so far; "preview WxH, injected light only" for the picture of the injected
    grid before the first propagation step); empty when the side has converged."""
    parts = []
    stamp = None if picture is None else picture.stamp
    if stamp is not None and not stamp.final:
        width, height = picture.size
        parts.append(f"preview {width}×{height}"
                     + (", injected light only" if stamp.injected else ""))
    if progress:
        parts.append(progress)
    return " · ".join(parts)


def _split(state: AppState, draw, origin, end, hovered: bool) -> bool:
    """Draw A left and B right of the divider; returns True while the divider is dragged."""
    rt = state.runtime
    width = end.x - origin.x
    x = origin.x + width * state.split_position
    frac = state.split_position
    tex_a, flip_a = side_texture(state, "A")
    tex_b, flip_b = side_texture(state, "B")
    draw.add_image(imgui.ImTextureRef(tex_a), origin, (x, end.y), *_uv(0.0, frac, flip_a))
    draw.add_image(imgui.ImTextureRef(tex_b), (x, origin.y), end, *_uv(frac, 1.0, flip_b))
    mouse = imgui.get_mouse_pos()
    near = hovered and abs(mouse.x - x) < 6.0
    grabbing = rt.view.split_dragging
    if near and imgui.is_mouse_clicked(0):
        grabbing = True
    if not imgui.is_mouse_down(0):
        grabbing = False
    rt.view.split_dragging = grabbing
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
    note = washed_out(state, "B")
    if note:    # under B's label, within B's side of the divider
        x = origin.x + (end.x - origin.x) * state.split_position
        _note(draw, imgui.ImVec2(x + 4, origin.y), end.x - x - 8, note)


def _note(draw, pos, width: float, text: str) -> None:
    """``text`` word-wrapped to ``width`` in a box below a label's line at ``pos``."""
    words, lines = text.split(), [""]
    for word in words:
        line = f"{lines[-1]} {word}".strip()
        if lines[-1] and imgui.calc_text_size(line).x + 12 > width:
            lines.append(word)
        else:
            lines[-1] = line
    _overlay(draw, imgui.ImVec2(pos.x, pos.y + imgui.get_text_line_height() + 16),
             "\n".join(lines))


def _overlay(draw, pos, text: str) -> None:
    pad = 6.0
    size = imgui.calc_text_size(text)
    p0 = imgui.ImVec2(pos.x + 4, pos.y + 4)
    p1 = imgui.ImVec2(p0.x + size.x + 2 * pad, p0.y + size.y + 2 * pad)
    draw.add_rect_filled(p0, p1, imgui.get_color_u32(imgui.ImVec4(0, 0, 0, 0.6)), 4.0)
    draw.add_text((p0.x + pad, p0.y + pad), imgui.get_color_u32(imgui.ImVec4(1, 1, 1, 1)),
                  text)


def grid_sides(state: AppState) -> tuple[str, ...]:
    """The sides a grid mode shows, in reading order (A first), or () for the other
    views: A and B side by side; for small multiples C and D too, one per further
    variant (``AppState.compare_variants``)."""
    if state.view_mode == "side-by-side":
        return ("A", "B")
    if state.view_mode == "small-multiples":
        return ("A", "B", "C", "D")[:2 + min(len(state.compare_variants), 2)]
    return ()


def cell_labels(state: AppState, sides: tuple[str, ...]) -> list[str]:
    """Each grid cell's label naming what differs from A ("B: grid 32")."""
    from explorer.ui.side_display import side_settings

    def settings_of(side: str):
        try:
            return side_settings(state, side)
        except ValueError:           # refused with A's rest: the controller says why
            return None

    a = state.settings
    b = settings_of("B")
    labels = [legend.side_labels(a, b if b is not None else a)[0]]
    for side in sides[1:]:
        settings = settings_of(side)
        if settings is None:
            labels.append(f"{side}: cannot run with A's settings")
            continue
        other = legend.side_labels(a, settings)[1]
        labels.append(side + other[1:])
    return labels


def washed_out(state: AppState, side: str) -> str:
    """What the caption says when the one shared exposure shows much of ``side`` white
    (``compare_views.exposure_note``), else ""; sides exposed separately have their own
    scale and need no note."""
    rt = state.runtime
    picture = rt.frame.pictures.get(side)
    display = rt.frame.displays.get(side)
    if picture is None or picture.result is None or display is None or \
            (state.expose_sides_separately and side == "B"
             and state.view_mode != "small-multiples"):
        return ""
    result = picture.result
    wanted = (display.exposure, display.scale, display.tone_map, display.indirect_only)
    parts = (result, *wanted)
    cached = _WHITE_CACHE.get(side)
    if cached is None or not cached[0].matches(parts):
        linear = result.indirect if display.indirect_only else result.final_image
        cached = _WHITE_CACHE[side] = (WeakVersion(parts, (int, float, str, bool)),
                                       white_share(linear, display.exposure * display.scale,
                                                   display.tone_map))
    return exposure_note(side, cached[1])


def _grid(state: AppState, draw, origin, sides: tuple[str, ...], cols: int, cell) -> None:
    """Each side's whole picture in its cell, with its label and the step's marks; a side
    not rendered yet says so in its cell."""
    rt = state.runtime
    pictures = rt.frame.pictures
    marks = in_view.step_marks(state)
    labels = cell_labels(state, sides)
    for index, side in enumerate(sides):
        row, col = divmod(index, cols)
        p0 = imgui.ImVec2(origin.x + col * (cell.x + GRID_GAP),
                          origin.y + row * (cell.y + GRID_GAP))
        p1 = imgui.ImVec2(p0.x + cell.x, p0.y + cell.y)
        if side not in pictures:
            draw.add_rect_filled(p0, p1, imgui.get_color_u32(imgui.ImVec4(0.06, 0.06, 0.07, 1)))
            _overlay(draw, p0, f"{labels[index]} (rendering…)")
            continue
        tex, flipped = side_texture(state, side)
        draw.add_image(imgui.ImTextureRef(tex), p0, p1, *_uv(0.0, 1.0, flipped))
        in_view.draw_marks(draw, rt.frame.result, marks, p0, p1)
        _overlay(draw, p0, labels[index])
        note = washed_out(state, side) if index else ""
        if note:
            _note(draw, p0, cell.x - 8, note)


def _difference(state: AppState, draw, origin, end) -> None:
    rt = state.runtime
    a, b = rt.frame.pictures["A"], rt.frame.pictures["B"]
    displays = [rt.frame.displays.get(side) or _display(state, side) for side in ("A", "B")]
    shown = rt.services.composer.difference(a, b, *displays, state.view_buffer,
                                   state.difference_scale, state.difference_colour_map)
    bar = widgets.SCALE_BAR_WIDTH + 60.0
    image_end = imgui.ImVec2(end.x - bar, end.y)
    draw.add_image(imgui.ImTextureRef(shown.texture), origin, image_end,
                   *_uv(0.0, 1.0, True))
    widgets.scale_bar(draw, imgui.ImVec2(image_end.x + 8, origin.y), end.y - origin.y,
                      shown.top, signed=shown.signed)
    what = "A − B" if shown.signed else "|A − B|"
    _overlay(draw, origin, f"{what} luminance of {state.view_buffer}"
             + (" (auto scale)" if state.difference_scale <= 0 else ""))


def difference_controls(state: AppState) -> None:
    """The difference view's scale and colour map (the Compare panel)."""
    changed, value = imgui.slider_float("Scale top (0 = auto)", state.difference_scale,
                                        0.0, 2.0, "%.3g")
    if changed:
        state.difference_scale = max(value, 0.0)
    _, state.difference_colour_map = widgets.combo("Colour map##difference",
                                                   state.difference_colour_map,
                                                   DIFFERENCE_MAPS)
