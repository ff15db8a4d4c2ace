"""How each side of the view is exposed (docs/MODEL.md "Display"): the display scale
(the auto exposure of its picture), its own exposure when the sides are exposed
separately, and the :class:`~explorer.ui.picture.SideDisplay` the view composer draws it
with. The controller (explorer/ui/controller.py) owns the sides and their jobs and asks
here how to show them; nothing here runs a stage.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

import numpy as np

from explorer.lpv.settings import Settings
from explorer.ui.kept_answers import KeptAnswers
from explorer.ui.picture import Picture, SideDisplay

if TYPE_CHECKING:
    from collections.abc import Callable

    from explorer.lpv.frame import FrameResult
    from explorer.ui.state import AppState

SIDES = ("A", "B")
VARIANT_SIDES = ("C", "D")
"""Small multiples' further views (``AppState.compare_variants``): always at A's exposure
and display scale, and so is B in small multiples, so that every view of the grid shares
one colour scale."""
ALL_SIDES = SIDES + VARIANT_SIDES
EXPOSURE_TOLERANCE = 0.05
"""Relative change of a side's own exposure (exposed separately) worth applying."""


def side_settings(state: AppState, side: str) -> Settings:
    """The Settings ``side`` shows: A's; B: A's with the compare corrections and overrides
    (display fields as the user set them); C and D: A's with the small multiples' further
    variants (A's own when there is none)."""
    a = state.settings
    if side == "A":
        return a
    if side in VARIANT_SIDES:
        variants = state.compare_variants
        index = VARIANT_SIDES.index(side)
        if index >= len(variants):
            return a
        changes, corrections = tuple(variants[index]), None
    else:
        changes = tuple(state.compare_overrides)
        corrections = state.compare_settings.corrections
    return _SIDE_SETTINGS.answer(
        side, (a, corrections, changes),
        lambda: a.with_changes(**dict(changes)) if corrections is None
        else a.with_changes(corrections=corrections, **dict(changes)))


_SIDE_SETTINGS = KeptAnswers(most=len(VARIANT_SIDES) + 2)
"""Each side's settings: the window asks for them every frame; they are made again only
when A's settings or what the side changes in them are others (settings are frozen)."""


class ShownSide(Protocol):
    """What the exposure reads of a side (explorer/ui/controller.py ``SideState``)."""

    result: FrameResult | None
    picture: Picture | None
    auto_scale: float | None
    """The display scale of its first preview (None until measured)."""
    scale_cache: dict
    """(result id, indirect only) -> its display scale."""


def side_display(state: AppState, sides: dict[str, ShownSide], side: str,
                 settings: Settings) -> SideDisplay:
    """How ``side`` is shown, ``settings`` being its own (B's are A's unless a lesson's
    before | after split overrides them, e.g. the indirect light alone on the right): its
    exposure, tone curve and indirect only, and its display scale (the auto exposure of
    its picture, A's for B unless each side is exposed separately)."""
    if side in VARIANT_SIDES:       # A's exposure and display scale, whatever A's are
        a = side_display(state, sides, "A", state.settings)
        return SideDisplay(a.exposure, a.scale, settings.tone_map, settings.indirect_only)
    # small multiples share one scale: a grid of views is read by comparing its cells
    per_side = state.comparing and state.expose_sides_separately and \
        state.view_mode != "small-multiples"
    exposure = settings.exposure
    if per_side and not state.settings.auto_exposure:
        exposure = state.runtime.frame.side_exposures[SIDES.index(side)]
    own = side == "A" or per_side
    scale = auto_scale(sides[side if own else "A"], settings if own else state.settings)
    return SideDisplay(float(exposure), scale, settings.tone_map, settings.indirect_only)


def auto_scale(side: ShownSide, settings: Settings) -> float:
    """The auto exposure of ``side``'s picture shown with the display fields of
    ``settings`` (1 without auto exposure)."""
    if not settings.auto_exposure:
        return 1.0
    result = side.result
    if result is None or side.picture is None or not side.picture.stamp.final:
        return side.auto_scale if side.auto_scale is not None else 1.0
    if not settings.indirect_only:     # what the pipeline measured (PINNED_DISPLAY)
        return float(result.display_scale)
    key = (id(result), True)
    if key not in side.scale_cache:
        side.scale_cache[key] = result_scale(result, True)
    return side.scale_cache[key]


def update_side_exposures(state: AppState, results: dict[str, FrameResult | None],
                          indirect_only: Callable[[str], bool]) -> None:
    """Each side's own exposure (``runtime.frame.side_exposures``) when the sides are exposed
    separately without the display's auto exposure, measured once per new result;
    ``indirect_only(side)``: whether that side shows the indirect light only (asked only
    then: it makes the side's Settings)."""
    from explorer.lpv.passes.display import exposed_image
    from explorer.ui.images import auto_exposure

    rt = state.runtime
    if not (state.comparing and state.expose_sides_separately) or \
            state.settings.auto_exposure or state.view_mode == "small-multiples":
        return
    values = list(rt.frame.side_exposures)
    for i, name in enumerate(SIDES):
        result = results[name]
        if result is None:
            continue
        key = (id(result), indirect_only(name))
        if rt.frame.exposure_seen[i] == key:
            continue
        rt.frame.exposure_seen[i] = key
        linear = exposed_image(result.direct, result.indirect, 1.0, key[1], result.fog)
        value = auto_exposure(linear, 1.0)
        if abs(value - values[i]) > EXPOSURE_TOLERANCE * max(values[i], 1e-12):
            values[i] = float(f"{value:.3g}")
    rt.frame.side_exposures = (values[0], values[1])


def result_scale(result: FrameResult, indirect_only: bool) -> float:
    """The auto exposure of a finished frame shown with ``indirect_only`` (the display
    stage's measure, explorer/lpv/passes/display.py)."""
    from explorer.lpv.passes.display import display_scale, exposed_image

    unexposed = exposed_image(result.direct, result.indirect, 1.0, indirect_only, result.fog)
    mask = np.asarray(result.gbuffer_position)[..., 3] > 0.5
    return display_scale(unexposed, mask, True)


def picture_scale(picture: Picture, indirect_only: bool) -> float:
    """The auto exposure of a picture read back (a first preview)."""
    from explorer.lpv.passes.display import display_scale, exposed_image

    direct, indirect, mask = picture.read()
    return display_scale(exposed_image(direct, indirect, 1.0, indirect_only), mask, True)
