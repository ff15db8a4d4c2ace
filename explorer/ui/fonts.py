"""The window's fonts: Roboto for prose (regular, bold, italic, bold italic), Inconsolata
for code, each with Latin Modern Math merged in for the symbols Roboto lacks (→, ⟨ ⟩, ∝,
⊥, ...). All ship with imgui_bundle (its ``assets/fonts``).

:func:`codepoints` reads a font's character map (the ``cmap`` table of a TrueType or
OpenType file) so that the tests can check every character a lesson draws as text against
the fonts that will draw it (:func:`covered`), without a window.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

TEXT_FONTS = {
    "regular": "Roboto/Roboto-Regular.ttf",
    "bold": "Roboto/Roboto-Bold.ttf",
    "italic": "Roboto/Roboto-RegularItalic.ttf",
    "bold-italic": "Roboto/Roboto-BoldItalic.ttf",
    "code": "Inconsolata-Medium.ttf",
}
"""Style (explorer.lessons.text.STYLES) -> font file under imgui_bundle's assets/fonts."""
SYMBOL_FONT = "latex/latinmodern-math.otf"
"""Merged into every text font: imgui falls back to it for glyphs the first font lacks."""
BODY_SIZE = 16.0
"""Pixel size of lesson prose (the rest of the window uses 15)."""


def fonts_dir() -> Path:
    import imgui_bundle

    return Path(imgui_bundle.__file__).parent / "assets" / "fonts"


@cache
def codepoints(path: str | Path) -> frozenset[int]:
    """Every code point the font at ``path`` maps to a glyph (cmap formats 4 and 12)."""
    data = Path(path).read_bytes()
    (tables,) = struct.unpack(">H", data[4:6])
    offsets = {}
    for i in range(tables):
        tag, _, offset, _ = struct.unpack(">4sIII", data[12 + 16 * i:28 + 16 * i])
        offsets[tag] = offset
    if b"cmap" not in offsets:
        raise ValueError(f"{path}: no cmap table")
    base = offsets[b"cmap"]
    (count,) = struct.unpack(">H", data[base + 2:base + 4])
    found: set[int] = set()
    for i in range(count):
        _, _, offset = struct.unpack(">HHI", data[base + 4 + 8 * i:base + 12 + 8 * i])
        sub = base + offset
        (fmt,) = struct.unpack(">H", data[sub:sub + 2])
        if fmt == 4:
            found |= _format4(data, sub)
        elif fmt == 12:
            (groups,) = struct.unpack(">I", data[sub + 12:sub + 16])
            for k in range(groups):
                start, end, _ = struct.unpack(">III", data[sub + 16 + 12 * k:sub + 28 + 12 * k])
                found.update(range(start, end + 1))
    return frozenset(found)


def _format4(data: bytes, sub: int) -> set[int]:
    """Code points of a cmap format-4 subtable (segments of 16-bit code points)."""
    (seg_x2,) = struct.unpack(">H", data[sub + 6:sub + 8])
    segments = seg_x2 // 2

    def array(start: int, kind: str = "H") -> tuple:
        return struct.unpack(f">{segments}{kind}", data[start:start + seg_x2])

    ends = array(sub + 14)
    starts = array(sub + 16 + seg_x2)
    deltas = array(sub + 16 + 2 * seg_x2, "h")
    range_base = sub + 16 + 3 * seg_x2
    range_offsets = array(range_base)
    found = set()
    for k in range(segments):
        for code in range(starts[k], ends[k] + 1):
            if code == 0xFFFF:
                continue
            if range_offsets[k] == 0:
                glyph = (code + deltas[k]) & 0xFFFF
            else:
                at = range_base + 2 * k + range_offsets[k] + 2 * (code - starts[k])
                (glyph,) = struct.unpack(">H", data[at:at + 2])
                glyph = (glyph + deltas[k]) & 0xFFFF if glyph else 0
            if glyph:
                found.add(code)
    return found


def covered(style: str = "regular") -> frozenset[int]:
    """Code points the window draws in ``style``: its font and the merged symbol font."""
    directory = fonts_dir()
    return codepoints(directory / TEXT_FONTS[style]) | codepoints(directory / SYMBOL_FONT)


def missing(text: str, style: str = "regular") -> set[str]:
    """The characters of ``text`` (other than line breaks) that ``style`` cannot draw."""
    have = covered(style)
    return {char for char in set(text) - {"\n", "\r", "\t"} if ord(char) not in have}


@dataclass
class Fonts:
    """imgui font handles by style; ``None`` entries fall back to the default font."""

    by_style: dict[str, Any]
    body_size: float

    def get(self, style: str) -> Any:
        return self.by_style.get(style) or self.by_style.get("regular")


def load(io, size: float = 15.0, scale: float = 1.0) -> Fonts:
    """Add the text fonts to imgui's atlas (the first becomes the default font), each
    with the symbol font merged in. A font file that fails to load is skipped."""
    from imgui_bundle import imgui

    directory = fonts_dir()
    symbols = directory / SYMBOL_FONT
    handles: dict[str, Any] = {}
    for style, relative in TEXT_FONTS.items():
        path = directory / relative
        if not path.is_file():
            continue
        try:
            font = io.fonts.add_font_from_file_ttf(str(path), size * scale)
            if symbols.is_file():
                config = imgui.ImFontConfig()
                config.merge_mode = True
                io.fonts.add_font_from_file_ttf(str(symbols), size * scale, config)
        except RuntimeError:
            continue
        handles[style] = font
    return Fonts(handles, BODY_SIZE * scale)
