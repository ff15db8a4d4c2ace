"""When a side shows a progressive picture of its propagation: after the first preview of
a job, at most every :data:`PREVIEW_INTERVAL_S` and at most :data:`PREVIEW_SHARE` of the
time, and none once the finished frame is due within :data:`FINISH_SOON_S`. The first
preview of a job is coarse (:data:`FIRST_PREVIEW_SCALE`), and a job that changes only
the gather (no propagation to show) gets that one too while its full-size gather runs.
A job that only refines the picture on screen to a larger size (a drag's release) shows
no preview: the picture it would preview is the one already shown. On a large grid
(:data:`INJECTED_PREVIEW_CELLS`) a job that ran the injection shows the injected light
as its first preview, before the propagation's first step; the next preview follows at
the usual pace."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

from explorer.lpv.cache_keys import downstream

if TYPE_CHECKING:
    from explorer.ui.controller_state import SideState
    from explorer.ui.state import AppState

PREVIEW_INTERVAL_S = 0.25
"""Progressive pictures after the first of a job come at most this often ..."""
PREVIEW_SHARE = 0.1
"""... and take at most this share of the time: a preview gathers the image and the
window draws it, so the interval grows with what the last preview and a drawn frame
cost (at 64³ on llvmpipe about every 0.6 s; a quarter of the time made the converged
picture come later than a window without previews)."""
PREVIEW_SCALE = 0.5
"""Progressive previews gather at this fraction of each edge (a quarter of the pixels;
the finished frame comes at the full size): a full-size preview cost as much as four
propagation steps at 32³ on llvmpipe."""
FIRST_PREVIEW_SCALE = 0.25
"""A job's first preview gathers at this fraction of each edge (a sixteenth of the
pixels, about a tenth of a half-size preview's time): the first changed picture after a
change comes as soon as the first propagation step (or the job's first gather band) is
done; the view labels it as a coarse preview."""
INJECTED_PREVIEW_CELLS = 40 ** 3
"""A job that ran the injection on grids of at least this many cells (all cascades
together) shows its first preview as soon as the injection is done: the injected light
alone (grid_0, no propagation step yet), a partial picture the view labels "injected light
only". The propagation's start and first step of a 64³ grid take 50–80 ms on llvmpipe
after the injection (its scratch grids, grid_0's copies, 8 slabs); a 32³ grid's first
step comes a few milliseconds after, and its first preview waits for it. (The threshold
is the one above which a grid's volume work is split into units,
explorer/lpv/passes/textures.py ``APART_TEXELS``.)"""
FINISH_SOON_S = 0.5
"""After a job's first preview no other comes once the finished frame is due within this
(the propagation's pace so far, then the gather and display as last timed): it would be
on screen too briefly to be worth its gather and its drawing. A short job (32³ on
llvmpipe) thus shows one growing picture, a long one (64³) several."""


def propagated_since_preview(side: SideState) -> bool:
    """The side's job is propagating and has steps its last preview did not show."""
    progress = side.progress
    return (progress is not None and progress.stage == "propagate"
            and progress.done > side.previewed)


def gathering_unpreviewed(side: SideState) -> bool:
    """The side's job is gathering (a change the propagation does not see, or one whose
    propagation has just finished) and has shown no preview yet."""
    progress = side.progress
    return progress is not None and progress.stage == "gather" and side.previews == 0


def injected_unpreviewed(side: SideState, min_cells: int = INJECTED_PREVIEW_CELLS) -> bool:
    """The side's job has shown no preview, has just injected grids of at least
    ``min_cells`` cells (:data:`INJECTED_PREVIEW_CELLS`) and has no propagation step yet:
    its first picture can be the injected light (``Job.preview_source`` "injected").
    Not for a drag's reduced jobs: their pictures follow one another, and each one's
    injected light would flash darker between them."""
    job, request = side.job, side.request
    if side.previews or job is None or request is None or request.interactive:
        return False
    if job.preview_source() != "injected":
        return False
    cells = job.size_of("propagate")
    return cells is not None and cells >= min_cells


def shows_nothing_new(side: SideState) -> bool:
    """The side's job renders the frame it last finished at another size only (the full
    size after a drag, after the first small picture): a preview would cost its gather
    and a drawn frame for a picture no larger than the one on screen."""
    request, done = side.request, side.done
    if request is None or request.interactive:
        return False
    if done is None or done.settings is request.settings:
        return False
    if side.refines is not None and side.refines[0] is request:
        return side.refines[1]
    s = request.settings
    refines = done.settings.with_changes(width=s.width, height=s.height) == s
    side.refines = (request, refines)
    return refines


def preview_due(side: SideState, interval_s: float, draw_ms: float) -> bool:
    """Whether a preview of ``side`` is worth it now (the module docstring's pacing);
    ``interval_s`` 0 previews after every step, ``draw_ms`` is what the window spends
    drawing a frame."""
    if side.previews == 0 or interval_s <= 0.0:
        return True
    cost_s = (side.preview_ms + draw_ms) / 1e3 / PREVIEW_SHARE
    if time.monotonic() - side.previewed_at < max(interval_s, cost_s):
        return False
    return finish_due_ms(side) >= FINISH_SOON_S * 1e3


def finish_due_ms(side: SideState) -> float:
    """When ``side``'s job should finish, in milliseconds of work from now: its
    propagation steps left at the pace since its first preview, then the gather and
    display as the pipeline last timed them (infinite before a pace is known)."""
    progress = side.progress
    if side.propagate_from is None or progress is None or progress.stage != "propagate":
        return float("inf")
    ms, steps = side.propagate_from
    if progress.done <= steps:
        return float("inf")
    per_step = (side.job_ms - side.previews_ms - ms) / (progress.done - steps)
    timings = side.pipeline.timings_ms
    rest = sum(timings.get(stage, 0.0) for stage in downstream("propagate")[1:])
    return (progress.total - progress.done) * max(per_step, 0.0) + rest


def first_preview_due(state: AppState, side: SideState, interacting: bool,
                      injected_cells: int = INJECTED_PREVIEW_CELLS) -> bool:
    """The side's job has shown no preview and has a picture to show now (the injected
    light of a large grid, a propagation step, a gather-only change's accumulation): the
    controller takes it in the frame whose unit made it possible (asked by the job after
    each unit, so ``side.progress`` is brought up to date). Not while the user drags
    (``interacting``: the camera, an object, a held slider): each job of a drag finishes,
    or is replaced by the next, often in the frame it started in, and its finished picture
    is the one to show (a drag's previews come at a turn's start, as before)."""
    job, request = side.job, side.request
    if job is None or side.previews or not state.progressive or interacting or (
            request is not None and request.interactive):
        return False
    side.progress = job.progress
    if shows_nothing_new(side):
        return False
    return (propagated_since_preview(side) or gathering_unpreviewed(side)
            or injected_unpreviewed(side, injected_cells))
