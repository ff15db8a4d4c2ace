"""Rendering a lesson step: its settings made small for a quick render
(:func:`shrink_settings`, :func:`preview_settings`) and its view as an image
(:func:`render_step`), split and difference views included: what the tests, the lesson
checks (:mod:`explorer.lessons.verify`), ``lpv-explorer lessons --check`` and
``lpv-explorer render --lesson`` render."""

from __future__ import annotations

from typing import Any

from explorer.lessons.model import COMPARE_VIEWS, Step
from explorer.lpv.settings import Settings


def shrink_settings(settings: Settings, size: int | None = 64, max_grid: int | None = 16,
                    rsm_size: int | None = 32, max_iterations: int | None = 8) -> Settings:
    """``settings`` made smaller for a quick render: a ``size``² image, at most
    ``max_grid``³ cells and ``max_iterations`` steps, at most a ``rsm_size``² RSM (None
    keeps that setting). Everything a step compares (corrections, views) is kept."""
    changes: dict[str, Any] = {}
    if size is not None:
        changes.update(width=size, height=size)
    for name, limit in (("rsm_size", rsm_size), ("grid_size", max_grid),
                        ("iterations", max_iterations)):
        if limit is not None:
            changes[name] = min(getattr(settings, name), limit)
    return settings.with_changes(**changes)


def preview_settings(step: Step, size: int = 64, max_grid: int = 16, rsm_size: int = 32,
                     max_iterations: int = 8, base: Settings | None = None) -> Settings:
    """The step's settings shrunk for a quick preview (tests, CI renders, thumbnails):
    :func:`shrink_settings` of :meth:`Step.settings`."""
    return shrink_settings(step.settings(base), size, max_grid, rsm_size, max_iterations)


def render_step(pipeline: Any, step: Step, settings: Settings | None = None
                ) -> tuple[Any, Any]:
    """Run ``pipeline`` (an ``explorer.lpv.pipeline.Pipeline``) for ``step`` and return
    ``(image, result)``: the step's view as an (H, W, 3) display image in [0, 1], and the
    FrameResult of the step's own configuration.

    ``settings`` defaults to ``step.settings()``; pass e.g. :func:`preview_settings` to
    render small. A "split" view puts the step's configuration on the left half and the
    ``compare`` preset on the right; a "difference" view shows ``|A − B|`` of the linear
    final images, scaled so that the largest difference is white."""
    import numpy as np

    from explorer.lpv.twin.tonemap import linear_to_srgb

    settings = step.settings() if settings is None else settings
    result = pipeline.run(settings)
    if step.view not in COMPARE_VIEWS:
        return pipeline.view(step.view), result
    mine_display = pipeline.view("final")
    mine_linear = np.array(result.final_image, copy=True)
    pipeline.run(settings.with_changes(corrections=step.compare))
    # the other side at this side's display scale: an auto exposure must not hide the
    # difference in brightness the step shows
    other_display = pipeline.view("final", display_scale=result.display_scale)
    other_linear = pipeline.last_result.final_image
    if step.view == "split":
        image = np.array(mine_display, copy=True)
        half = int(round(image.shape[1] * (0.5 if step.split_at is None else step.split_at)))
        image[:, half:] = other_display[:, half:]
        image[:, half] = 1.0  # the divider
        return image, result
    difference = np.abs(mine_linear - other_linear)
    scale = float(difference.max())
    image = linear_to_srgb(difference / scale) if scale > 0 else np.zeros_like(difference)
    return np.clip(image, 0.0, 1.0), result
