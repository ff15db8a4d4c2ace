"""Which controls the reader's mode keeps inside the panels it shows: while a lesson step is
applied, the View toolbar and the Show in scene panel draw only what the step uses (its
view, its overlays, the settings its try-this buttons change); everywhere else, and with
all panels shown, every control is drawn. No imgui here: the panels ask."""

from __future__ import annotations

from typing import TYPE_CHECKING

from explorer.lessons import COMPARE_VIEWS, Step

if TYPE_CHECKING:
    from explorer.ui.state import AppState

OVERLAY_SWITCHES = ("slice", "glyphs", "vpls", "lattice", "cascade_boxes", "blockers")
"""The Show in scene panel's sections, by the overlay switch that heads each."""


def reader_step(state: AppState) -> Step | None:
    """The lesson step the reader's mode trims the panels for (None: every control)."""
    if not getattr(state, "reader_mode", False):
        return None
    session = state.lesson_session
    if session is None or not session.applied:
        return None
    return session.step


def view_controls(step: Step | None) -> frozenset[str]:
    """The View toolbar's controls a step uses: "modes" (single/split/difference) for a
    comparison or a before | after try-this, "buffer" for a step that shows one light,
    "frame-picked" when it picks a point, "indirect-only" when a try-this switches it;
    the frame button and the exposure always. None: all of them."""
    every = frozenset({"modes", "buffer", "frame", "frame-picked", "fly", "exposure",
                       "indirect-only", "screenshot"})
    if step is None:
        return every
    used = {"frame", "exposure"}
    if step.view in COMPARE_VIEWS or any(item.split for item in step.try_this):
        used.add("modes")
    if step.view in ("direct", "indirect", "albedo"):
        used.add("buffer")
    if step.overlays().picked_kind != "none":
        used.add("frame-picked")
    if "indirect_only" in step.controls() or "indirect_only" in dict(step.overrides):
        used.add("indirect-only")
    return frozenset(used)


def overlay_sections(step: Step | None, shown: dict[str, bool]) -> frozenset[str]:
    """The Show in scene sections a step uses: the overlays its ``[steps.show]`` table
    turns on, and any the reader has turned on since (``shown``: switch -> on now).
    None: all of them."""
    if step is None:
        return frozenset(OVERLAY_SWITCHES)
    table = dict(step.show)
    return frozenset(name for name in OVERLAY_SWITCHES
                     if table.get(name) or shown.get(name))
