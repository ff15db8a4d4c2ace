"""When the window draws, waits or hurries: input and changes draw at once, an idle window
waits for events (up to a timeout that ends early when a camera move settles or a message
is due to disappear), a camera move or a playing animation counts as interaction (the
pipelines render at the drag's reduced size), and a running job with nothing new to show
redraws its progress label only every :data:`PROGRESS_REDRAW_S`."""

from __future__ import annotations

import time
from copy import deepcopy
from dataclasses import fields, is_dataclass
from pathlib import PurePath
from typing import TYPE_CHECKING

from explorer.ui.frame_budget import FRAME_TARGET_MS
from explorer.ui.state import AppState

if TYPE_CHECKING:
    from explorer.lpv.settings import Settings

INTERACTION_SETTLE_S = 0.2
"""After the last wheel step or key move the camera counts as moving this much longer."""
FRAMES_AFTER_INPUT = 2
"""Frames drawn after input or a change before the loop may wait (imgui settles hover
and click states over a frame or two)."""
IDLE_TIMEOUT_S = 0.5
"""An idle loop wakes this often without input (shader files, the Error panel's delay);
it draws only if something changed."""
MESSAGE_SHOWN_S = 20.0
"""The status line shows the last message this long."""
DRAG_MARGIN_MS = 6.0
"""How far inside ``FRAME_TARGET_MS`` a drag's frames aim (:data:`DRAG_FPS`)."""
DRAG_FPS = 1000.0 / (FRAME_TARGET_MS - DRAG_MARGIN_MS)
"""Frame rate aimed at while the camera is dragged (a frame :data:`DRAG_MARGIN_MS` inside
explorer/ui/frame_budget.py ``FRAME_TARGET_MS``, the 50 ms no frame of a drag should pass):
the pipelines get what a frame at this rate leaves after the window's own drawing, and
render at the size that fits (explorer/ui/frame_budget.py DRAG_SCALES). Aimed at 50 ms
itself, a unit's misestimate and the drawing's jitter (the window's own drawing is a
smoothed figure, a frame showing a new picture draws several ms more) put the drags' longest
frames at 48–60 ms on llvmpipe; at 47 ms, 45–52; at 44 ms, 42–47, the first pictures and
convergence as before (BENCHMARKS.md, issue #32 item 3)."""
MIN_DRAG_BUDGET_MS = 4.0
PROGRESS_REDRAW_S = 1.0
"""While a job runs and no new picture or input arrives, the window draws this often
(the progress label; each drawing costs the job about as much as a propagation step on
llvmpipe)."""


def drag_budget_ms(ui_ms: float) -> float:
    """What a drag's frame may spend on the pipelines: a :data:`DRAG_FPS` frame less the
    window's own drawing (``ui_ms``)."""
    return max(1000.0 / DRAG_FPS - ui_ms, MIN_DRAG_BUDGET_MS)


def interacting(state: AppState) -> bool:
    """The camera or an object is being moved (a drag, the gizmo, a wheel step or a fly
    key a moment ago) or the animation plays (its paths move the light and objects, the
    fly-through the camera): the pipelines render at the drag's reduced size, a frame in
    flight finishes before the next starts, and the loop does not idle."""
    rt = state.runtime
    return (rt.view.interaction.active(time.monotonic(), INTERACTION_SETTLE_S)
            or (rt.services.animation is not None and rt.services.animation.active))


def may_wait(busy: bool, updated_moving: bool, moving: bool) -> bool:
    """Whether the next frame may wait for events: nothing to draw or work on (``busy``
    false), the camera not moving now, and not moving either when this frame's update ran
    (``updated_moving``): a move that settled during the frame has its full-size frame
    due, which waiting would hold back by the whole idle timeout."""
    return not (busy or updated_moving or moving)


def note_setting_drag(state: AppState, before: Settings) -> None:
    """A widget held down (a slider being dragged) changed what the pipelines run this
    frame (``before``: the settings when the panels began): it counts as a move, as a
    camera drag does, so that each job of the drag renders at the drag's size and finishes
    before the next starts (else every frame of the drag cancels the job in flight and no
    picture comes until the drag ends). A display field's slider (exposure) runs no stage
    and is not counted."""
    from imgui_bundle import imgui

    settings = state.settings
    if settings is before or not imgui.is_any_item_active():
        return
    from explorer.ui.controller import PINNED_DISPLAY

    if settings.with_changes(**PINNED_DISPLAY) != before.with_changes(**PINNED_DISPLAY):
        state.runtime.view.interaction.moved_at = time.monotonic()


def idle_timeout(state: AppState, timeout_s: float) -> float:
    """How long an idle loop may wait: ``timeout_s``, or less when the status line's
    message is due to disappear sooner or a camera move settles sooner (its full-size
    frame starts then)."""
    timeout = timeout_s
    interaction = state.runtime.view.interaction
    if not interaction.held:      # a camera move settling: the full size follows then
        settles = interaction.moved_at + INTERACTION_SETTLE_S - time.monotonic()
        if settles > 0:
            timeout = min(timeout, settles + 0.01)
    messages = state.messages
    if messages and messages[-1].level != "error":
        left = messages[-1].created + MESSAGE_SHOWN_S - time.monotonic()
        if left > 0:
            timeout = min(timeout, left + 0.05)
    return max(timeout, 0.0)


def message_expired(state: AppState, drawn_at: float) -> bool:
    """The status line shows a message whose time is up (it was still due when the frame
    of ``drawn_at`` was drawn): draw it away."""
    messages = state.messages
    if not messages or messages[-1].level == "error":
        return False
    created = messages[-1].created
    return drawn_at - created < MESSAGE_SHOWN_S <= time.monotonic() - created


def fingerprint(state: AppState) -> tuple:
    """What the window shows depends on besides input and the pipelines' work, so that a
    script or test that changes the state between frames gets it drawn."""
    s = state
    return (s.settings, s.compare_settings, s.compare_overrides, s.compare_variants,
            s.view_mode,
            s.view_buffer, s.split_position, s.expose_sides_separately,
            s.difference_scale, s.difference_colour_map, s.follow_view_size,
            s.render_scale, s.frame_budget_ms, s.progressive, values_of(s.inspect),
            values_of(s.overlays), tuple(s.open_panels.items()), s.lesson_id,
            s.lesson_step, s.plot_tab, len(s.messages), values_of(s.requests),
            s.runtime.frame.side_exposures)


_PLAIN = (str, int, float, bool, type(None), PurePath)
"""Values a fingerprint holds as they are (immutable)."""
_FIELDS: dict[type, tuple[str, ...]] = {}


def values_of(obj) -> tuple:
    """The field values of the dataclass ``obj`` as a tuple, as ``dataclasses.astuple``
    gives them (a nested dataclass as its values, any other value not immutable copied
    deeply), without astuple's deep copy of every plain value: the window takes three of
    these fingerprints a frame."""
    cls = type(obj)
    names = _FIELDS.get(cls)
    if names is None:
        names = _FIELDS[cls] = tuple(f.name for f in fields(obj))
    out = []
    for name in names:
        value = getattr(obj, name)
        if not isinstance(value, _PLAIN):
            value = (values_of(value) if is_dataclass(value) and not isinstance(value, type)
                     else deepcopy(value))
        out.append(value)
    return tuple(out)
