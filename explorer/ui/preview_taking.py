"""Taking a side's pictures for the window's pipeline controller (explorer/ui/controller.py):
:func:`take_preview_if_due`, a progressive picture of the job in flight when one is due
(the pacing of explorer/ui/previews.py), and :func:`snapshot`, the copy of a side's linear
buffers into its :class:`~explorer.ui.picture.Picture` (a preview's or a finished frame's)."""

from __future__ import annotations

import sys
import time
from typing import TYPE_CHECKING, Protocol

from explorer.gl.context import use_screen
from explorer.ui import previews
from explorer.ui.controller_state import ControllerStatus, SideState, WorkUnit
from explorer.ui.picture import Picture, Stamp
from explorer.ui.side_display import picture_scale

if TYPE_CHECKING:
    import moderngl

    from explorer.gl.program import ProgramCache
    from explorer.lpv.frame import FrameResult
    from explorer.lpv.settings import Settings
    from explorer.ui.state import AppState


class PipelineController(Protocol):
    """What the pictures are taken with: the controller's context, programs and preview
    settings (explorer/ui/controller.py ``PipelineController``)."""

    ctx: moderngl.Context
    programs: ProgramCache
    preview_interval_s: float
    preview_scale: float
    first_preview_scale: float
    injected_preview_cells: int
    draw_ms: float

    @property
    def interacting(self) -> bool: ...

    def settings_for(self, state: AppState, side: str) -> Settings: ...


def take_preview_if_due(controller: PipelineController, state: AppState, side: SideState,
                        status: ControllerStatus) -> None:
    """A progressive picture of ``side``'s job when the propagation advanced since the
    last one and one is due (explorer/ui/previews.py); a large grid's first can be the
    injected light, before the first step (``previews.injected_unpreviewed``). The
    controller's preview settings (``preview_interval_s``, ``preview_scale``,
    ``first_preview_scale``, ``injected_preview_cells``) choose when and at what size."""
    if not state.progressive or previews.shows_nothing_new(side):
        return
    gathering = previews.gathering_unpreviewed(side)
    # a drag's pictures follow one another: the injected light of each would flash
    injected = not controller.interacting and previews.injected_unpreviewed(
        side, controller.injected_preview_cells)
    if not (gathering or injected or previews.propagated_since_preview(side)):
        return
    if not (gathering or injected) and not previews.preview_due(
            side, controller.preview_interval_s, controller.draw_ms):
        return
    progress, first = side.progress, side.previews == 0
    scale = controller.preview_scale if not first else min(controller.first_preview_scale,
                                                           controller.preview_scale)
    began = time.perf_counter()
    side.previewed_at = time.monotonic()
    if side.propagate_from is None and progress.stage == "propagate" and progress.done:
        side.propagate_from = (side.job_ms, progress.done)   # the pace from here
    try:
        shown = side.job.preview(scale, injected=injected)
        if shown:
            side.serial += 1
            side.previews += 1
            textures = side.pipeline.preview_textures
            # the injected light: no step of the propagation (its total once begun)
            stamp = Stamp(side.serial, False, 0, progress.total if progress.stage ==
                          "propagate" else 0, injected=True) if injected else Stamp(
                side.serial, False, progress.done, progress.total)
            snapshot(controller, side, stamp, side.result, textures)
            display = controller.settings_for(state, side.name)
            if side.auto_scale is None and display.auto_exposure:
                side.auto_scale = picture_scale(side.picture, display.indirect_only)
            status.published = True
    except Exception as exc:  # noqa: BLE001 - the job's own run reports it next
        print(f"lpv-explorer: preview of {side.name} failed: {exc}", file=sys.stderr)
    finally:
        use_screen(controller.ctx)
    if progress.stage == "propagate":
        side.previewed = progress.done
    elapsed = (time.perf_counter() - began) * 1e3
    side.job_ms += elapsed
    side.previews_ms += elapsed
    side.preview_ms = elapsed
    if first and side.previews == 1:
        side.first_preview_ms = elapsed     # (kept from job to job: the next's estimate)
    status.work.append(WorkUnit(side.name, f"preview {progress.done}/{progress.total}",
                                elapsed))


def snapshot(controller: PipelineController, side: SideState, stamp: Stamp,
             result: FrameResult | None, textures: tuple | None = None) -> None:
    """Copy the side's linear buffers (``textures``: a preview's own, e.g. reduced) into
    its picture; a finished frame's fog too (a preview shows the surfaces without it, as
    the pipeline's own preview does)."""
    if side.picture is None:
        side.picture = Picture(controller.ctx, controller.programs)
    fog = side.pipeline.fog_textures if stamp.final else None
    side.picture.copy_from(*(textures or side.pipeline.linear_textures), stamp, result,
                           fog, getattr(side.pipeline, "surface_textures", None))
