"""A comparing try-this as a picture, headless: the step (before) and its change (after,
or each of a small multiples' values) rendered and composed the way its ``compare``
says (:func:`render_try`), every side at the step's display scale, and the grid the
side-by-side and small-multiples views share with the window (:func:`grid_shape`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from explorer.lessons.model import Step
from explorer.lpv.settings import Settings

GRID_GAP_PX = 2
"""Pixels between two cells of a headless grid (the window's gap is its own)."""
WHITE = 0.98
"""A displayed (sRGB-encoded) channel at or above this reads as white; a pixel whose
three channels all do has lost its shading to the shared exposure."""
MOST_WHITE = 0.02
"""Largest share of a side's pixels that may read white before its caption says so."""


def grid_shape(count: int, width: float, height: float, aspect: float = 1.0
               ) -> tuple[int, int]:
    """(columns, rows) for ``count`` cells in a ``width`` × ``height`` area: the grid
    whose cells are largest, a cell's size measured by the largest ``aspect`` picture it
    holds (a scene framed by the camera's vertical field of view reads about square;
    wide areas put the cells in a row, tall ones in a column)."""
    best, best_size = (count, 1), -1.0
    for cols in range(1, count + 1):
        rows = -(-count // cols)
        size = min(width / cols, height / rows * aspect)
        if size > best_size + 1e-9:
            best, best_size = (cols, rows), size
    return best


@dataclass(frozen=True)
class TryPicture:
    """A comparing try-this rendered: the composed ``image`` (H, W, 3) in [0, 1], each
    side's display image (the step first) and FrameResult, and the one display scale
    every side is shown at (the step's: a shared colour scale)."""

    image: np.ndarray
    sides: tuple[np.ndarray, ...]
    results: tuple[Any, ...]
    display_scale: float


def white_share(linear: np.ndarray, scale: float, tone_map: str = "filmic") -> float:
    """Share of the pixels of ``linear`` (a frame's unexposed or exposed final image)
    shown white at ``scale`` (exposure × display scale) with ``tone_map``."""
    from explorer.lpv.twin.tonemap import display_encode

    shown = display_encode(np.asarray(linear)[..., :3], scale, tone_map)
    return float(np.mean(np.all(shown >= WHITE, axis=-1)))


def white_at(image: np.ndarray, points: list[tuple[float, float]]) -> list[bool]:
    """For each (x, y) pixel of a display ``image``, whether its 3 × 3 neighbourhood
    reads white (the feature a mark names has lost its shading)."""
    height, width = image.shape[:2]
    out = []
    for x, y in points:
        col, row = int(np.clip(x, 0, width - 1)), int(np.clip(y, 0, height - 1))
        patch = image[max(row - 1, 0):row + 2, max(col - 1, 0):col + 2, :3]
        out.append(bool(np.all(patch >= WHITE, axis=-1).mean() > 0.5))
    return out


def exposure_note(side: str, share: float) -> str:
    """The caption's word for a side that the shared exposure washes out ("" when at
    most :data:`MOST_WHITE` of it reads white): it is far brighter than the step's
    side, which sets the one colour scale of the comparison."""
    if share <= MOST_WHITE:
        return ""
    return (f"{side}: {share:.0%} white at A's exposure (one shared scale: {side} is that "
            "much brighter)")


def try_settings(step: Step, index: int, settings: Settings | None = None
                 ) -> tuple[Settings, ...]:
    """The settings of every side of the ``index``-th (1-based) try-this: the step's,
    then one per value it shows (``TryThis.variants``)."""
    settings = step.settings() if settings is None else settings
    item = step.try_this[index - 1]
    return (settings, *(item.apply(settings, value) for value in item.variants))


def render_try(pipeline: Any, step: Step, index: int, settings: Settings | None = None
               ) -> TryPicture:
    """Render the ``index``-th try-this of ``step`` with ``pipeline`` (an
    ``explorer.lpv.pipeline.Pipeline``) as its ``compare`` shows it: split (the step left
    of ``step.split_at``, the change right of it), difference (``|A − B|`` of the linear
    final images, the largest difference white), side-by-side or small multiples (whole
    pictures in a :func:`grid_shape` grid). ``settings``: the step's (default
    ``step.settings()``; pass ``preview_settings`` to render small)."""
    from explorer.lpv.twin.tonemap import linear_to_srgb

    item = step.try_this[index - 1]
    if not item.compares:
        raise ValueError(f"try-this {index} of step {step.number} compares nothing "
                         f"(compare = {item.compare!r})")
    results, sides, linear = [], [], []
    scale = None
    for side in try_settings(step, index, settings):
        result = pipeline.run(side)
        scale = float(result.display_scale) if scale is None else scale
        # every side at the step's display scale: an auto exposure must not hide the
        # difference in brightness the try-this shows
        sides.append(np.array(pipeline.view("final", display_scale=scale), copy=True))
        linear.append(np.array(result.final_image, copy=True))
        results.append(result)
    if item.compare == "split":
        image = np.array(sides[0], copy=True)
        at = int(round(image.shape[1] * (0.5 if step.split_at is None else step.split_at)))
        image[:, at:] = sides[1][:, at:]
        image[:, at] = 1.0                      # the divider
    elif item.compare == "difference":
        difference = np.abs(linear[0] - linear[1])
        top = float(difference.max())
        image = np.clip(linear_to_srgb(difference / top), 0.0, 1.0) if top > 0 \
            else np.zeros_like(difference)
    else:
        image = _grid(sides)
    return TryPicture(image, tuple(sides), tuple(results), scale)


def _grid(images: list[np.ndarray]) -> np.ndarray:
    """``images`` (all one size) in reading order, two to a row (a 2 × 2 grid for three
    or four), black gaps between the cells."""
    height, width = images[0].shape[:2]
    cols, rows = 2, -(-len(images) // 2)
    gap = GRID_GAP_PX
    out = np.zeros((rows * height + (rows - 1) * gap, cols * width + (cols - 1) * gap, 3),
                   np.float32)
    for number, image in enumerate(images):
        row, col = divmod(number, cols)
        y, x = row * (height + gap), col * (width + gap)
        out[y:y + height, x:x + width] = image[..., :3]
    return out
