"""A picture with a colour ramp under it, the values at the ramp's ends and a caption:
compare's error images and render's grid-slice PNGs, so that a reader knows what a colour
means in numbers."""

from __future__ import annotations

from pathlib import Path

import numpy as np

TEXT_HEIGHT = 12
"""Pixels per text row (Pillow's default bitmap font is 11 pixels high)."""
CHAR_WIDTH = 6


def save_with_scale_bar(path: Path, picture: np.ndarray, ramp: np.ndarray, low: str,
                        high: str, caption: str | list[str]) -> None:
    """``picture`` ``(H, W, 3)`` in [0, 1] over a ramp strip (``ramp``: ``(W, 3)`` display
    colours from the low end to the high end), one text row with ``low`` at the left and
    ``high`` at the right, then the caption's rows."""
    from PIL import Image, ImageDraw

    height, width = picture.shape[:2]
    captions = [caption] if isinstance(caption, str) else list(caption)
    ramp_height = max(6, height // 20)
    canvas = np.ones((height + ramp_height + (1 + len(captions)) * TEXT_HEIGHT, width, 3))
    canvas[:height] = picture
    canvas[height:height + ramp_height] = np.broadcast_to(ramp[None], (ramp_height, width, 3))
    image = Image.fromarray((np.clip(canvas, 0, 1) * 255 + 0.5).astype(np.uint8))
    draw = ImageDraw.Draw(image)
    y = height + ramp_height
    draw.text((1, y), low, fill=(0, 0, 0))
    draw.text((max(width - CHAR_WIDTH * len(high) - 1, 0), y), high, fill=(0, 0, 0))
    for row, text in enumerate(captions, start=1):
        draw.text((1, y + row * TEXT_HEIGHT), text, fill=(0, 0, 0))
    image.save(path)
